"""iMars delivery form: int16 GeoTIFF + PVL metadata + GeoJSON footprint, checked with GDAL and pvl."""

from __future__ import annotations

import json

import numpy as np
import pvl
import pytest
import rasterio
from affine import Affine

from pdsgen.products.dtm import write_dtm

from helpers import elevation_array, run_cli, write_raster

SOUTH_POLAR = "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs"


@pytest.fixture
def polar_dtm(tmp_path):
    heights = elevation_array(90, 70, seed=11)
    heights[:5, :] = np.nan
    transform = Affine(100.0, 0, -20000.0, 0, -100.0, 150000.0)
    return write_raster(tmp_path / "in.tif", heights, SOUTH_POLAR, transform), heights


def test_geotiff_has_nodata_scaling_and_processing_tags(tmp_path, polar_dtm):
    source, heights = polar_dtm
    params = tmp_path / "params.toml"
    params.write_text('extraction_method = "CASP-GO"\n[matcher_parameters]\nwindow = 15\nthreshold = 0.2\n')
    product = write_dtm(source, tmp_path / "out", profile="imars", product_id="h0022_0000", precision=0.1,
                        params=params)
    assert product.tiff_path.name == "h0022_0000_da4_ucl.tif"
    with rasterio.open(product.tiff_path) as out:
        assert out.nodata == -32768
        assert out.dtypes[0] == "int16"
        assert out.scales[0] == pytest.approx(0.1)
        tags = out.tags()
        dn = out.read(1)
        assert out.crs.to_dict()["proj"] == "stere"
    assert tags["PRODUCT_ID"] == "h0022_0000_da4" and tags["ALGORITHM"] == "CASP-GO"
    assert tags["TIFFTAG_SOFTWARE"].startswith("pdsgen")
    valid = np.isfinite(heights)
    assert np.all(dn[~valid] == -32768)
    restored = dn * 0.1 + product.encoding.offset
    assert np.max(np.abs(restored[valid] - heights[valid])) <= 0.05 + 1e-3


def test_pvl_metadata_matches_the_geotiff(tmp_path, polar_dtm):
    source, _ = polar_dtm
    params = tmp_path / "params.pvl"
    params.write_text('EXTRACTION_METHOD = "CASP-GO"\nGROUP = MATCHER_PARAMETERS\n  WINDOW = 15\n'
                      'END_GROUP = MATCHER_PARAMETERS\nEND\n')
    product = write_dtm(source, tmp_path / "out", profile="imars", product_id="h0022_0000", params=params)
    assert product.pvl_path.name == "h0022_0000_da4_ucl.pvl"
    label = pvl.load(str(product.pvl_path))
    assert set(label.keys()) >= {"ProductInfo", "Image", "DataProduct", "MapProjection", "Algorithm"}
    assert label["ProductInfo"]["Producer"]["ProducerInstitutionName"]
    with rasterio.open(product.tiff_path) as out:
        image = label["Image"]
        assert (image["Lines"], image["Samples"], image["Bands"]) == (out.height, out.width, out.count)
        assert image["NoData"] == out.nodata
        assert image["ScalingFactor"] == out.scales[0] and image["Offset"] == out.offsets[0]
        data = out.read(1, masked=True)
        assert (image["ValidMinimum"], image["ValidMaximum"]) == (data.min(), data.max())
        projection = label["MapProjection"]
        assert projection["PixelResolution"].value == out.transform.a
        assert projection["UpperLeftCornerX"].value == out.transform.c
        assert projection["UpperLeftCornerY"].value == out.transform.f
        assert rasterio.crs.CRS.from_proj4(projection["Proj4"]) == out.crs
    assert label["DataProduct"]["FileName"] == product.tiff_path.name
    assert label["Algorithm"]["Name"] == "CASP-GO" and label["Algorithm"]["WINDOW"] == 15


