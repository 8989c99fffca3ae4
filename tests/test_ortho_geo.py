"""GeoJP2 (and GMLJP2) boxes: GDAL reads back the input's CRS and geotransform."""

import numpy as np
import pytest
import rasterio
from affine import Affine
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen import write_ortho
from pdsgen.formats.geojp2 import (
    GEOJP2_UUID,
    PROJ_CENTER_LAT,
    PROJ_STD_PARALLEL1,
    degenerate_geotiff,
    geokeys,
    read_geojp2,
)
from pdsgen.formats.jp2 import jp2_boxes
from pdsgen.synthetic import write_geotiff

MARS = "+R=3396190 +units=m +no_defs"
PROJECTIONS = {
    "equirectangular": f"+proj=eqc +lat_ts=-5 +lat_0=0 +lon_0=180 {MARS}",
    "south polar stereographic": f"+proj=stere +lat_0=-90 +lon_0=0 +k=1 +x_0=0 +y_0=0 {MARS}",
    "sinusoidal": f"+proj=sinu +lon_0=75 {MARS}",
}
ORIGINS = {
    "equirectangular": (6099776.25, -563110.75),
    "south polar stereographic": (-123456.5, 234567.25),
    "sinusoidal": (98765.75, 1234567.5),
}


def _input(tmp_path, name, crs, origin, scale=0.5, shape=(300, 420)):
    rng = np.random.default_rng(7)
    data = rng.uniform(0.02, 0.3, size=shape).astype(np.float32)
    transform = Affine(scale, 0.0, origin[0], 0.0, -scale, origin[1])
    return write_geotiff(tmp_path / f"{name}.tif", data, transform, CRS.from_proj4(crs), None), transform


def _same_crs(a: CRS, b: CRS) -> bool:
    """Equivalent CRSs: same body and same projected coordinates for points across the globe."""
    geographic = CRS.from_proj4(f"+proj=longlat {MARS}")
    lons, lats = np.meshgrid(np.arange(0.0, 360.0, 30.0), np.arange(-80.0, -5.0, 15.0))
    xa, ya = warp_transform(geographic, a, lons.ravel(), lats.ravel())
    xb, yb = warp_transform(geographic, b, lons.ravel(), lats.ravel())
    return bool(np.allclose(xa, xb, rtol=0, atol=1e-6) and np.allclose(ya, yb, rtol=0, atol=1e-6))


@pytest.mark.parametrize("name", sorted(PROJECTIONS))
def test_gdal_reads_the_input_geotransform_and_crs(tmp_path, name):
    source, transform = _input(tmp_path, name.replace(" ", "_"), PROJECTIONS[name], ORIGINS[name])
    product = write_ortho(source, tmp_path / "out")
    with rasterio.open(product.jp2_path) as jp2:
        got = jp2.transform
        assert _same_crs(jp2.crs, CRS.from_proj4(PROJECTIONS[name])), jp2.crs.to_proj4()
    assert (got.b, got.d) == (0.0, 0.0)
    assert abs(got.a - transform.a) / transform.a < 1e-12 and abs(got.e - transform.e) / transform.a < 1e-12
    assert abs(got.c - transform.c) / transform.a < 1e-6
    assert abs(got.f - transform.f) / transform.a < 1e-6


def test_equirectangular_standard_parallel_is_in_key_3078(tmp_path):
    tiff = degenerate_geotiff(CRS.from_proj4(PROJECTIONS["equirectangular"]), Affine(1, 0, 0, 0, -1, 0))
    keys = geokeys(tiff)
    assert keys[PROJ_STD_PARALLEL1] == -5.0
    assert keys.get(PROJ_CENTER_LAT, 0.0) == 0.0


def test_geojp2_box_sits_between_header_and_code_stream(tmp_path):
    source, transform = _input(tmp_path, "eqc", PROJECTIONS["equirectangular"], ORIGINS["equirectangular"])
    product = write_ortho(source, tmp_path / "out")
    kinds = [kind for kind, _, _ in jp2_boxes(product.jp2_path)]
    assert kinds == [b"jP  ", b"ftyp", b"jp2h", b"uuid", b"jp2c"]
    with open(product.jp2_path, "rb") as handle:
        handle.seek(jp2_boxes(product.jp2_path)[3][1] + 8)
        assert handle.read(16) == GEOJP2_UUID.bytes
    with rasterio.open(rasterio.io.MemoryFile(read_geojp2(product.jp2_path)).name) as tiff:
        assert (tiff.width, tiff.height) == (1, 1)
        assert tiff.transform == transform


def test_gmljp2_box_gives_the_same_geotransform(tmp_path):
    source, transform = _input(tmp_path, "sinu", PROJECTIONS["sinusoidal"], ORIGINS["sinusoidal"])
    product = write_ortho(source, tmp_path / "out", gmljp2=True)
    kinds = [kind for kind, _, _ in jp2_boxes(product.jp2_path)]
    assert kinds == [b"jP  ", b"ftyp", b"jp2h", b"uuid", b"asoc", b"jp2c"]
    with rasterio.Env(GDAL_GEOREF_SOURCES="GMLJP2"), rasterio.open(product.jp2_path) as jp2:
        got = jp2.transform
    for a, b in zip(got[:6], transform[:6], strict=True):
        assert abs(a - b) <= 1e-6 * transform.a
    with rasterio.open(product.jp2_path) as jp2:  # default sources: GeoJP2 wins, CRS included
        assert _same_crs(jp2.crs, CRS.from_proj4(PROJECTIONS["sinusoidal"]))
        assert jp2.transform == transform


def test_crs_comparison_notices_a_different_standard_parallel():
    moved = PROJECTIONS["equirectangular"].replace("lat_ts=-5", "lat_ts=-4")
    assert not _same_crs(CRS.from_proj4(moved), CRS.from_proj4(PROJECTIONS["equirectangular"]))
