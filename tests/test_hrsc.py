"""HRSC level-4 DTMs (DT4/DA4): 16-bit heights with MEX:DTM scaling, read back by GDAL and pvl."""

from __future__ import annotations

import numpy as np
import pvl
import pytest
import rasterio
from affine import Affine
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen.errors import PdsgenError
from pdsgen.products.dtm import write_dtm

from helpers import elevation_array, run_cli, write_raster

SINUSOIDAL = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"
SOUTH_POLAR = "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs"
GRIDS = {
    "sinusoidal": (SINUSOIDAL, Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0)),
    "south_polar": (SOUTH_POLAR, Affine(50.0, 0, 100000.0, 0, -50.0, 60000.0)),
}
LONLAT = CRS.from_proj4("+proj=longlat +R=3396000 +no_defs")


def _areoid_height(lon, lat):
    """A smooth areoid model, linear in lon/lat so bilinear resampling reproduces it exactly."""
    return 250.0 + 12.5 * np.asarray(lon) - 40.0 * np.asarray(lat)


def _areoid_grid(tmp_path, lon_range, lat_range):
    lons = np.arange(lon_range[0], lon_range[1] + 1e-9, 0.05)
    lats = np.arange(lat_range[1], lat_range[0] - 1e-9, -0.05)
    grid = _areoid_height(lons[None, :], lats[:, None]).astype(np.float32)
    transform = Affine(0.05, 0, lons[0] - 0.025, 0, -0.05, lats[0] + 0.025)
    return write_raster(tmp_path / "areoid.tif", grid, LONLAT.to_proj4(), transform)


def _pixel_lonlat(dataset):
    rows, cols = np.mgrid[0 : dataset.height, 0 : dataset.width]
    xs, ys = rasterio.transform.xy(dataset.transform, rows.ravel(), cols.ravel())
    lons, lats = warp_transform(dataset.crs, LONLAT, xs, ys)
    return np.reshape(lons, rows.shape), np.reshape(lats, rows.shape)


@pytest.mark.parametrize("grid", ["sinusoidal", "south_polar"])
def test_dt4_heights_round_trip_through_scaling_and_gdal_reads_grid(tmp_path, grid):
    crs, transform = GRIDS[grid]
    heights = elevation_array(120, 100, seed=7)
    heights[10:14, 20:30] = np.nan
    source = write_raster(tmp_path / "in.tif", heights, crs, transform)
    product = write_dtm(source, tmp_path / "out", profile="hrsc", precision=0.05, source_product_ids=["H1234_0000_ND3"])
    assert product.path.name == "h1234_0000_dt4.img"
    with rasterio.open(source) as src, rasterio.open(product.path) as out:
        assert out.dtypes[0] == "int16"
        assert out.transform.almost_equals(src.transform, precision=1e-6 * 50)
        assert out.crs.to_dict()["proj"] == src.crs.to_dict()["proj"]
        assert out.scales[0] == pytest.approx(0.05) and out.offsets[0] == product.encoding.offset
        dn = out.read(1)
    valid = np.isfinite(heights)
    assert np.all(dn[~valid] == -32768)
    restored = dn * product.encoding.scaling_factor + product.encoding.offset
    assert np.max(np.abs(restored[valid] - heights[valid])) <= 0.05 / 2 + 1e-3
    label = pvl.load(str(product.path))
    group = label["MEX:DTM"]
    assert group["MEX:DTM_MISSING_DN"] == -32768
    assert group["MEX:DTM_A_AXIS_RADIUS"].value == 3396.0
    assert group["MEX:DTM_DESC"] == "HEIGHT ABOVE SPHEROID"
    assert group["MEX:DTM_SCALING_FACTOR"].value == pytest.approx(0.05)
    expected_type = "SINUSOIDAL" if grid == "sinusoidal" else "POLAR STEREOGRAPHIC"
    assert label["IMAGE_MAP_PROJECTION"]["MAP_PROJECTION_TYPE"] == expected_type
    assert label["ORBIT_NUMBER"] == 1234


