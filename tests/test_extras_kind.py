"""Kind detection of GeoTIFFs without a PDS3 label: integer DTMs (iMars, scaled int16)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import rasterio

from pdsgen.extras import make_extras
from pdsgen.extras.product_source import DTM, ORTHO, open_product
from pdsgen.extras.renderings import render_product
from pdsgen.products.dtm import write_dtm
from pdsgen.products.ortho import write_ortho
from test_extras_helpers import crater_field, write_geotiff

DTM_CODES = ("br", "ab", "th", "sb", "sa", "st", "cb", "ca", "ct")


@pytest.fixture()
def heights_tif(tmp_path: Path) -> tuple[Path, np.ndarray]:
    (tmp_path / "in").mkdir()
    z = crater_field(120, 160)
    return write_geotiff(tmp_path / "in" / "heights.tif", z), z


def preview_range(path: Path) -> tuple[float, float]:
    previews = render_product(open_product(path), credit="c", browse_width=80, thumb_width=20,
                              azimuth=315.0, altitude=45.0)
    return previews.display_range


@pytest.mark.parametrize("precision", [1.0, 0.1])
def test_imars_dtm_geotiff_is_a_dtm_in_metres(heights_tif, tmp_path: Path, precision):
    source, z = heights_tif
    product = write_dtm(source, tmp_path / "o", profile="imars", product_id="h1234_0000",
                        precision=precision)
    tif = product.tiff_path
    assert tif.name == "h1234_0000_da4_ucl.tif"
    with rasterio.open(tif) as ds:
        assert ds.dtypes[0] == "int16" and ds.nodata == -32768
    src = open_product(tif)
    assert src.kind == DTM
    low, high = preview_range(tif)
    assert float(z.min()) - 1 <= low < high <= float(z.max()) + 1  # metres, not DN
    out = tmp_path / "extras"
    written = make_extras([tif], out, browse_width=100)
    assert {f"h1234_0000_da4_ucl.{c}.jpg" for c in DTM_CODES} <= {p.name for p in written}
    text = (out / "README.TXT").read_text()
    shown = float(re.search(r"VALID_MINIMUM:\s+(\S+)", text).group(1))
    assert shown == pytest.approx(float(z.min()), abs=precision)
    assert "Digital terrain model" in text


def test_int16_with_band_scale_and_no_other_hint_is_a_dtm(tmp_path: Path):
    (tmp_path / "in").mkdir()
    z = crater_field(100, 120)
    dn = np.rint((z + 4000.0) / 0.25).astype(np.int16)
    tif = write_geotiff(tmp_path / "in" / "scene.tif", dn, nodata=-32768)
    with rasterio.open(tif, "r+") as ds:
        ds.scales, ds.offsets = (0.25,), (-4000.0,)
    src = open_product(tif)
    assert src.kind == DTM and (src.scale, src.offset) == (0.25, -4000.0)
    low, high = preview_range(tif)
    assert float(z.min()) - 1 <= low < high <= float(z.max()) + 1


@pytest.mark.parametrize("tags", [
    {"DESCRIPTION": "Elevation above the areoid"},
    {"TIFFTAG_IMAGEDESCRIPTION": "HiRISE DTM, heights in metres"},
    {"PRODUCT_ID": "ctx_stereo_dtm_01"},
])
def test_int16_tags_saying_height_make_a_dtm(tmp_path: Path, tags):
    (tmp_path / "in").mkdir()
    dn = np.rint(crater_field(60, 80)).astype(np.int16)
    tif = write_geotiff(tmp_path / "in" / "scene.tif", dn)
    with rasterio.open(tif, "r+") as ds:
        ds.update_tags(**tags)
    assert open_product(tif).kind == DTM


def test_hrsc_dtm_names_make_a_dtm_and_orthoimages_stay_orthoimages(tmp_path: Path):
    (tmp_path / "in").mkdir()
    dn = np.rint(crater_field(60, 80)).astype(np.int16)
    for name in ("h1234_0000_dt4.tif", "H5678_0001_DA4_UCL.tif"):
        assert open_product(write_geotiff(tmp_path / "in" / name, dn)).kind == DTM, name
    for name in ("h1234_0000_nd4.tif", "plain.tif", "dtmaker_output.tif"):
        assert open_product(write_geotiff(tmp_path / "in" / name, dn)).kind == ORTHO, name
    byte = (np.arange(60 * 80).reshape(60, 80) % 250 + 1).astype(np.uint8)
    source = write_geotiff(tmp_path / "in" / "ori.tif", byte)
    ori = write_ortho(source, tmp_path / "o", profile="imars", product_id="h1234_0000")
    assert open_product(ori.tiff_path).kind == ORTHO


def test_kind_option_still_overrides_detection(heights_tif, tmp_path: Path):
    source, _ = heights_tif
    tif = write_dtm(source, tmp_path / "o", profile="imars", product_id="h1234_0000").tiff_path
    assert open_product(tif, "ortho").kind == ORTHO


def test_gdal_band_unit_in_kilometres_gives_heights_in_metres(tmp_path: Path):
    (tmp_path / "in").mkdir()
    z = crater_field(100, 120)
    dn = np.rint(z).astype(np.int16)          # metres as DN, declared km * 0.001
    tif = write_geotiff(tmp_path / "in" / "scene.tif", dn)
    with rasterio.open(tif, "r+") as ds:
        ds.scales = (0.001,)
        ds.units = ("km",)
    low, high = preview_range(tif)
    assert float(z.min()) - 1 <= low < high <= float(z.max()) + 1


def test_float_reflectance_geotiff_is_an_orthoimage_not_a_dtm(tmp_path: Path):
    """I/F 0.06 .. 0.14 once got shaded relief and an 'Elevation (m) 0.06-0.14' ramp."""
    from click.testing import CliRunner

    from pdsgen.cli import main

    (tmp_path / "in").mkdir()
    rows, cols = np.mgrid[0:80, 0:120]
    iof = (0.06 + 0.08 * ((rows * 5 + cols * 3) % 97) / 96.0).astype(np.float32)
    tif = write_geotiff(tmp_path / "in" / "scene_iof.tif", iof)
    src = open_product(tif)
    assert src.kind == ORTHO and "reflectance" in src.kind_reason
    result = CliRunner().invoke(main, ["extras", str(tif), "-o", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert "taken as an orthoimage" in result.stderr and result.stderr.count("\n") == 1
    names = {p.name for p in (tmp_path / "out").iterdir()}
    assert "scene_iof.abrowse.jpg" in names and not any(".sa." in n for n in names)


def test_ambiguous_float_raster_is_refused_with_a_hint_to_give_kind(tmp_path: Path):
    from click.testing import CliRunner

    from pdsgen.cli import main

    (tmp_path / "in").mkdir()
    values = (crater_field(60, 80) + 4500.0).astype(np.float32)   # 420 .. 500, nothing said
    tif = write_geotiff(tmp_path / "in" / "unknown.tif", values)
    result = CliRunner().invoke(main, ["extras", str(tif), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1
    assert "--kind dtm or --kind ortho" in result.stderr and "unknown.tif" in result.stderr
    assert not (tmp_path / "out").exists()
    assert open_product(tif, "dtm").kind == DTM            # the user decides
    with rasterio.open(tif, "r+") as ds:
        ds.units = ("metre",)
    assert open_product(tif).kind_reason == "its band unit is metre"
