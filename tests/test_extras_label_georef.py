"""Georeferencing from the label when GDAL reads none: a Magellan-style sinusoidal product."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pvl
import pytest
import rasterio
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.extras.product_source import open_product
from pdsgen.extras.renderings import render_product
from pdsgen.geo.label_georef import LabelGeorefError, label_georeferencing

VENUS_R_KM = 6051.92
MAP_SCALE_M = 75.0
LINE_OFFSET = -24579.0     # Magellan's X axis runs down the image (lines)
SAMPLE_OFFSET = 4096.0     # and its Y axis across (samples)
LINES, SAMPLES = 300, 400


def magellan_style(folder: Path) -> Path:
    """An F-MIDR-like framelet: 8-bit image, IMAGE_MAP_PROJECTION_CATALOG, X/Y offsets."""
    rows, cols = np.mgrid[0:LINES, 0:SAMPLES]
    image = (30 + (rows * 7 + cols * 3) % 200).astype(np.uint8)
    (folder / "FF99.IMG").write_bytes(image.tobytes())
    label = f"""PDS_VERSION_ID = PDS3
RECORD_TYPE = FIXED_LENGTH
RECORD_BYTES = {SAMPLES}
FILE_RECORDS = {LINES}
^IMAGE = ("FF99.IMG", 1)
SPACECRAFT_NAME = MAGELLAN
IMAGE_ID = 'F-MIDR.20S145;1'
TARGET_NAME = VENUS
OBJECT = IMAGE
 LINES = {LINES}
 LINE_SAMPLES = {SAMPLES}
 SAMPLE_TYPE = UNSIGNED_INTEGER
 SAMPLE_BITS = 8
END_OBJECT = IMAGE
OBJECT = IMAGE_MAP_PROJECTION_CATALOG
 MAP_PROJECTION_TYPE = SINUSOIDAL
 MAP_SCALE = {MAP_SCALE_M:g} <M/PIXEL>
 X_AXIS_PROJECTION_OFFSET = {LINE_OFFSET:g}
 Y_AXIS_PROJECTION_OFFSET = {SAMPLE_OFFSET:g}
 A_AXIS_RADIUS = {VENUS_R_KM} <KM>
 B_AXIS_RADIUS = {VENUS_R_KM} <KM>
 C_AXIS_RADIUS = {VENUS_R_KM} <KM>
 POSITIVE_LONGITUDE_DIRECTION = EAST
 CENTER_LATITUDE = 0.0
 CENTER_LONGITUDE = 144.6882
END_OBJECT = IMAGE_MAP_PROJECTION_CATALOG
END
"""
    path = folder / "FF99.LBL"
    path.write_text(label.replace("\n", "\r\n"))
    return path


def test_gdal_reads_no_georeferencing_from_it(tmp_path: Path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
        with rasterio.open(magellan_style(tmp_path)) as ds:
            assert ds.crs is None


def test_crs_and_grid_come_from_the_label_with_the_standard_offsets(tmp_path: Path):
    src = open_product(magellan_style(tmp_path))
    assert src.georeferencing == "label"
    t = src.transform
    assert (t.a, -t.e) == (MAP_SCALE_M, MAP_SCALE_M)
    assert t.c == pytest.approx(-(SAMPLE_OFFSET + 0.5) * MAP_SCALE_M)
    assert t.f == pytest.approx((LINE_OFFSET + 0.5) * MAP_SCALE_M)
    assert "sinu" in src.crs.to_proj4() and "6051920" in src.crs.to_proj4()


def test_scale_bar_is_true_and_the_centre_lies_where_the_label_says(tmp_path: Path):
    src = open_product(magellan_style(tmp_path))
    previews = render_product(src, credit="", browse_width=200, thumb_width=50,
                              azimuth=315.0, altitude=45.0)
    preview = previews.previews[0]
    bar = preview.layout.scale_bar
    # Sinusoidal is true to scale along parallels: a browse pixel is MAP_SCALE * step.
    metres_per_pixel = MAP_SCALE_M * previews.grid.step_x
    assert abs(bar.pixels - bar.metres / metres_per_pixel) <= 1.0
    # The bar drawn in the image has that many dark pixels along its top edge.
    x0, y0, x1, _ = preview.layout.scale_bar_box
    row = np.asarray(preview.annotated.convert("L"))[y0]
    dark = np.flatnonzero(row[x0 - 3:x1 + 4] < 80)
    assert abs((dark.max() - dark.min() + 1) - bar.metres / metres_per_pixel) <= 1.0
    # Image centre by hand: y = R * lat, x = R * cos(lat) * (lon - lon0).
    r = VENUS_R_KM * 1000.0
    y = (LINE_OFFSET + 0.5 - LINES / 2) * MAP_SCALE_M
    x = (SAMPLES / 2 - SAMPLE_OFFSET - 0.5) * MAP_SCALE_M
    lat = math.degrees(y / r)
    lon = 144.6882 + math.degrees(x / (r * math.cos(math.radians(lat))))
    assert previews.scale.latitude == pytest.approx(lat, abs=1e-6)
    assert previews.scale.longitude % 360 == pytest.approx(lon, abs=1e-6)
    assert preview.layout.north_tip[1] < preview.layout.scale_bar_box[1] + 40  # north is up-ish
    assert abs(previews.scale.north_deg) < 5 or abs(previews.scale.north_deg - 360) < 5


def test_cli_makes_extras_of_it_and_credits_the_mission(tmp_path: Path):
    label = magellan_style(tmp_path)
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["extras", str(label), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "Warning" not in result.stderr and "taken as an orthoimage" in result.stderr
    text = (out / "README.TXT").read_text()
    assert "from the label's map projection object" in text
    assert "Image credit:      MAGELLAN" in text
    assert "Label identifier: F-MIDR.20S145;1" in text  # its title, as the label writes it


def test_real_magellan_framelet_lands_inside_its_label_bounds(corpus_dir: Path):
    label = corpus_dir / "products" / "MGN_FMIDR_FF01" / "FF01.LBL"
    src = open_product(label)
    previews = render_product(src, credit="", browse_width=256, thumb_width=64,
                              azimuth=315.0, altitude=45.0)
    # FF01.LBL: latitudes -18.1813 .. -17.4548, longitudes 141.6269 .. 142.4009.
    assert -18.1813 < previews.scale.latitude < -17.4548
    assert 141.6269 < previews.scale.longitude % 360 < 142.4009
    assert previews.scale.metres_per_column == pytest.approx(75.0 * 1024 / 256, rel=1e-6)


def test_unusable_projection_is_one_line(tmp_path: Path):
    label = magellan_style(tmp_path)
    label.write_text(label.read_text().replace("SINUSOIDAL", '"OBLIQUE CYLINDRICAL"'))
    with pytest.raises(LabelGeorefError, match="OBLIQUE CYLINDRICAL"):
        label_georeferencing(pvl.load(str(label)))
    result = CliRunner().invoke(main, ["extras", str(label), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1
    assert "OBLIQUE CYLINDRICAL" in result.stderr and not (tmp_path / "out").exists()
