"""The review page (pdsgen review, deliver's REVIEW.html, validate --format html), rendered in a
real browser: headless Chromium loads it from a file URL; its DOM after the script ran, a
filter, a screenshot's pixels, and Chromium's own network log are checked. Footprints are read
back from the SVG with the projection formulas the page documents, and compared with the
labels' own bounds (genuine HiRISE labels, read with pvl) and with GDAL's corners of a
polar product (gdalinfo, gdaltransform)."""

from __future__ import annotations

import csv
import json
import math
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest
from affine import Affine
from lxml import html
from PIL import Image

from pdsgen.deliver import make_delivery
from pdsgen.extras import make_extras
from pdsgen.products.dtm import write_dtm
from pdsgen.products.ortho import write_ortho
from pdsgen.synthetic import make_scene, write_geotiff
from pdsgen.validate import validate_paths

from helpers import CRS_SOUTH_POLAR, elevation_array, run_cli, write_raster

DATA = Path(__file__).resolve().parent / "data"
# Genuine HiRISE RDR labels (provenance in their directories' SOURCES.md / PROVENANCE.md)
GENUINE_MAP_LABELS = (
    DATA / "genuine_pds3" / "mwaldstein_pds3" / "ESP_011707_1440_COLOR.LBL",
    DATA / "genuine_pds3" / "mwaldstein_pds3" / "PSP_010737_2050_COLOR.LBL",
)
POLAR_TRANSFORM = Affine(200.0, 0, -150000.0, 0, -200.0, 250000.0)


def chromium(url: str, *args: str, timeout: float = 90) -> subprocess.CompletedProcess:
    """Headless Chromium on a file URL: no sandbox (tests may run as root), a fresh profile, no
    background traffic of its own, and every host name unresolvable."""
    binary = shutil.which("chromium") or shutil.which("chromium-browser")
    assert binary, "headless Chromium is needed (make test installs Debian's chromium)"
    with tempfile.TemporaryDirectory(prefix="pdsgen-chromium-") as profile:
        command = [binary, "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={profile}",
                   "--no-first-run", "--disable-background-networking", "--disable-component-update",
                   "--disable-sync", "--disable-default-apps", "--host-resolver-rules=MAP * ~NOTFOUND",
                   *args, url]
        return subprocess.run(command, capture_output=True, text=True, timeout=timeout)


def dom_after_scripts(page: Path, fragment: str = "") -> html.HtmlElement:
    result = chromium(page.resolve().as_uri() + fragment, "--dump-dom", "--virtual-time-budget=3000")
    assert result.returncode == 0 and "<html" in result.stdout, result.stderr[-2000:]
    return html.fromstring(result.stdout)


@pytest.fixture(scope="module")
def delivery(tmp_path_factory) -> Path:
    """A PDS3 volume of the demo's products (small) and a south-polar DTM: REVIEW.html written by
    pdsgen deliver."""
    root = tmp_path_factory.mktemp("review")
    scene = make_scene(width=240, height=320)
    (root / "in").mkdir()
    dtm_in = write_geotiff(root / "in" / "dtm.tif", scene.elevation, scene.transform, scene.crs, None)
    ortho_in = write_geotiff(root / "in" / "ortho.tif", scene.reflectance, scene.transform, scene.crs, None)
    polar_in = write_raster(root / "in" / "polar.tif", elevation_array(40, 50, seed=4), CRS_SOUTH_POLAR,
                            POLAR_TRANSFORM)
    products = root / "products"
    dtm = write_dtm(dtm_in, products, profile="hirise", source_product_ids=("PSP_008669_1705", "PSP_009025_1705"),
                    institution="U")
    ortho = write_ortho(ortho_in, products, profile="hirise", observation_id="PSP_008669_1705",
                        source_dtm_id=dtm.product_id)
    polar = write_dtm(polar_in, products, product_id="SOUTH_POLAR_DTM")
    # one seeded defect, for the filters: a sample type PDS3 does not have (IMG-002, an error)
    text = ortho.label_path.read_text()
    ortho.label_path.write_text(text.replace("= MSB_UNSIGNED_INTEGER", "= MSB_UNSIGNED_INTEGEX"))
    make_extras([dtm.path, ortho.label_path, polar.path], products / "extras")
    out = root / "volume"
    make_delivery(products, out, dialect="pds3", volume_id="REVIEW_01")
    return out


