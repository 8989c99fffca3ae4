"""The DTM .IMG read back by independent readers: GDAL (rasterio), pdr and pvl."""

from __future__ import annotations

import math

import numpy as np
import pdr
import pvl
import pytest
import rasterio
from affine import Affine

from pdsgen import write_dtm

from helpers import CRS_EQUIRECTANGULAR, ORIGINS, elevation_array, write_raster

ISIS_NULL = -3.4028226550889045e38


def _equivalent_crs(a, b) -> None:
    da, db = a.to_dict(), b.to_dict()
    assert da["proj"] == db["proj"]
    for key in ("lat_ts", "lon_0", "lat_0"):
        if key in da or key in db:
            assert math.isclose(float(da.get(key, 0.0)) % 360, float(db.get(key, 0.0)) % 360, abs_tol=1e-9), key
    radius_a = float(da.get("R", da.get("a")))
    radius_b = float(db.get("R", db.get("a")))
    assert math.isclose(radius_a, radius_b, rel_tol=1e-12)


def _assert_same_georeference(src_transform: Affine, out_transform: Affine) -> None:
    pixel = src_transform.a
    for got, want in zip(out_transform[:6], src_transform[:6], strict=True):
        assert abs(got - want) <= 1e-6 * pixel


@pytest.mark.parametrize("kind", ["equirectangular", "polar", "sinusoidal"])
def test_gdal_reads_same_grid_values_and_nodata(tmp_path, kind):
    crs, transform = ORIGINS[kind]
    data = elevation_array(120, 90, seed=3)
    data[5:9, 7:11] = -9999.0
    data[50, 50] = np.nan
    source = write_raster(tmp_path / "in.tif", data, crs, transform, nodata=-9999.0)

    product = write_dtm(source, tmp_path / "out", product_id="TEST_DTM")

    with rasterio.open(source) as src, rasterio.open(product.path) as out:
        assert out.driver == "PDS"
        assert (out.width, out.height, out.count) == (90, 120, 1)
        _assert_same_georeference(src.transform, out.transform)
        _equivalent_crs(src.crs, out.crs)
        values = out.read(1)
    valid = (data != -9999.0) & np.isfinite(data)
    assert np.array_equal(values[valid].view(np.uint32), data[valid].view(np.uint32))
    assert np.all(values[~valid] == np.float32(ISIS_NULL))
    assert np.float32(product.valid_minimum) == data[valid].min()
    assert np.float32(product.valid_maximum) == data[valid].max()


def test_label_record_arithmetic_and_text_rules(tmp_path):
    data = elevation_array(40, 64)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1])
    product = write_dtm(source, tmp_path / "out")
    raw = product.path.read_bytes()
    label = pvl.loads(product.label_text)
    record_bytes = label["RECORD_BYTES"]
    assert record_bytes == 64 * 4
    assert len(raw) == label["FILE_RECORDS"] * record_bytes
    assert label["FILE_RECORDS"] == label["LABEL_RECORDS"] + 40
    assert label["^IMAGE"] == label["LABEL_RECORDS"] + 1
    label_bytes = raw[: label["LABEL_RECORDS"] * record_bytes]
    text = label_bytes.rstrip(b" ")
    assert text.endswith(b"END\r\n")
    assert math.ceil(len(text) / record_bytes) == label["LABEL_RECORDS"]  # minimal, not over-reserved
    assert label_bytes[len(text):] == b" " * (len(label_bytes) - len(text))
    for line in text.split(b"\r\n")[:-1]:
        assert len(line) + 2 <= 80
        assert b"\n" not in line and b"\r" not in line
        assert all(32 <= byte < 127 for byte in line)
    assert text.startswith(b"PDS_VERSION_ID = PDS3\r\n")