def test_da4_differs_from_dt4_by_the_areoid(tmp_path):
    crs, transform = GRIDS["sinusoidal"]
    heights = elevation_array(80, 60, seed=9)
    source = write_raster(tmp_path / "in.tif", heights, crs, transform)
    with rasterio.open(source) as src:
        lons, lats = _pixel_lonlat(src)
    areoid = _areoid_grid(tmp_path, (lons.min() - 0.5, lons.max() + 0.5), (lats.min() - 0.5, lats.max() + 0.5))
    dt4 = write_dtm(source, tmp_path / "out", profile="hrsc", kind="dt4", precision=0.05, product_id="h0001_0000")
    da4 = write_dtm(source, tmp_path / "out", profile="hrsc", kind="da4", areoid=areoid, precision=0.05,
                    product_id="h0001_0000")
    assert da4.path.name == "h0001_0000_da4.img"
    with rasterio.open(dt4.path) as a, rasterio.open(da4.path) as b:
        sphere = a.read(1) * a.scales[0] + a.offsets[0]
        above_areoid = b.read(1) * b.scales[0] + b.offsets[0]
    difference = sphere - above_areoid
    assert np.max(np.abs(difference - _areoid_height(lons, lats))) <= 0.05 + 1e-3
    label = pvl.load(str(da4.path))
    assert label["MEX:DTM"]["MEX:DTM_DESC"] == "HEIGHT ABOVE GM3-AREOID"
    assert label["MEX:DTM"]["MEX:DTM_A_AXIS_RADIUS"].value == -1e32


def test_datum_conversion_needs_an_areoid(tmp_path):
    crs, transform = GRIDS["sinusoidal"]
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), crs, transform)
    with pytest.raises(PdsgenError, match="`areoid`"):
        write_dtm(source, tmp_path / "out", profile="hrsc", kind="da4", product_id="h0001_0000")


def test_range_that_cannot_fit_16_bits_is_refused(tmp_path):
    crs, transform = GRIDS["sinusoidal"]
    heights = elevation_array(10, 10)
    heights[0, 0] = -8000.0
    heights[0, 1] = 21000.0
    source = write_raster(tmp_path / "in.tif", heights, crs, transform)
    result = run_cli("dtm", source, "-o", tmp_path / "out", "--profile", "hrsc", "--product-id", "h0001_0000",
                     "--precision", "0.1")
    assert result.returncode == 2
    assert "do not fit 16-bit samples" in result.stderr
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_wrong_projection_is_refused_then_reprojected(tmp_path):
    equirectangular = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs"
    heights = elevation_array(60, 80, seed=2)
    source = write_raster(tmp_path / "in.tif", heights, equirectangular,
                          Affine(100.0, 0, 4000000.0, 0, -100.0, -1200000.0))
    refused = run_cli("dtm", source, "-o", tmp_path / "out", "--profile", "hrsc", "--product-id", "h0002_0001")
    assert refused.returncode == 2 and "--reproject" in refused.stderr
    product = write_dtm(source, tmp_path / "out", profile="hrsc", product_id="h0002_0001", reproject_input=True,
                        precision=0.1)
    with rasterio.open(product.path) as out:
        params = out.crs.to_dict()
        assert params["proj"] == "sinu" and float(params.get("R", params.get("a"))) == 3396000.0
        assert out.transform.a == pytest.approx(100.0)
        restored = out.read(1, masked=True) * out.scales[0] + out.offsets[0]
    assert restored.count() > 0.8 * heights.size * 0.8
    # heights above the 3396.19 km input sphere are 190 m higher above the 3396.0 km sphere
    shift = 3396190.0 - 3396000.0
    assert heights.min() + shift - 1 <= restored.min() and restored.max() <= heights.max() + shift + 1


def test_polar_product_near_the_pole_must_be_polar_stereographic(tmp_path):
    near_pole_sinusoidal = "+proj=sinu +lon_0=0 +R=3396000 +units=m +no_defs"
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), near_pole_sinusoidal,
                          Affine(50.0, 0, 0.0, 0, -50.0, -5200000.0))
    with pytest.raises(PdsgenError, match="polar stereographic"):
        write_dtm(source, tmp_path / "out", profile="hrsc", product_id="h0003_0000")


def test_vicar_earth_input_from_hrsc_ax(tmp_path):
    """HRSC-AX airborne DEMs: VICAR files on an Earth ellipsoid, read through GDAL."""
    earth = "+proj=eqc +lat_ts=0 +lon_0=0 +a=6378140 +b=6356750 +units=m +no_defs"
    heights = (36.5 + elevation_array(40, 30) / 100.0).astype(np.float32)
    source = write_raster(tmp_path / "ax.vic", heights, earth, Affine(1.0, 0, 500000.0, 0, -1.0, 5300000.0),
                          driver="VICAR")
    from pdsgen import write_dtm

    product = write_dtm(source, tmp_path / "out", product_id="HRSC_AX_TILE")
    label = pvl.load(str(product.path))
    assert label["TARGET_NAME"] == "EARTH"
    projection = label["IMAGE_MAP_PROJECTION"]
    with rasterio.open(source) as src:
        radius = float(src.crs.to_dict().get("R", src.crs.to_dict().get("a")))
    assert projection["A_AXIS_RADIUS"].value == pytest.approx(radius / 1000.0)
    with rasterio.open(product.path) as out:
        assert np.array_equal(out.read(1), heights)