@pytest.fixture(scope="module")
def delivery_dom(delivery) -> html.HtmlElement:
    """The delivery's page after its script ran, as Chromium holds it."""
    return dom_after_scripts(delivery / "REVIEW.html")


def _index_product_ids(volume: Path) -> list[str]:
    """PRODUCT_ID of every INDEX.TAB row (csv: quoted fields, the third column)."""
    with open(volume / "INDEX" / "INDEX.TAB", newline="", encoding="ascii") as table:
        return [row[2].strip() for row in csv.reader(table)]


def test_deliver_writes_the_page_outside_the_manifest(delivery):
    page = delivery / "REVIEW.html"
    assert page.is_file()
    listed = [line.split("  ", 1)[1] for line in (delivery / "MD5SUMS.TXT").read_text().splitlines()]
    assert "REVIEW.html" not in listed
    report = validate_paths([delivery])
    assert not [f for f in report.findings if f.rule.startswith("DLV-02")], "the page breaks no manifest check"


def test_the_dom_after_scripts_holds_every_product_and_every_rule(delivery, delivery_dom):
    ids = _index_product_ids(delivery)
    assert len(ids) == 3
    dom = delivery_dom
    shown = {article.get("data-product") for article in dom.xpath("//article[@data-product]")}
    assert shown == set(ids)
    # the validator run on its own, as deliver runs it for the page (labels and the delivery's files)
    rules = {f.rule for f in validate_paths([delivery], labels_only=True).findings}
    assert rules and rules <= {row.get("data-rule") for row in dom.xpath("//tr[@data-rule]")}
    assert dom.get_element_by_id("filters").get("hidden") is None, "the script shows the filters"
    assert {a.get("href")[1:] for a in dom.xpath("//*[local-name()='svg']//*[local-name()='a']")} == {
        article.get("id") for article in dom.xpath("//article[@data-product]")}, "each footprint links its entry"
    assert dom.xpath("//*[local-name()='svg'][@data-projection='south-polar']"), "the polar DTM in a polar view"
    for img in dom.xpath("//img"):
        assert (delivery / img.get("src")).is_file(), "previews are linked relatively, inside the delivery"


def test_a_filter_hides_what_it_should(delivery):
    dom = dom_after_scripts(delivery / "REVIEW.html", "#severity=error&rule=&only=1")
    rows = dom.xpath("//tr[contains(@class, 'finding')]")
    assert {r.get("data-severity") for r in rows if r.get("hidden") is None} == {"error"}
    assert [r for r in rows if r.get("data-severity") != "error" and r.get("hidden") is None] == []
    for article in dom.xpath("//article[@data-product]"):
        has_error = bool(article.xpath(".//tr[@data-severity='error']"))
        assert (article.get("hidden") is None) == has_error, article.get("data-product")
    shown = [a.get("data-product") for a in dom.xpath("//article[@data-product]") if a.get("hidden") is None]
    assert shown == ["PSP_008669_1705_RED_C_01_ORTHO"], "only the product with the seeded error"
    dom = dom_after_scripts(delivery / "REVIEW.html", "#severity=error,warning,info&rule=MAP-004&only=0")
    visible = [r.get("data-rule") for r in dom.xpath("//tr[contains(@class, 'finding')]") if r.get("hidden") is None]
    assert visible and set(visible) == {"MAP-004"}
    assert not dom.xpath("//article[@hidden]")


def test_without_scripts_the_page_is_whole(delivery):
    """Read as written (no script run): every product and finding is there, filters hidden."""
    page = html.fromstring((delivery / "REVIEW.html").read_text(encoding="utf-8"))
    assert {a.get("data-product") for a in page.xpath("//article[@data-product]")} == set(
        _index_product_ids(delivery))
    assert page.get_element_by_id("filters").get("hidden") is not None
    assert not page.xpath("//*[@hidden and contains(@class, 'finding')]")


def test_a_screenshot_is_not_blank(delivery, tmp_path):
    shot = tmp_path / "page.png"
    result = chromium((delivery / "REVIEW.html").as_uri(), f"--screenshot={shot}", "--window-size=1200,1600",
                      "--virtual-time-budget=3000")
    assert result.returncode == 0 and shot.is_file(), result.stderr[-2000:]
    pixels = np.asarray(Image.open(shot).convert("RGB"))
    assert pixels.shape[:2] == (1600, 1200)
    not_white = np.any(pixels < 235, axis=2).mean()
    colours = len(np.unique(pixels.reshape(-1, 3), axis=0))
    assert not_white > 0.05 and colours > 200, (not_white, colours)
    # the DTM footprints' fill colour is on screen (the map rendered)
    orange = (np.abs(pixels.astype(int) - (234, 199, 179)).sum(axis=2) < 40).mean()
    assert orange > 0.001


