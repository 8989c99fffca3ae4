// Filters for the findings: by severity and rule, optionally only the products that have such
// findings. The page is complete without this script; the filter state is kept in the address
// (#severity=error,warning&rule=MAP-003&only=1), so a filtered view can be bookmarked.
(function () {
  "use strict";
  var form = document.getElementById("filters");
  if (!form) { return; }
  var boxes = Array.prototype.slice.call(form.querySelectorAll("input[name=severity]"));
  var rule = form.querySelector("select[name=rule]");
  var only = form.querySelector("input[name=only]");
  var shown = form.querySelector("output[name=shown]");
  var rows = Array.prototype.slice.call(document.querySelectorAll("tr.finding"));
  var entries = Array.prototype.slice.call(document.querySelectorAll("article.entry"));
  var outlines = {};
  // (outlines of products on other pages of a large delivery link there: not filtered here)
  Array.prototype.forEach.call(document.querySelectorAll(".footprints a[href^='#']"), function (a) {
    outlines[a.getAttribute("href").slice(1)] = a;
  });

  function readAddress() {
    var state = {};
    location.hash.replace(/^#/, "").split("&").forEach(function (part) {
      var pair = part.split("=");
      if (pair.length === 2) { state[pair[0]] = decodeURIComponent(pair[1]); }
    });
    if (state.severity !== undefined) {
      var wanted = state.severity.split(",");
      boxes.forEach(function (box) { box.checked = wanted.indexOf(box.value) >= 0; });
    }
    if (state.rule !== undefined) { rule.value = state.rule; }
    if (state.only !== undefined) { only.checked = state.only === "1"; }
  }

  function apply(remember) {
    var severities = boxes.filter(function (box) { return box.checked; }).map(function (box) { return box.value; });
    var wantedRule = rule.value;
    rows.forEach(function (row) {
      row.hidden = severities.indexOf(row.getAttribute("data-severity")) < 0 ||
        (wantedRule !== "" && row.getAttribute("data-rule") !== wantedRule);
    });
    var count = 0;
    entries.forEach(function (entry) {
      var keep = !only.checked || entry.querySelector("tr.finding:not([hidden])") !== null;
      entry.hidden = !keep;
      if (keep && !entry.classList.contains("other")) { count += 1; }
      var outline = outlines[entry.id];
      if (outline) { if (keep) { outline.removeAttribute("hidden"); } else { outline.setAttribute("hidden", ""); } }
    });
    shown.value = count + " product(s) shown";
    if (remember) {
      var address = "severity=" + severities.join(",") + "&rule=" + encodeURIComponent(wantedRule) +
        "&only=" + (only.checked ? "1" : "0");
      history.replaceState(null, "", "#" + address);
    }
  }

  // the outline of the product whose entry is selected (#p-...) stands out on the map
  function markSelected() {
    Array.prototype.forEach.call(document.querySelectorAll(".footprints polygon.selected"), function (p) {
      p.classList.remove("selected");
    });
    var link = outlines[location.hash.slice(1)];
    if (link) { link.querySelector("polygon").classList.add("selected"); }
  }
  window.addEventListener("hashchange", markSelected);
  markSelected();

  // Thumbnails beyond the first products are built as their entry comes near the screen (a
  // page of 10,000 products would otherwise read 10,000 images on opening); the larger browse
  // image when its preview is opened.
  function showThumbnails(entry) {
    Array.prototype.forEach.call(entry.querySelectorAll("a.thumb[data-thumb]"), function (link) {
      var img = document.createElement("img");
      img.src = link.getAttribute("data-thumb");
      img.alt = link.textContent;
      img.title = link.title;
      link.parentNode.replaceChild(img, link);
    });
  }
  var waiting = entries.filter(function (entry) { return entry.querySelector("a.thumb[data-thumb]"); });
  if (waiting.length && "IntersectionObserver" in window) {
    var observer = new IntersectionObserver(function (seen) {
      seen.forEach(function (item) {
        if (item.isIntersecting) { showThumbnails(item.target); observer.unobserve(item.target); }
      });
    }, { rootMargin: "1500px 0px" });
    waiting.forEach(function (entry) { observer.observe(entry); });
  }
  document.addEventListener("toggle", function (event) {
    var details = event.target;
    if (!details.open || !details.classList || !details.classList.contains("preview")) { return; }
    var link = details.querySelector("a.browse");
    if (link && !link.querySelector("img")) {
      var img = document.createElement("img");
      img.className = "browse";
      img.src = link.getAttribute("href");
      img.alt = "browse image";
      link.textContent = "";
      link.appendChild(img);
    }
  }, true);

  form.hidden = false;
  if (/severity=|rule=|only=/.test(location.hash)) { readAddress(); }
  apply(false);
  form.addEventListener("change", function () { apply(true); });
  form.addEventListener("submit", function (event) { event.preventDefault(); });
}());