def test_footprint_is_geojson_around_the_valid_data(tmp_path, polar_dtm):
    source, _ = polar_dtm
    product = write_dtm(source, tmp_path / "out", profile="imars", product_id="h0022_0000")
    collection = json.loads(product.footprint_path.read_text())
    assert product.footprint_path.name == "h0022_0000.geojson"
    assert collection["type"] == "FeatureCollection"
    (feature,) = collection["features"]
    assert feature["id"] == "h0022_0000_da4" and feature["geometry"]["type"] == "Polygon"
    ring = np.array(feature["geometry"]["coordinates"][0])
    assert np.all(ring[:, 1] < -80)  # a south-polar product
    again = write_dtm(source, tmp_path / "out", profile="imars", product_id="h0022_0000", kind="dt", overwrite=True)
    ids = [f["id"] for f in json.loads(again.footprint_path.read_text())["features"]]
    assert ids == ["h0022_0000_da4", "h0022_0000_dt4"]


def test_cli_imars_profile(tmp_path, polar_dtm):
    source, _ = polar_dtm
    result = run_cli("dtm", source, "-o", tmp_path / "out", "--profile", "imars", "--product-id", "h0022_0000",
                     "--kind", "da4", "--vertical-datum", "areoid")
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "out" / "h0022_0000_da4_ucl.tif").exists()
    assert (tmp_path / "out" / "h0022_0000_da4_ucl.pvl").exists()


def test_ori_is_byte_geotiff_with_nodata_zero_and_shares_the_footprint(tmp_path, polar_dtm):
    dtm_source, _ = polar_dtm
    image = np.linspace(0.0, 1.0, 90 * 70, dtype=np.float32).reshape(90, 70)
    image[:, :3] = np.nan
    with rasterio.open(dtm_source) as src:
        ori_source = write_raster(tmp_path / "ori.tif", image, src.crs.to_proj4(), src.transform)
    from pdsgen.products.ortho import write_ortho

    write_dtm(dtm_source, tmp_path / "out", profile="imars", product_id="h0022_0000")
    ori = write_ortho(ori_source, tmp_path / "out", profile="imars", product_id="h0022_0000")
    assert ori.tiff_path.name == "h0022_0000_nd4_ucl.tif"
    with rasterio.open(ori.tiff_path) as out:
        assert out.nodata == 0 and out.dtypes[0] == "uint8"
        dn = out.read(1)
    assert np.all(dn[:, :3] == 0) and dn[:, 3:].min() >= 1
    label = pvl.load(str(ori.pvl_path))
    assert label["ProductInfo"]["ProductType"] == "ORI" and label["Image"]["NoData"] == 0
    ids = [f["id"] for f in json.loads(ori.footprint_path.read_text())["features"]]
    assert ids == ["h0022_0000_da4", "h0022_0000_nd4"]


def test_areoid_heights_from_sphere_input_need_an_areoid(tmp_path, polar_dtm):
    source, _ = polar_dtm
    result = run_cli("dtm", source, "-o", tmp_path / "out", "--profile", "imars", "--product-id", "h0022_0000",
                     "--kind", "da4")
    assert result.returncode == 2 and "--areoid" in result.stderr
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


@pytest.mark.parametrize("existing", ["directory", "not a collection"])
def test_footprint_that_cannot_be_updated_leaves_nothing_published(tmp_path, polar_dtm, existing):
    source, _ = polar_dtm
    out = tmp_path / "out"
    out.mkdir()
    footprint = out / "h0022_0000.geojson"
    if existing == "directory":
        footprint.mkdir()
    else:
        footprint.write_text('{"precious": 1}')
    result = run_cli("dtm", source, "-o", out, "--profile", "imars", "--product-id", "h0022_0000")
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and "h0022_0000.geojson" in result.stderr
    assert sorted(p.name for p in out.iterdir()) == ["h0022_0000.geojson"]
    if existing != "directory":
        assert footprint.read_text() == '{"precious": 1}'
