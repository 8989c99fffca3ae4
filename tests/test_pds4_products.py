"""PDS4 products: DTMs in the three projections and a HiRISE orthoimage pass XML Schema and
Schematron, and independent readers (GDAL's PDS4 driver, pds4_tools, OpenJPEG) read back
the same grid, CRS, nodata and samples."""

from __future__ import annotations

import numpy as np
import pytest
import rasterio

from pdsgen.pds4 import schematron
from pdsgen.pds4.products import write_dtm_pds4, write_ortho_pds4
from pdsgen.pds4.validate import validate_pds4

from helpers import ORIGINS, elevation_array, write_raster

pytestmark = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")


@pytest.fixture(scope="module")
def dtms(tmp_path_factory):
    """One small DTM per projection (with a nodata pixel), written as PDS4; the MSB one polar."""
    root = tmp_path_factory.mktemp("pds4_dtm")
    made = {}
    for name, (crs, transform) in ORIGINS.items():
        data = elevation_array(37, 53, seed=len(name))
        data[3, 5] = -9999.0
        source = write_raster(root / f"{name}.tif", data, crs, transform, nodata=-9999.0)
        label = write_dtm_pds4(source, root / "out", product_id=f"DTM_{name.upper()}",
                               byte_order="msb" if name == "polar" else "lsb")
        made[name] = (source, label)
    return made


@pytest.mark.parametrize("name", sorted(ORIGINS))
def test_dtm_label_passes_schema_and_schematron(dtms, name):
    _, label = dtms[name]
    assert validate_pds4(label.path) == []
    assert "cart:Geo_Transformation" in label.text and "IEEE754" in label.text


@pytest.mark.parametrize("name", sorted(ORIGINS))
def test_gdal_reads_dtm_back_to_same_grid_crs_and_nodata(dtms, name):
    source, label = dtms[name]
    with rasterio.open(source) as original, rasterio.open(label.path) as product:
        assert product.driver == "PDS4"
        assert product.transform == original.transform
        assert product.crs == original.crs
        assert product.nodata == pytest.approx(-3.4028226550889045e38, rel=1e-15)
        data, expected = product.read(1), original.read(1)
        valid = expected != -9999.0
        assert np.array_equal(data[valid], expected[valid])
        assert data[3, 5] == np.float32(product.nodata)


@pytest.mark.parametrize("name", sorted(ORIGINS))
def test_pds4_tools_reads_the_array(dtms, name):
    pds4_tools = pytest.importorskip("pds4_tools")
    source, label = dtms[name]
    structures = pds4_tools.read(str(label.path), quiet=True, lazy_load=True)
    array = np.asarray(structures["image"].data)
    with rasterio.open(source) as original:
        expected = original.read(1)
    valid = expected != -9999.0
    assert array.shape == expected.shape
    assert np.array_equal(array[valid], expected[valid])


def test_dtm_statistics_are_those_of_the_valid_samples(dtms):
    source, label = dtms["equirectangular"]
    with rasterio.open(source) as original:
        values = original.read(1).astype(np.float64)
    values = values[values != -9999.0]
    stats = label.statistics
    assert stats.count == values.size
    assert stats.minimum == np.float32(values.min()) and stats.maximum == np.float32(values.max())
    assert stats.mean == pytest.approx(values.mean(), rel=1e-12)
    assert stats.standard_deviation == pytest.approx(values.std(), rel=1e-9)


@pytest.fixture(scope="module")
def ortho(tmp_path_factory):
    root = tmp_path_factory.mktemp("pds4_ortho")
    crs, transform = ORIGINS["equirectangular"]
    rng = np.random.default_rng(5)
    data = (rng.random((45, 70)) * 0.2 + 0.05).astype("float32")
    data[0, :4] = np.nan
    source = write_raster(root / "ortho.tif", data, crs, transform)
    label = write_ortho_pds4(source, root / "out", product_id="PSP_008669_1705_RED_C_01_ORTHO", profile="hirise")
    return source, label


def test_hirise_ortho_passes_schema_and_schematron(ortho):
    _, label = ortho
    assert validate_pds4(label.path) == []
    assert "<encoding_standard_id>JP2</encoding_standard_id>" in label.text
    assert "urn:nasa:pds:context:instrument:mro.hirise" in label.text


def test_ortho_primary_array_equals_the_jp2_and_keeps_the_grid(ortho):
    source, label = ortho
    jp2 = label.path.with_suffix(".jp2")
    with rasterio.open(label.path) as primary, rasterio.open(jp2) as encoded, rasterio.open(source) as original:
        assert primary.transform == original.transform and primary.crs == original.crs
        assert encoded.transform == original.transform
        dns = primary.read(1)
        assert np.array_equal(dns, encoded.read(1))
        assert primary.nodata == 0 and (dns[0, :4] == 0).all() and dns[1:].min() >= 3


def test_three_band_ortho_is_an_array_3d_image_gdal_reads_band_by_band(tmp_path):
    crs, transform = ORIGINS["polar"]
    data = np.random.default_rng(8).integers(3, 1000, (3, 30, 41)).astype("uint16")
    source = write_raster(tmp_path / "irb.tif", data, crs, transform)
    label = write_ortho_pds4(source, tmp_path / "out", product_id="PSP_008669_1705_IRB_C_01_ORTHO",
                             profile="hirise", bits=10)
    assert validate_pds4(label.path) == []
    assert "<Array_3D_Image>" in label.text and "<axis_name>Band</axis_name>" in label.text
    with rasterio.open(label.path) as primary, rasterio.open(label.path.with_suffix(".jp2")) as encoded:
        assert primary.count == 3 and primary.crs == encoded.crs
        assert np.array_equal(primary.read(), data) and np.array_equal(encoded.read(), data)
