"""The review page as a reader sees it, measured in headless Chromium: footprints that coincide
(a DTM and the orthoimage on its grid) drawn in different colours and strokes with a legend
naming each kind; the graticule's labels outside the plot and inside the drawing (none clipped);
rule ids on one line even in a narrow window; no text cut off in the findings; a message shown
once, not after its own keyword; no green verdict while placeholder warnings remain; an inset
showing the region around a small view, and none beside a view of most of the body.

The measurements are made by a script added to a copy of the page (the page's own
Content-Security-Policy admits only its own script), which writes element boxes and computed
styles into the document that Chromium dumps."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from lxml import html

from pdsgen.review.collect import OtherFile, ProductEntry, Review
from pdsgen.review.footprint import EDGE_POINTS, Outline
from pdsgen.review.mapview import build_views
from pdsgen.review.page import render_page
from pdsgen.validate.model import Finding
from test_review import chromium, delivery  # noqa: F401  (delivery: the module's fixture, reused)

MEASURE = """
<script>
(function () {
  function box(e) { var r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; }
  function texts(root) {
    return Array.prototype.map.call(root.querySelectorAll(".graticule text"),
      function (t) { return {text: t.textContent, box: box(t)}; });
  }
  var out = {views: [], rules: [], cells: []};
  document.querySelectorAll("figure.view").forEach(function (fig) {
    var svg = fig.querySelector("svg.plot"), inset = fig.querySelector("svg.inset");
    out.views.push({
      projection: svg.getAttribute("data-projection"), svg: box(svg), frame: box(svg.querySelector("rect.frame")),
      labels: texts(svg),
      polygons: Array.prototype.map.call(svg.querySelectorAll(".footprints polygon"), function (p) {
        var s = getComputedStyle(p); return {kind: p.getAttribute("data-kind"), stroke: s.stroke,
                                              dash: s.strokeDasharray, fill: s.fill}; }),
      legend: Array.prototype.map.call(fig.querySelectorAll("ul.legend li[data-kind]"), function (li) {
        var s = getComputedStyle(li.querySelector("rect"));
        return {kind: li.getAttribute("data-kind"), text: li.textContent.trim(), stroke: s.stroke,
                dash: s.strokeDasharray, fill: s.fill, box: box(li)}; }),
      figure: box(fig),
      inset: inset ? {svg: box(inset), frame: box(inset.querySelector("rect.frame")),
                      box: box(inset.querySelector("rect.box")), labels: texts(inset)} : null
    });
  });
  document.querySelectorAll("td.rule").forEach(function (td) {
    var range = document.createRange(); range.selectNodeContents(td);
    out.rules.push({text: td.textContent, lines: range.getClientRects().length});
  });
  document.querySelectorAll("table.findings td, table.facts td").forEach(function (td) {
    out.cells.push({text: td.textContent.slice(0, 40), scroll: td.scrollWidth, client: td.clientWidth});
  });
  document.body.setAttribute("data-measured", JSON.stringify(out));
})();
</script>
"""


def _measured(page: Path, width: int = 1200) -> dict:
    copy = page.with_name("MEASURED.html")
    text = page.read_text(encoding="utf-8")
    start = text.index('<meta http-equiv="Content-Security-Policy"')
    text = text[:start] + text[text.index(">", start) + 1:]
    copy.write_text(text.replace("</body>", MEASURE + "</body>"), encoding="utf-8")
    result = chromium(copy.as_uri(), "--dump-dom", "--virtual-time-budget=3000", f"--window-size={width},2000")
    assert result.returncode == 0 and "data-measured" in result.stdout, result.stderr[-2000:]
    return json.loads(html.fromstring(result.stdout).xpath("//body")[0].get("data-measured"))


def _inside(inner: list[float], outer: list[float], slack: float = 0.5) -> bool:
    return (inner[0] >= outer[0] - slack and inner[1] >= outer[1] - slack
            and inner[2] <= outer[2] + slack and inner[3] <= outer[3] + slack)


def _overlap(a: list[float], b: list[float]) -> bool:
    return a[0] < b[2] - 0.5 and b[0] < a[2] - 0.5 and a[1] < b[3] - 0.5 and b[1] < a[3] - 0.5


def test_coinciding_outlines_differ_by_kind_and_the_legend_names_each(delivery):  # noqa: F811
    measured = _measured(delivery / "REVIEW.html")
    (view,) = [v for v in measured["views"] if v["projection"] == "equirectangular"]
    kinds = {p["kind"]: p for p in view["polygons"]}
    assert set(kinds) == {"DTM", "orthoimage"}  # the demo's DTM and orthoimage: one grid
    dtm, ortho = kinds["DTM"], kinds["orthoimage"]
    assert dtm["stroke"] != ortho["stroke"] and dtm["dash"] != ortho["dash"]
    legend = {entry["kind"]: entry for entry in view["legend"]}
    assert set(legend) == {"DTM", "orthoimage"}
    for kind, entry in legend.items():  # each legend swatch is drawn as its footprints are
        assert entry["text"] == kind
        assert (entry["stroke"], entry["dash"]) == (kinds[kind]["stroke"], kinds[kind]["dash"])
        assert _inside(entry["box"], view["figure"])


def test_graticule_labels_stand_outside_the_plot_and_none_is_clipped(delivery):  # noqa: F811
    measured = _measured(delivery / "REVIEW.html")
    assert {v["projection"] for v in measured["views"]} == {"equirectangular", "south-polar"}
    for view in measured["views"]:
        assert view["labels"], view["projection"]
        for n, label in enumerate(view["labels"]):
            assert not _overlap(label["box"], view["frame"]), (view["projection"], label)
            assert _inside(label["box"], view["svg"]), (view["projection"], label)  # not cut off by the drawing
            assert not [other for other in view["labels"][n + 1:] if _overlap(label["box"], other["box"])], label
        inset = view["inset"]
        if inset:
            assert _inside(inset["box"], inset["frame"]) and inset["box"][2] - inset["box"][0] >= 4
            for label in inset["labels"]:
                assert not _overlap(label["box"], inset["frame"]) and _inside(label["box"], inset["svg"]), label


def test_rule_ids_keep_to_one_line_and_no_cell_cuts_its_text(delivery):  # noqa: F811
    measured = _measured(delivery / "REVIEW.html", width=520)  # narrow: the message column wraps
    assert measured["rules"] and all(rule["lines"] == 1 for rule in measured["rules"]), measured["rules"]
    assert all("-" in rule["text"] for rule in measured["rules"])
    cut = [cell for cell in measured["cells"] if cell["scroll"] > cell["client"] + 1]
    assert not cut, cut


def _review(findings: list[Finding]) -> Review:
    review = Review("test", Path("."), verdict="3 file(s) checked: 0 error(s) - OK")
    review.others = [OtherFile("VOLDESC.CAT", findings)]
    return review


def test_no_green_verdict_while_placeholders_remain_and_messages_are_told_once():
    placeholder = Finding("DLV-006", "warning", "VOLDESC.CAT", "text still to be written: [TO BE WRITTEN: X]", 5)
    keyword = Finding("DICT-009", "info", "VOLDESC.CAT", "KEY = 1: a number for a CHARACTER keyword", 7, "KEY")
    other = Finding("DICT-001", "info", "VOLDESC.CAT", "not in the dictionary", 8, "ODD_KEY")
    page = html.fromstring(render_page(_review([placeholder, keyword, other])))
    verdicts = page.xpath("//p[contains(@class, 'verdict')]")
    assert verdicts and not page.xpath("//p[contains(@class, 'verdict') and contains(@class, 'ok')]")
    assert "1 of the 1 warning(s)" in verdicts[-1].text_content()
    messages = [row.xpath("./td")[-1].text_content() for row in page.xpath("//tr[@data-rule]")]
    assert messages[1] == "KEY = 1: a number for a CHARACTER keyword"  # not "KEY: KEY = 1 ..."
    assert messages[2] == "ODD_KEY: not in the dictionary"  # the keyword, where the message lacks it
    clean = html.fromstring(render_page(_review([keyword])))
    assert clean.xpath("//p[contains(@class, 'verdict') and contains(@class, 'ok')]")


def _outline(west: float, south: float, east: float, north: float) -> Outline:
    n = EDGE_POINTS - 1
    lons = np.concatenate([np.linspace(west, east, n, endpoint=False), np.full(n, east),
                           np.linspace(east, west, n, endpoint=False), np.full(n, west)])
    lats = np.concatenate([np.full(n, north), np.linspace(north, south, n, endpoint=False),
                           np.full(n, south), np.linspace(south, north, n, endpoint=False)])
    return Outline(lons, lats, False, True)


def test_the_inset_shows_the_region_of_a_small_view_and_is_left_out_for_a_large_one():
    (small,) = build_views([("A", "#a", "MARS", _outline(70.0, -17.0, 70.2, -16.8), "DTM")])
    assert small.inset is not None
    x, y, w, h = small.inset.box
    assert 0 <= x and x + w <= small.inset.width and 0 <= y and y + h <= small.inset.height
    lon_centre = small.inset.west + (x + w / 2) / small.inset.scale
    lat_centre = small.inset.north - (y + h / 2) / small.inset.scale
    assert abs(lon_centre - 70.1) < 0.05 and abs(lat_centre + 16.9) < 0.05  # the box is where the view is
    assert 360.0 / small.inset.scale * small.inset.scale == 360.0 and small.inset.width / small.inset.scale < 360
    (large,) = build_views([("B", "#b", "MARS", _outline(-170.0, -60.0, 170.0, 60.0), "DTM")])
    assert large.inset is None
    assert [shape.kind for shape in large.shapes] == ["DTM"] and large.kinds == ["DTM"]


def test_unknown_product_kinds_are_drawn_as_products_after_dtms_and_orthoimages():
    outline = _outline(10.0, 0.0, 10.5, 0.5)
    (view,) = build_views([("P", "#p", "MARS", outline, "something"), ("O", "#o", "MARS", outline, "orthoimage"),
                           ("D", "#d", "MARS", outline, "DTM")])
    assert [shape.product_id for shape in view.shapes] == ["D", "O", "P"] and view.kinds == ["DTM", "orthoimage",
                                                                                          "product"]
    assert ProductEntry("X", "p-X", "X.LBL").kind == "product"