def test_label_content_matches_data_and_geometry(tmp_path):
    data = elevation_array(30, 20)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1])
    product = write_dtm(source, tmp_path / "out", source_product_ids=["PSP_008669_1705", "PSP_009025_1705"])
    label = pvl.load(str(product.path))
    image = label["IMAGE"]
    assert image["SAMPLE_TYPE"] == "PC_REAL"
    assert image["SAMPLE_BITS"] == 32
    assert image["MISSING_CONSTANT"] == 0xFF7FFFFB
    assert np.float32(image["VALID_MINIMUM"]) == data.min()
    assert np.float32(image["VALID_MAXIMUM"]) == data.max()
    assert list(label["SOURCE_PRODUCT_ID"]) == ["PSP_008669_1705", "PSP_009025_1705"]
    projection = label["IMAGE_MAP_PROJECTION"]
    assert projection["MAP_PROJECTION_TYPE"] == "EQUIRECTANGULAR"
    assert projection["A_AXIS_RADIUS"].value == 3396.19
    assert projection["CENTER_LATITUDE"].value == -5.0
    scale = projection["MAP_SCALE"].value
    resolution = projection["MAP_RESOLUTION"].value
    assert math.isclose(resolution, math.pi * 3396190.0 / 180.0 / scale, rel_tol=1e-12)
    ulx, uly = ORIGINS["equirectangular"][1].c, ORIGINS["equirectangular"][1].f
    assert projection["SAMPLE_PROJECTION_OFFSET"].value == pytest.approx(-ulx / scale - 0.5, abs=1e-6)
    assert projection["LINE_PROJECTION_OFFSET"].value == pytest.approx(uly / scale - 0.5, abs=1e-6)
    # Bounds from the outer pixel edges through the sphere formulas of the docs.
    r = 3396190.0
    lat_top = math.degrees(uly / r)
    lat_bottom = math.degrees((uly - 30 * scale) / r)
    assert projection["MAXIMUM_LATITUDE"].value == pytest.approx(lat_top, abs=1e-9)
    assert projection["MINIMUM_LATITUDE"].value == pytest.approx(lat_bottom, abs=1e-9)
    west = 180.0 + math.degrees(ulx / (r * math.cos(math.radians(-5.0))))
    east = 180.0 + math.degrees((ulx + 20 * scale) / (r * math.cos(math.radians(-5.0))))
    assert projection["WESTERNMOST_LONGITUDE"].value == pytest.approx(west % 360, abs=1e-9)
    assert projection["EASTERNMOST_LONGITUDE"].value == pytest.approx(east % 360, abs=1e-9)
    assert label["VIEWING_PARAMETERS"]["NORTH_AZIMUTH"].value == 270.0


def test_pdr_reads_the_same_array(tmp_path):
    data = elevation_array(25, 33)
    data[0, 0] = -9999.0
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1],
                          nodata=-9999.0)
    product = write_dtm(source, tmp_path / "out", product_id="PDR_CHECK")
    observed = pdr.read(str(product.path))
    image = np.asarray(observed["IMAGE"])
    assert image.shape == (25, 33)
    assert np.array_equal(image[1:], data[1:])
    assert image[0, 0] == np.float32(ISIS_NULL)


@pytest.mark.parametrize("width", [1, 3, 7])
def test_narrow_rasters_need_many_label_records(tmp_path, width):
    data = elevation_array(50, width)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1])
    product = write_dtm(source, tmp_path / "out", product_id="NARROW")
    raw = product.path.read_bytes()
    label = pvl.load(str(product.path))
    assert label["RECORD_BYTES"] == width * 4
    assert label["LABEL_RECORDS"] > 10
    assert len(raw) == label["FILE_RECORDS"] * label["RECORD_BYTES"]
    assert math.ceil(len(product.label_text) / (width * 4)) == label["LABEL_RECORDS"]
    with rasterio.open(product.path) as out:
        assert np.array_equal(out.read(1), data)


def test_msb_byte_order_reads_back_identically(tmp_path):
    data = elevation_array(40, 30)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1])
    lsb = write_dtm(source, tmp_path / "lsb", product_id="ORDER")
    msb = write_dtm(source, tmp_path / "msb", product_id="ORDER", byte_order="msb")
    assert pvl.load(str(msb.path))["IMAGE"]["SAMPLE_TYPE"] == "IEEE_REAL"
    with rasterio.open(lsb.path) as a, rasterio.open(msb.path) as b:
        assert np.array_equal(a.read(1), b.read(1))
        assert np.array_equal(b.read(1), data)
    assert np.array_equal(np.asarray(pdr.read(str(msb.path))["IMAGE"]), data)


def test_integer_input_and_multiple_strips(tmp_path, monkeypatch):
    import pdsgen.formats.raster as read_raster

    monkeypatch.setattr(read_raster, "STRIP_BYTES", 4096)  # force many strips on a small raster
    data = (elevation_array(257, 61) * 1).astype(np.int16)
    data[100, :] = -32768
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1],
                          nodata=-32768)
    product = write_dtm(source, tmp_path / "out", product_id="INT16")
    with rasterio.open(product.path) as out:
        values = out.read(1)
    assert np.array_equal(values[data != -32768], data[data != -32768].astype(np.float32))
    assert np.all(values[100] == np.float32(ISIS_NULL))
    assert product.valid_minimum == float(data[data != -32768].min())


def test_output_is_byte_for_byte_reproducible(tmp_path):
    data = elevation_array(20, 20)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1])
    first = write_dtm(source, tmp_path / "a", product_id="SAME").path.read_bytes()
    second = write_dtm(source, tmp_path / "b", product_id="SAME").path.read_bytes()
    assert first == second


def test_isis_cube_input(tmp_path):
    data = elevation_array(64, 48)
    transform = ORIGINS["equirectangular"][1]
    cube = write_raster(tmp_path / "in.cub", data, CRS_EQUIRECTANGULAR, transform, driver="ISIS3")
    product = write_dtm(cube, tmp_path / "out", product_id="FROM_CUBE")
    with rasterio.open(cube) as src, rasterio.open(product.path) as out:
        _assert_same_georeference(src.transform, out.transform)
        assert np.array_equal(out.read(1), src.read(1))
