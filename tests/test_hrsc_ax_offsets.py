"""Where HRSC-AX products land, against references outside pdsgen.

The tiles' MAP offsets are written by the tests' own writer as the HRSC-AX image
description defines them (Table B2: from the centre of pixel 1,1). Two references:

- SCALE_FACTOR 1: GDAL's VICAR reader, which reads the MAP group that way (and ignores
  only SCALE_FACTOR, so with 1 its reading is exact). The product, read by GDAL through
  rasterio and through the installed `gdalinfo`, must put the corner and centre pixels
  within 1 cm of where GDAL puts them in the tile.
- SCALE_FACTOR 0.9996: PROJ (rasterio.warp) computing the grid straight from the header
  numbers by Table B2, the pixel centres as longitude/latitude.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pvl
import pytest
import rasterio
from affine import Affine
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen import write_dtm, write_ortho
from pdsgen.errors import ParamsError

from helpers import run_cli
from hrsc_ax_tiles import A_KM, C_KM, GEODETIC, LON0, dtm_group, map_group, tile_name, write_vicar

EAST, NORTH = 430000.0, 8765000.0
LINES, SAMPLES = 30, 44
PIXELS = [(0, 0), (0, SAMPLES - 1), (LINES - 1, 0), (LINES - 1, SAMPLES - 1), (LINES // 2, SAMPLES // 2)]
KINDS = {"DEM": ("dsm",), "PAN": ("pan",), "RGB": ("re", "gr", "bl")}
PIXEL_M = {"DEM": 0.5, "PAN": 0.2, "RGB": 0.2}
LOCAL = CRS.from_proj4(f"+proj=aeqd +lat_0=78.94 +lon_0=11.73 +a={A_KM * 1000} +b={C_KM * 1000} +units=m +no_defs")


def _tiles(tmp_path: Path, kind: str, scale_factor: float, counting: str = "table_b2") -> tuple[list[Path], dict]:
    pixel = PIXEL_M[kind]
    group = map_group(EAST, NORTH, pixel, scale_factor=scale_factor, counting=counting)
    name = tile_name(430, 8765, LINES, pixel)
    rng = np.random.default_rng(7)
    paths = []
    for extension in KINDS[kind]:
        if kind == "DEM":
            data = rng.uniform(0, 100, (LINES, SAMPLES)).astype(np.float32)
            groups = {"MAP": group, "DIGITAL_TERRAIN_MODEL": dtm_group(0.0, 1.0, -500, 2000)}
        else:
            data = rng.integers(1, 256, (LINES, SAMPLES)).astype(np.uint8)
            groups = {"MAP": group}
        paths.append(write_vicar(tmp_path / f"{name}.{extension}", data, groups))
    return paths, group


def _make(paths: list[Path], kind: str, outdir: Path, dialect: str, **options):
    """The product and the files GDAL opens it by (PDS3 label, JP2, PDS4 label)."""
    if kind == "DEM":
        product = write_dtm(paths[0], outdir, profile="hrsc-ax", label=dialect, **options)
        opened = [product.pds4_label_path] if dialect == "pds4" else [product.path]
    else:
        product = write_ortho(paths if len(paths) > 1 else paths[0], outdir, profile="hrsc-ax", label=dialect,
                              **options)
        opened = [product.pds4_label_path, product.jp2_path] if dialect == "pds4" else \
            [product.label_path, product.jp2_path]
    return product, opened


def _ground_m(crs: CRS, transform: Affine) -> np.ndarray:
    """The corner and centre pixels' centres as metres of a local tangent grid on the ellipsoid."""
    xs, ys = zip(*(transform @ (s + 0.5, r + 0.5) for r, s in PIXELS), strict=True)
    lon, lat = warp_transform(crs, CRS.from_proj4(GEODETIC), list(xs), list(ys))
    return _local(lon, lat)


def _local(lon, lat) -> np.ndarray:
    x, y = warp_transform(CRS.from_proj4(GEODETIC), LOCAL, list(lon), list(lat))
    return np.column_stack([x, y])


def _gdal_readings(path: Path) -> list[tuple[CRS, Affine]]:
    """(CRS, geotransform) of `path` as GDAL reads it: through rasterio, and through `gdalinfo`."""
    with rasterio.open(path) as ds:
        readings = [(ds.crs, ds.transform)]
    if shutil.which("gdalinfo"):
        info = json.loads(subprocess.run(["gdalinfo", "-json", str(path)], capture_output=True, text=True,
                                         check=True, timeout=60).stdout)
        readings.append((CRS.from_wkt(info["coordinateSystem"]["wkt"]), Affine.from_gdal(*info["geoTransform"])))
    return readings