def _requests(net_log: Path) -> list[str]:
    """URLs Chromium's network stack was asked for on a document's behalf (its net log's
    URL_REQUEST_START_JOB events; the browser's own service traffic, which even a blank page
    starts, has the initiator "not an origin" and is not the page's)."""
    log = json.loads(net_log.read_text())
    types = {v: k for k, v in log["constants"]["logEventTypes"].items()}
    return [event["params"]["url"] for event in log["events"]
            if types.get(event["type"]) == "URL_REQUEST_START_JOB" and "url" in event.get("params", {})
            and event["params"].get("initiator") != "not an origin"]


def test_the_page_makes_no_network_request(delivery, tmp_path):
    """Chromium's net log: the page's own loads are file URLs only. The same page with an image
    and a script from the network added is blocked by its Content-Security-Policy; without the
    policy that image is requested (the check can see a request)."""
    text = (delivery / "REVIEW.html").read_text(encoding="utf-8")
    assert "http://" not in text.replace('xmlns="http://www.w3.org/2000/svg"', "") and "https://" not in text
    meta = html.fromstring(text).xpath("//meta[@http-equiv='Content-Security-Policy']")[0].get("content")
    assert "default-src 'none'" in meta and "unsafe-inline" not in meta
    hostile = '<img src="http://tiles.example.org/x.png"><script src="https://cdn.example.org/x.js"></script>'
    cases = {"page": text, "with_csp": text.replace("</body>", hostile + "</body>"),
             "without_csp": re.sub(r"<meta http-equiv=\"Content-Security-Policy\"[^>]*>", "",
                                   text).replace("</body>", hostile + "</body>")}
    seen = {}
    for name, content in cases.items():
        page = delivery / f".{name}.html"
        page.write_text(content, encoding="utf-8")
        net_log = tmp_path / f"{name}.json"
        try:
            result = chromium(page.as_uri(), "--dump-dom", f"--log-net-log={net_log}",
                              "--virtual-time-budget=3000")
        finally:
            page.unlink()
        assert result.returncode == 0, result.stderr[-2000:]
        seen[name] = [url for url in _requests(net_log) if not url.startswith(("file:", "data:"))]
    assert seen["page"] == [] and seen["with_csp"] == []
    assert "http://tiles.example.org/x.png" in seen["without_csp"]


def _svg_points(svg) -> dict[str, np.ndarray]:
    return {polygon.get("data-product"): np.array([[float(v) for v in pair.split(",")]
                                                    for pair in polygon.get("points").split()])
            for polygon in svg.xpath(".//*[local-name()='polygon'][@data-product]")}