def test_nd4_orthoimage_is_8_bit_with_null_zero(tmp_path):
    crs, transform = GRIDS["sinusoidal"]
    reflectance = np.linspace(0.02, 0.3, 60 * 40, dtype=np.float32).reshape(60, 40)
    reflectance[0, :5] = np.nan
    source = write_raster(tmp_path / "nadir.tif", reflectance, crs, transform)
    result = run_cli("ortho", source, "-o", tmp_path / "out", "--profile", "hrsc",
                     "--source-product-id", "H1234_0000_ND3")
    assert result.returncode == 0, result.stderr
    path = tmp_path / "out" / "h1234_0000_nd4.img"
    label = pvl.load(str(path))
    assert label["IMAGE"]["SAMPLE_BITS"] == 8 and label["IMAGE"]["MISSING_CONSTANT"] == 0
    with rasterio.open(path) as out:
        dn = out.read(1)
        assert out.transform.almost_equals(transform, precision=1e-6)
    assert np.all(dn[0, :5] == 0) and dn[1:].min() >= 1 and dn.max() <= 254
    scale, offset = label["IMAGE"]["SCALING_FACTOR"], label["IMAGE"]["OFFSET"]
    valid = np.isfinite(reflectance)
    assert np.max(np.abs(dn[valid] * scale + offset - reflectance[valid])) <= scale / 2 + 1e-7


def test_extras_of_hrsc_products_use_hrsc_names_and_credit(tmp_path):
    from PIL import Image

    from pdsgen.extras import make_extras
    from pdsgen.extras.product_source import open_product

    crs, transform = GRIDS["sinusoidal"]
    source = write_raster(tmp_path / "in.tif", elevation_array(120, 100, seed=4), crs, transform)
    product = write_dtm(source, tmp_path / "out", profile="hrsc", product_id="h1234_0000")
    assert open_product(product.path).mission == "hrsc"
    written = make_extras([product.path], tmp_path / "extras")
    names = {path.name for path in written}
    assert {"h1234_0000_dt4.br.jpg", "h1234_0000_dt4.ca.jpg", "README.TXT"} <= names
    readme = (tmp_path / "extras" / "README.TXT").read_text()
    assert "ESA/DLR/FU Berlin" in readme
    with Image.open(tmp_path / "extras" / "h1234_0000_dt4.ab.jpg") as annotated:
        assert annotated.width > 0



@pytest.mark.parametrize(("precision", "needle"), [("inf", "positive number"), ("nan", "positive number"),
                                                    ("0", "positive number"), ("1e6", "too coarse")])
def test_unusable_precision_is_refused(tmp_path, precision, needle):
    crs, transform = GRIDS["sinusoidal"]
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), crs, transform)
    for profile in ("hrsc", "imars"):
        result = run_cli("dtm", source, "-o", tmp_path / "out", "--profile", profile, "--product-id",
                         "h0001_0000", "--precision", precision)
        assert result.returncode == 2 and needle in result.stderr, (profile, result.stderr)
        assert "Traceback" not in result.stderr
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_reproject_without_a_crs_is_a_clear_error(tmp_path):
    source = write_raster(tmp_path / "nocrs.tif", elevation_array(10, 10), None, Affine(1, 0, 0, 0, -1, 10))
    for command in ("dtm", "ortho"):
        result = run_cli(command, source, "-o", tmp_path / "out", "--profile", "hrsc", "--product-id",
                         "h0001_0000", "--reproject")
        assert result.returncode == 2, result.stderr
        assert "no coordinate reference system" in result.stderr and "Traceback" not in result.stderr


def test_hrsc_ortho_refuses_options_it_cannot_honour(tmp_path):
    crs, transform = GRIDS["sinusoidal"]
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), crs, transform)
    for args, needle in ((["--bits", "16"], "8-bit"), (["--gmljp2"], "--gmljp2 does not apply"),
                         (["--sequence", "3"], "--sequence does not apply")):
        result = run_cli("ortho", source, "-o", tmp_path / "out", "--profile", "hrsc", "--product-id",
                         "h0001_0000", *args)
        assert result.returncode == 2 and needle in result.stderr, result.stderr


def test_multiband_nadir_image_is_named_as_such(tmp_path):
    crs, transform = GRIDS["sinusoidal"]
    data = np.stack([elevation_array(10, 10)] * 3)
    source = write_raster(tmp_path / "rgb.tif", data, crs, transform)
    result = run_cli("ortho", source, "-o", tmp_path / "out", "--profile", "hrsc", "--product-id", "h0001_0000",
                     "--reproject")
    assert result.returncode == 2
    assert "rgb.tif: has 3 bands; an HRSC nadir image must have exactly one" in result.stderr
