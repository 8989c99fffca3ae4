"""Heights above the stated datum: LDEM-style radii, the HiRISE areoid, the legend text."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import rasterio

from pdsgen.extras import make_extras
from pdsgen.extras.product_source import DTM, open_product
from pdsgen.extras.renderings import render_product
from test_extras_helpers import crater_field, write_geotiff

MOON_R_M = 1737400.0
LINES, SAMPLES = 90, 180


def ldem_style(folder: Path) -> tuple[Path, np.ndarray]:
    """A LOLA LDEM-like product: int16 DN, radius = DN * 0.5 + 1737400 (OFFSET = radius)."""
    heights = crater_field(LINES, SAMPLES) + 4000.0 + 900.0   # about -100 .. +1000 m
    dn = np.rint(heights / 0.5).astype("<i2")
    (folder / "LDEM_T.IMG").write_bytes(dn.tobytes())
    label = f"""PDS_VERSION_ID = "PDS3"
PRODUCT_ID = "LDEM_T"
INSTRUMENT_HOST_NAME = "LUNAR RECONNAISSANCE ORBITER"
INSTRUMENT_ID = "LOLA"
TARGET_NAME = MOON
PRODUCER_INSTITUTION_NAME = "GODDARD SPACE FLIGHT CENTER"
OBJECT = UNCOMPRESSED_FILE
 FILE_NAME = "LDEM_T.IMG"
 RECORD_TYPE = FIXED_LENGTH
 FILE_RECORDS = {LINES}
 RECORD_BYTES = {2 * SAMPLES}
 ^IMAGE = "LDEM_T.IMG"
 OBJECT = IMAGE
  NAME = HEIGHT
  DESCRIPTION = "Each sample represents height relative to a reference radius (OFFSET)."
  LINES = {LINES}
  LINE_SAMPLES = {SAMPLES}
  SAMPLE_TYPE = LSB_INTEGER
  SAMPLE_BITS = 16
  UNIT = METER
  SCALING_FACTOR = 0.5
  OFFSET = 1737400.
 END_OBJECT = IMAGE
END_OBJECT = UNCOMPRESSED_FILE
OBJECT = IMAGE_MAP_PROJECTION
 MAP_PROJECTION_TYPE = "SIMPLE CYLINDRICAL"
 A_AXIS_RADIUS = 1737.4 <km>
 B_AXIS_RADIUS = 1737.4 <km>
 C_AXIS_RADIUS = 1737.4 <km>
 CENTER_LATITUDE = 0. <deg>
 CENTER_LONGITUDE = 180. <deg>
 MAP_RESOLUTION = 0.5 <pix/deg>
 MAP_SCALE = 60.6466 <km/pix>
 LINE_PROJECTION_OFFSET = 44.5 <pix>
 SAMPLE_PROJECTION_OFFSET = 89.5 <pix>
 POSITIVE_LONGITUDE_DIRECTION = "EAST"
END_OBJECT = IMAGE_MAP_PROJECTION
END
"""
    path = folder / "LDEM_T.LBL"
    path.write_text(label.replace("\n", "\r\n"))
    return path, dn.astype(np.float64) * 0.5


def test_ldem_radii_are_shown_as_heights_above_the_reference_sphere(tmp_path: Path):
    label, heights = ldem_style(tmp_path)
    src = open_product(label)
    assert src.kind == DTM and src.heights is not None
    assert src.heights.radius_removed_m == MOON_R_M
    assert src.heights.phrase == "m above the 1737.4 km reference sphere"
    previews = render_product(src, credit="", browse_width=SAMPLES, thumb_width=40,
                              azimuth=315.0, altitude=45.0)
    low, high = previews.display_range
    assert heights.min() - 1 <= low < high <= heights.max() + 1      # metres, not radii
    colour = next(p for p in previews.previews if p.rendering.key == "colour")
    assert colour.layout.ramp_box is not None


def test_ldem_readme_and_legend_say_above_what(tmp_path: Path):
    label, heights = ldem_style(tmp_path)
    out = tmp_path / "out"
    make_extras([label], out, browse_width=SAMPLES)
    text = " ".join((out / "README.TXT").read_text().split())
    assert "Heights: metres above the 1737.4 km reference sphere" in text
    assert "OFFSET (1737400 m) is that sphere's radius" in text
    assert "height in metres = DN * 0.5 + 0" in text
    assert "1737" not in re.search(r"VALID_MINIMUM:.*?No data", text).group(0).split(
        "DN *")[0]
    assert "Image credit: LUNAR RECONNAISSANCE ORBITER / GODDARD SPACE FLIGHT CENTER" in text


def test_legend_heading_names_the_datum_and_the_ramp_ends(tmp_path: Path):
    from PIL import ImageFont

    from pdsgen.extras.annotate import Legend, _heading_lines, _legend_labels

    legend = Legend(-4433.62, -4128.57, "the Mars 2000 areoid")
    texts = [t for _, t in _legend_labels(legend)]
    assert texts[:2] == ["-4129", "-4434"]        # both ends, to the metre
    assert [t for _, t in _legend_labels(Legend(0.061, 0.139))][:2] == ["0.139", "0.061"]
    font = ImageFont.load_default(size=12)
    lines = _heading_lines(legend, 90, font)
    assert " ".join(lines) == "Height (m) above the Mars 2000 areoid" and len(lines) > 1


def test_hirise_dtm_heights_are_above_the_mars_2000_areoid(tmp_path: Path):
    from pdsgen import write_dtm

    (tmp_path / "in").mkdir()
    tif = write_geotiff(tmp_path / "in" / "z.tif", crater_field(80, 100))
    product = write_dtm(tif, tmp_path / "p", product_id="DTEEC_000001_1000_000002_1000_U01",
                        profile="hirise")
    src = open_product(product.path)
    assert src.heights is not None and src.heights.datum == "the Mars 2000 areoid"
    assert src.heights.radius_removed_m is None and src.offset == 0.0


def test_float_heights_without_label_name_no_datum(tmp_path: Path):
    tif = write_geotiff(tmp_path / "z.tif", crater_field(60, 80))
    with rasterio.open(tif) as ds:
        assert ds.count == 1
    src = open_product(tif)
    assert src.heights is not None and "does not name" in src.heights.datum


def test_real_ldem_label_offset_is_its_radius(corpus_dir: Path):
    import pvl

    from pdsgen.extras.heights import radius_offset_m

    label = pvl.load(str(corpus_dir / "real" / "LDEM_4.LBL"))
    offset = float(label["UNCOMPRESSED_FILE"]["IMAGE"]["OFFSET"])
    assert radius_offset_m(label, offset) == MOON_R_M
    assert radius_offset_m(label, 0.0) is None and radius_offset_m(label, 1737000.0) is None