def _to_lonlat(svg, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Invert the view's projection with the formulas the page states (review/mapview.py)."""
    kind = svg.get("data-projection")
    k = float(svg.get("data-k"))
    if kind == "equirectangular":
        return points[:, 0] / k + float(svg.get("data-lon0")), float(svg.get("data-lat0")) - points[:, 1] / k
    x = points[:, 0] / k + float(svg.get("data-x0"))
    y = float(svg.get("data-y0")) - points[:, 1] / k
    r = np.hypot(x, y)
    if kind == "north-polar":
        return np.degrees(np.arctan2(x, -y)), 90.0 - r
    return np.degrees(np.arctan2(x, y)), r - 90.0


def test_footprints_of_genuine_labels_match_their_bounds(tmp_path):
    """validate --format html over genuine HiRISE labels: each outline's extremes, read back from
    the SVG, are the bounds the HiRISE pipeline wrote in the label (read with pvl)."""
    import pvl

    for label in GENUINE_MAP_LABELS:  # one page each: a view zoomed on one product shows its pixels
        (tmp_path / label.stem).mkdir()
        shutil.copy(label, tmp_path / label.stem / label.name)
        page = tmp_path / f"{label.stem}.html"
        result = run_cli("validate", tmp_path / label.stem, "--labels-only", "--format", "html", "-o", page)
        assert result.returncode in (0, 1) and page.is_file(), result.stderr
        svg = dom_after_scripts(page).xpath("//*[local-name()='svg'][@data-projection]")[0]
        parsed = pvl.load(str(label))
        projection = parsed["IMAGE_MAP_PROJECTION"]
        lons, lats = _to_lonlat(svg, _svg_points(svg)[parsed["PRODUCT_ID"]])
        metres = projection["MAP_SCALE"].value * (1000.0 if projection["MAP_SCALE"].units.startswith("K") else 1.0)
        scale_deg = math.degrees(metres / (projection["A_AXIS_RADIUS"].value * 1000.0))
        # HiRISE RDR labels place their grid by the older one-pixel-apart convention (the validator's
        # MAP-005): one pixel east and one south of where the standard convention (the page's, GDAL's)
        # puts it; so placed, the outline's extremes are their bounds within their own residuals (MAP-010,
        # under a pixel)
        cos_lat = math.cos(math.radians(projection["CENTER_LATITUDE"].value))
        lats, lons = lats - scale_deg, lons + scale_deg / cos_lat
        assert lats.min() == pytest.approx(projection["MINIMUM_LATITUDE"].value, abs=scale_deg)
        assert lats.max() == pytest.approx(projection["MAXIMUM_LATITUDE"].value, abs=scale_deg)
        assert lons.min() % 360.0 == pytest.approx(projection["WESTERNMOST_LONGITUDE"].value, abs=scale_deg / cos_lat)
        assert lons.max() % 360.0 == pytest.approx(projection["EASTERNMOST_LONGITUDE"].value, abs=scale_deg / cos_lat)


@pytest.mark.parametrize("product, projection", [("DTEEC_008669_1705_009025_1705_U01", "equirectangular"),
                                                 ("SOUTH_POLAR_DTM", "south-polar")])
def test_footprint_corners_are_gdals_corners(delivery, delivery_dom, product, projection):
    """GDAL reads the product (its PDS driver reads the label) and transforms the raster's four
    corners to longitude/latitude (gdaltransform); each is a vertex of the page's outline, read
    back from the SVG of its view (the polar DTM in the south-polar view)."""
    image = delivery / "DATA" / f"{product}.IMG"
    info = json.loads(subprocess.run(["gdalinfo", "-json", str(image)], capture_output=True, text=True,
                                     check=True, timeout=60).stdout)
    corners = [info["cornerCoordinates"][c] for c in ("upperLeft", "upperRight", "lowerRight", "lowerLeft")]
    wkt = info["coordinateSystem"]["wkt"]
    out = subprocess.run(["gdaltransform", "-s_srs", wkt, "-t_srs", "+proj=longlat +R=3396190 +no_defs",
                          "-output_xy"], input="\n".join(f"{x} {y}" for x, y in corners), capture_output=True,
                         text=True, check=True, timeout=60).stdout.split("\n")
    gdal_corners = np.array([[float(v) for v in line.split()[:2]] for line in out if line.strip()])
    pixel_deg = math.degrees(abs(info["geoTransform"][1]) / 3396190.0)
    svg = delivery_dom.xpath(f"//*[local-name()='svg'][@data-projection='{projection}']")[0]
    lons, lats = _to_lonlat(svg, _svg_points(svg)[product])
    assert len(gdal_corners) == 4
    for lon, lat in gdal_corners:  # within a hundredth of a pixel
        nearest = np.argmin(np.hypot(((lons - lon + 180.0) % 360.0 - 180.0) * math.cos(math.radians(lat)),
                                     lats - lat))
        assert lats[nearest] == pytest.approx(lat, abs=0.01 * pixel_deg)
        east = (lons[nearest] - lon + 180.0) % 360.0 - 180.0
        assert east * math.cos(math.radians(lat)) == pytest.approx(0.0, abs=0.01 * pixel_deg)


def test_review_command_and_its_errors(delivery, tmp_path):
    page = tmp_path / "out.html"
    result = run_cli("review", delivery, "-o", page, "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["products"] == 3 and summary["footprints"] == 3 and Path(summary["path"]) == page
    written = html.fromstring(page.read_text(encoding="utf-8"))
    assert {f.rule for f in validate_paths([delivery]).findings} <= {
        row.get("data-rule") for row in written.xpath("//tr[@data-rule]")}, "review checks the data too"
    for img in html.fromstring(page.read_text(encoding="utf-8")).xpath("//img"):
        assert (tmp_path / img.get("src")).resolve().is_file(), "links are relative to where the page is"
    missing = run_cli("review", tmp_path / "nothing")
    assert missing.returncode == 2 and missing.stderr.count("\n") == 1 and "nothing" in missing.stderr
    empty = tmp_path / "empty"
    empty.mkdir()
    refused = run_cli("review", empty)
    assert refused.returncode == 2 and "no data product" in refused.stderr and not list(empty.iterdir())


class DevTools:
    """Chromium driven over its DevTools protocol on a pipe (--remote-debugging-pipe: JSON messages
    ended by NUL, commands on fd 3, replies on fd 4): no websocket, no extra package."""

    def __init__(self, url: str, profile: str) -> None:
        import os

        binary = shutil.which("chromium") or shutil.which("chromium-browser")
        assert binary
        to_browser, self._write = os.pipe()
        self._read, from_browser = os.pipe()
        # the child's fds 3 and 4 are the pipe ends Chromium reads and writes
        self.process = subprocess.Popen(
            [binary, "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={profile}", "--no-first-run",
             "--disable-background-networking", "--host-resolver-rules=MAP * ~NOTFOUND", "--window-size=1200,1600",
             "--remote-debugging-pipe", url],
            pass_fds=(3, 4), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            preexec_fn=lambda: (os.dup2(to_browser, 3), os.dup2(from_browser, 4)))
        os.close(to_browser)
        os.close(from_browser)
        self._buffer = b""
        self._next = 0
        self.session = None
        page = next(t for t in self.call("Target.getTargets")["targetInfos"] if t["type"] == "page")
        self.session = self.call("Target.attachToTarget", targetId=page["targetId"], flatten=True)["sessionId"]

    def call(self, method: str, **params):
        import os
        import select
        import time

        self._next += 1
        message = {"id": self._next, "method": method, "params": params}
        if self.session:
            message["sessionId"] = self.session
        os.write(self._write, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + 30
        while True:
            while b"\0" in self._buffer:
                raw, self._buffer = self._buffer.split(b"\0", 1)
                reply = json.loads(raw)
                if reply.get("id") == self._next:
                    assert "error" not in reply, reply
                    return reply["result"]
            ready, _, _ = select.select([self._read], [], [], max(0.0, deadline - time.monotonic()))
            assert ready, f"no reply to {method}"
            self._buffer += os.read(self._read, 1 << 16)

    def evaluate(self, expression: str):
        return self.call("Runtime.evaluate", expression=expression, returnByValue=True)["result"].get("value")

    def click(self, selector: str) -> None:
        """A real mouse click (pressed, released) at the middle of the element."""
        box = self.evaluate(f"(function () {{ var e = document.querySelector({json.dumps(selector)}); "
                            "e.scrollIntoView(); var r = e.getBoundingClientRect(); "
                            "return [r.left + r.width / 2, r.top + r.height / 2]; }())")
        for kind in ("mousePressed", "mouseReleased"):
            self.call("Input.dispatchMouseEvent", type=kind, x=box[0], y=box[1], button="left", clickCount=1)

    def close(self) -> None:
        import os

        self.process.kill()
        self.process.wait(timeout=30)
        os.close(self._write)
        os.close(self._read)


def test_clicking_a_severity_box_hides_its_findings(delivery, tmp_path):
    """The filter as a person uses it: a mouse click on the "info" box (DevTools protocol) hides
    every info finding and nothing else, and the address remembers it."""
    import time

    browser = DevTools((delivery / "REVIEW.html").as_uri(), str(tmp_path / "profile"))
    try:
        for _ in range(300):
            if browser.evaluate("location.protocol + document.readyState") == "file:complete":
                break
            time.sleep(0.1)
        count = "document.querySelectorAll('tr.finding[data-severity=\"{}\"]{}').length"
        infos, warnings = browser.evaluate(count.format("info", "")), browser.evaluate(count.format("warning", ""))
        assert infos > 0 and browser.evaluate(count.format("info", "[hidden]")) == 0
        browser.click("#filters input[value=info]")
        assert browser.evaluate("document.querySelector('#filters input[value=info]').checked") is False
        assert browser.evaluate(count.format("info", "[hidden]")) == infos
        assert browser.evaluate(count.format("warning", "[hidden]")) == 0 and warnings >= 0
        assert "severity=error,warning" in browser.evaluate("location.hash")
    finally:
        browser.close()


def test_thumbnails_beyond_the_first_are_built_as_their_entry_is_scrolled_near(delivery, tmp_path):
    """With one product's thumbnails in the HTML, the others are links until their entry comes
    near the screen; scrolled to, they become images of the previews; a preview opened shows its
    browse image."""
    import time

    from pdsgen.review import write_review

    page = write_review(delivery, tmp_path / "page.html", labels_only=True, inline_thumbnails=1).path
    written = html.fromstring(page.read_text(encoding="utf-8"))
    articles = written.xpath("//article[@data-product]")
    assert articles[0].xpath(".//summary/img") and not articles[0].xpath(".//a[@data-thumb]")
    assert all(a.xpath(".//a[@data-thumb]") and not a.xpath(".//summary/img") for a in articles[1:]
               if a.xpath(".//details[@class='preview']"))
    browser = DevTools(page.as_uri(), str(tmp_path / "profile"))
    try:
        for _ in range(300):
            if browser.evaluate("location.protocol + document.readyState") == "file:complete":
                break
            time.sleep(0.1)
        last = articles[-1].get("id")
        images = f"document.getElementById('{last}').querySelectorAll('summary img').length"
        browser.evaluate(f"document.getElementById('{last}').scrollIntoView()")
        for _ in range(50):
            if browser.evaluate(images):
                break
            time.sleep(0.1)
        assert browser.evaluate(images) == len(articles[-1].xpath(".//a[@data-thumb]")) > 0
        sources = browser.evaluate(f"Array.prototype.map.call(document.getElementById('{last}')"
                                   ".querySelectorAll('summary img'), function (i) { return i.src; })")
        assert all(source.startswith("file://") and Path(source[7:]).is_file() for source in sources)
        loaded = (f"Array.prototype.every.call(document.getElementById('{last}').querySelectorAll('summary img'), "
                  "function (i) { return i.complete && i.naturalWidth > 0; })")
        for _ in range(50):
            if browser.evaluate(loaded):
                break
            time.sleep(0.1)
        assert browser.evaluate(loaded), "the thumbnails load (the page's policy lets its own images in)"
        browser.click(f"#{last} details.preview summary")
        opened = f"document.querySelector('#{last} details.preview a.browse img') !== null"
        for _ in range(50):  # the toggle event comes after the click
            if browser.evaluate(opened):
                break
            time.sleep(0.1)
        assert browser.evaluate(opened)
    finally:
        browser.close()


def _small_pds3_product(directory: Path, number: int) -> str:
    """A detached PDS3 label of a 4 x 4 equirectangular PC_REAL image over Mars, written here from
    the PDS3 Standards' keywords (offsets by the standard convention), not by pdsgen's writer."""
    product_id = f"SMALL_{number:03d}"
    radius_m, scale, posts = 3396190.0, 1000.0, 4
    lat, lon = -30.0 + 10.0 * (number // 4), 20.0 + 15.0 * (number % 4)
    deg = math.degrees(scale / radius_m)
    label = [
        "PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", f"RECORD_BYTES = {posts * 4}",
        f"FILE_RECORDS = {posts}", f'^IMAGE = "{product_id}.IMG"', f'PRODUCT_ID = "{product_id}"',
        'DATA_SET_ID = "SMALL-M-DTM-V1.0"', "TARGET_NAME = MARS", "PRODUCT_CREATION_TIME = 2026-01-01T00:00:00",
        'INSTRUMENT_ID = "SMALL"', "OBJECT = IMAGE", f"  LINES = {posts}", f"  LINE_SAMPLES = {posts}",
        "  BANDS = 1", "  SAMPLE_TYPE = PC_REAL", "  SAMPLE_BITS = 32", "  UNIT = METER",
        "  VALID_MINIMUM = -4000.0", f"  VALID_MAXIMUM = {-4000.0 + posts * posts - 1:.1f}", "END_OBJECT = IMAGE",
        "OBJECT = IMAGE_MAP_PROJECTION", '  MAP_PROJECTION_TYPE = "EQUIRECTANGULAR"',
        f"  A_AXIS_RADIUS = {radius_m / 1000} <KM>", f"  B_AXIS_RADIUS = {radius_m / 1000} <KM>",
        f"  C_AXIS_RADIUS = {radius_m / 1000} <KM>", "  POSITIVE_LONGITUDE_DIRECTION = EAST",
        "  CENTER_LATITUDE = 0.0 <DEG>", "  CENTER_LONGITUDE = 0.0 <DEG>", f"  MAP_SCALE = {scale} <METERS/PIXEL>",
        f"  MAP_RESOLUTION = {1.0 / deg:.10f} <PIX/DEG>", f"  MAXIMUM_LATITUDE = {lat:.10f} <DEG>",
        f"  MINIMUM_LATITUDE = {lat - posts * deg:.10f} <DEG>", f"  WESTERNMOST_LONGITUDE = {lon:.10f} <DEG>",
        f"  EASTERNMOST_LONGITUDE = {lon + posts * deg:.10f} <DEG>",
        f"  LINE_PROJECTION_OFFSET = {math.radians(lat) * radius_m / scale - 0.5:.4f} <PIXEL>",
        f"  SAMPLE_PROJECTION_OFFSET = {-math.radians(lon) * radius_m / scale - 0.5:.4f} <PIXEL>",
        "END_OBJECT = IMAGE_MAP_PROJECTION", "END", ""]
    (directory / f"{product_id}.LBL").write_bytes("\r\n".join(label).encode("ascii"))
    (directory / f"{product_id}.IMG").write_bytes((-4000.0 + np.arange(posts * posts, dtype="<f4")).tobytes())
    return product_id


def test_a_large_delivery_is_reviewed_in_pages_each_product_on_exactly_one(tmp_path):
    """Seven products, three per page: REVIEW.html (summary, map, first three), REVIEW-2.html,
    REVIEW-3.html. In Chromium, after the script ran, every product id is on exactly one page, every
    footprint's link on the first page reaches an entry on the page it names, every finding's rule
    is on some page; the delivery's manifest check takes every page as the delivery's own, and a
    review in fewer pages removes the pages it no longer has."""
    from pdsgen.archive.scan import scan
    from pdsgen.review import write_review

    products = tmp_path / "products"
    products.mkdir()
    made = {_small_pds3_product(products, number) for number in range(7)}
    volume = tmp_path / "volume"
    make_delivery(products, volume, dialect="pds3", volume_id="PAGED_01")
    assert set(_index_product_ids(volume)) == made
    assert not list(volume.glob("REVIEW-*.html")), "seven products fit in one page by default"

    result = write_review(volume, labels_only=True, per_page=3)
    assert [p.name for p in result.pages] == ["REVIEW.html", "REVIEW-2.html", "REVIEW-3.html"]
    doms = {p.name: dom_after_scripts(p) for p in result.pages}
    pages_of: dict[str, list[str]] = {}
    for name, dom in doms.items():
        for article in dom.xpath("//article[@data-product]"):
            pages_of.setdefault(article.get("data-product"), []).append(name)
        assert len(dom.xpath("//article[@data-product]")) <= 3
        for link in dom.xpath("//nav[@class='pages']//a/@href"):
            assert (volume / link).is_file(), "the pages link each other"
    assert set(pages_of) == made and all(len(names) == 1 for names in pages_of.values()), pages_of
    links = [a.get("href") for a in doms["REVIEW.html"].xpath("//*[local-name()='svg']//*[local-name()='a']")]
    assert len(links) == len(made), "the first page maps every footprint"
    for link in links:
        name, _, anchor = link.partition("#")
        dom = doms[name or "REVIEW.html"]
        entry = dom.xpath(f"//article[@id='{anchor}']")
        assert entry and pages_of[entry[0].get("data-product")] == [name or "REVIEW.html"], link
    rules = {f.rule for f in validate_paths([volume], labels_only=True).findings}
    assert rules <= {row.get("data-rule") for dom in doms.values() for row in dom.xpath("//tr[@data-rule]")}
    assert doms["REVIEW-2.html"].get_element_by_id("filters").get("hidden") is None, "filters on every page"
    assert not doms["REVIEW-2.html"].xpath("//*[local-name()='svg']"), "the map is on the first page only"

    report = validate_paths([volume])
    assert not [f for f in report.findings if f.rule.startswith("DLV-02")], "no page is taken as unlisted"
    assert not [p for p in scan(volume).others if p.name.startswith("REVIEW")]

    again = write_review(volume, labels_only=True, per_page=4)
    assert [p.name for p in again.pages] == ["REVIEW.html", "REVIEW-2.html"]
    assert not (volume / "REVIEW-3.html").exists(), "a page of the earlier review is removed"