def _header_grid_positions(group: dict) -> np.ndarray:
    """The corner and centre pixels as the header defines them (Table B2), placed by PROJ."""
    scale = group["MAP_SCALE"] * 1000.0
    ulx = -(group["SAMPLE_PROJECTION_OFFSET"] + 0.5) * scale  # the origin, from pixel (1, 1)'s centre
    uly = (group["LINE_PROJECTION_OFFSET"] + 0.5) * scale
    tmerc = CRS.from_proj4(f"+proj=tmerc +lat_0={group['CENTER_LATITUDE']} +lon_0={group['CENTER_LONGITUDE']} "
                           f"+k={group['SCALE_FACTOR']} +x_0=0 +y_0=0 +a={group['A_AXIS_RADIUS'] * 1000} "
                           f"+b={group['C_AXIS_RADIUS'] * 1000} +units=m +no_defs")
    return _ground_m(tmerc, Affine(scale, 0.0, ulx, 0.0, -scale, uly))


CASES = [("DEM", "pds3"), ("DEM", "pds4"), ("PAN", "pds3"), ("RGB", "pds3"), ("RGB", "pds4")]


@pytest.mark.parametrize("kind, dialect", CASES)
def test_scale_factor_1_product_lands_where_gdal_reads_the_tile(tmp_path, kind, dialect):
    paths, _ = _tiles(tmp_path, kind, 1.0)
    with rasterio.open(paths[0]) as tile:
        assert tile.driver == "VICAR"
        expected = _ground_m(tile.crs, tile.transform)
    _, opened = _make(paths, kind, tmp_path / "out", dialect)
    for path in opened:
        for crs, transform in _gdal_readings(path):
            errors = np.hypot(*(_ground_m(crs, transform) - expected).T)
            assert errors.max() < 0.01, f"{path.name}: {errors.round(3)} m from GDAL's reading of the tile"


@pytest.mark.parametrize("kind, dialect", CASES)
def test_utm_scale_factor_product_lands_where_the_header_puts_the_tile(tmp_path, kind, dialect):
    paths, group = _tiles(tmp_path, kind, 0.9996)
    assert group["CENTER_LONGITUDE"] == LON0
    expected = _header_grid_positions(group)
    _, opened = _make(paths, kind, tmp_path / "out", dialect)
    for path in opened:
        for crs, transform in _gdal_readings(path):
            errors = np.hypot(*(_ground_m(crs, transform) - expected).T)
            assert errors.max() < 0.01, f"{path.name}: {errors.round(3)} m from the header's grid"


def test_gdal_vicar_reader_follows_table_b2_for_the_independent_writer(tmp_path):
    """The tests' writer and GDAL agree on the definition: the tile's upper-left corner opens
    exactly at its grid position (natural origin: no false easting with scale factor 1)."""
    paths, _ = _tiles(tmp_path, "PAN", 1.0)
    with rasterio.open(paths[0]) as tile:
        assert tile.transform.c == pytest.approx(EAST - 500000.0, abs=1e-6)
        assert tile.transform.f == pytest.approx(NORTH, abs=1e-6)


@pytest.mark.parametrize("kind", ["DEM", "RGB"])
def test_dlr_counting_is_an_explicit_choice_stated_in_the_label(tmp_path, kind):
    """Tiles whose offsets count one pixel further (DLR's Mars practice) land right only when
    the producer says so; the label's comment says how the offsets were read."""
    paths, group = _tiles(tmp_path, kind, 0.9996, counting="dlr")
    standard_group = map_group(EAST, NORTH, PIXEL_M[kind], scale_factor=0.9996)
    expected = _header_grid_positions(standard_group)
    command = "dtm" if kind == "DEM" else "ortho"
    result = run_cli(command, *paths, "-o", tmp_path / "dlr", "--profile", "hrsc-ax", "--vicar-offsets", "dlr")
    assert result.returncode == 0, result.stderr
    default, _ = _make(paths, kind, tmp_path / "default", "pds3")
    made = sorted((tmp_path / "dlr").glob("*.IMG" if kind == "DEM" else "*.LBL"))
    assert len(made) == 1
    with rasterio.open(made[0]) as ds:
        assert np.hypot(*(_ground_m(ds.crs, ds.transform) - expected).T).max() < 0.01
    default_label = default.path if kind == "DEM" else default.label_path
    with rasterio.open(default_label) as ds:  # read by Table B2, the same header is one pixel off
        off = np.hypot(*(_ground_m(ds.crs, ds.transform) - expected).T)
        assert off.min() > 0.9 * PIXEL_M[kind] * np.sqrt(2)
    text = made[0].read_bytes()[:60000].decode("ascii", "replace")
    assert "DLR's HRSC Mars counting" in " ".join(text.split())
    default_text = " ".join(default_label.read_bytes()[:60000].decode("ascii", "replace").split())
    assert "(Table B2)" in default_text and "centre of pixel 1,1" in default_text
    pvl.load(str(made[0]))  # the comment keeps the label readable


def test_unknown_counting_refused_in_one_line(tmp_path):
    paths, _ = _tiles(tmp_path, "DEM", 0.9996)
    with pytest.raises(ParamsError, match="vicar_offsets"):
        write_dtm(paths[0], tmp_path / "out", profile="hrsc-ax", vicar_offsets="mars")
    result = run_cli("dtm", paths[0], "-o", tmp_path / "cli", "--profile", "generic", "--vicar-offsets", "dlr")
    assert result.returncode == 2 and "--vicar-offsets does not apply to --profile generic" in result.stderr
