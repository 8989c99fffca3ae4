"""HRSC-AX orthoimages: panchromatic, RGB and CIR channel files (VICAR, BYTE) to lossless JP2 +
.LBL, read back by GDAL (JP2OpenJPEG and the PDS label) and glymur."""

from __future__ import annotations

from pathlib import Path

import glymur
import numpy as np
import pvl
import pytest
import rasterio
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen import write_ortho
from pdsgen.validate import validate_paths

from helpers import run_cli
from hrsc_ax_tiles import GEODETIC, UTM33_HRSCAX, grid_corner_positions, map_group, tile_name, write_vicar

EAST, NORTH, PIXEL = 430000.0, 8765000.0, 0.2
LINES, SAMPLES = 200, 260


def _channel(seed: int, lines: int = LINES, samples: int = SAMPLES, dtype=np.uint8) -> np.ndarray:
    data = np.random.default_rng(seed).integers(1, 256, (lines, samples)).astype(dtype)
    data[:3, :5] = 0  # no data in a corner
    return data


def _tile(tmp_path: Path, extensions: tuple[str, ...], **changes) -> list[Path]:
    name = tile_name(430, 8765, 1000, PIXEL)
    paths = []
    for seed, extension in enumerate(extensions):
        data = _channel(seed, **changes.get(extension, {}))
        group = map_group(EAST, NORTH, PIXEL) if extension not in changes.get("other_grid", ()) \
            else map_group(EAST + 200.0, NORTH, PIXEL)
        paths.append(write_vicar(tmp_path / f"{name}.{extension}", data, {"MAP": group}))
    return paths


@pytest.mark.parametrize("extensions, kind, names", [
    (("pan",), "PAN", "PANCHROMATIC"),
    (("re", "gr", "bl"), "RGB", ["RED", "GREEN", "BLUE"]),
    (("cir_re", "cir_gr", "cir_bl"), "CIR", ["NEAR-INFRARED", "RED", "GREEN"]),
])
def test_dns_exact_bands_in_order_and_ground_positions(tmp_path, extensions, kind, names):
    paths = _tile(tmp_path, extensions)
    product = write_ortho(paths if len(paths) > 1 else paths[0], tmp_path / "out", profile="hrsc-ax")
    assert product.product_id == f"HRSCAX_430_8765_0_2X0_2KM_{kind}"
    expected = np.stack([_channel(seed) for seed in range(len(extensions))])
    with rasterio.open(product.jp2_path) as ds:
        assert ds.count == len(extensions)
        np.testing.assert_array_equal(ds.read(), expected)  # GDAL's JPEG 2000 reader, band by band
        pixels, lon, lat = grid_corner_positions(EAST, NORTH, PIXEL, LINES, SAMPLES)
        xs, ys = zip(*(ds.transform @ (s + 0.5, r + 0.5) for r, s in pixels), strict=True)
        glon, glat = warp_transform(ds.crs, CRS.from_proj4(GEODETIC), list(xs), list(ys))
    decoded = glymur.Jp2k(str(product.jp2_path))[:]
    np.testing.assert_array_equal(decoded if decoded.ndim == 2 else np.moveaxis(decoded, 2, 0), expected.squeeze())
    utm = CRS.from_proj4(UTM33_HRSCAX)
    ex, ey = warp_transform(CRS.from_proj4(GEODETIC), utm, list(lon), list(lat))
    gx, gy = warp_transform(CRS.from_proj4(GEODETIC), utm, list(glon), list(glat))
    assert np.hypot(np.subtract(gx, ex), np.subtract(gy, ey)).max() < 0.01
    label = pvl.load(str(product.label_path))
    image = label["UNCOMPRESSED_FILE"]["IMAGE"]
    assert image["FILTER_NAME"] == names
    assert label["TARGET_NAME"] == "EARTH" and label["INSTRUMENT_ID"] == "HRSC-AX"
    # The label read by GDAL's PDS driver places the image where the JP2's GeoJP2 box does.
    with rasterio.open(product.label_path) as lbl, rasterio.open(product.jp2_path) as jp2:
        for r, s in pixels:
            lx, ly = lbl.transform @ (s + 0.5, r + 0.5)
            jx, jy = jp2.transform @ (s + 0.5, r + 0.5)
            (llon,), (llat,) = warp_transform(lbl.crs, CRS.from_proj4(GEODETIC), [lx], [ly])
            (jlon,), (jlat,) = warp_transform(jp2.crs, CRS.from_proj4(GEODETIC), [jx], [jy])
            assert abs(llon - jlon) * 1.2e5 * np.cos(np.radians(llat)) < 0.01 and abs(llat - jlat) * 1.2e5 < 0.01
    report = validate_paths([product.label_path])
    assert not [f for f in report.findings if f.severity == "error"]


def test_cli_composes_the_rgb_in_the_order_given(tmp_path):
    paths = _tile(tmp_path, ("re", "gr", "bl"))
    result = run_cli("ortho", *paths, "--profile", "hrsc-ax", "-o", tmp_path / "out")
    assert result.returncode == 0, result.stderr
    with rasterio.open(tmp_path / "out" / "HRSCAX_430_8765_0_2X0_2KM_RGB.JP2") as ds:
        np.testing.assert_array_equal(ds.read(3), _channel(2))


@pytest.mark.parametrize("changes, extensions, message", [
    ({"gr": {"lines": LINES - 1}}, ("re", "gr", "bl"), "not channels of one tile"),
    ({"bl": {"dtype": np.int16}}, ("re", "gr", "bl"), "not channels of one tile"),
    ({"other_grid": ("gr",)}, ("re", "gr", "bl"), "another map grid"),
    ({}, ("gr", "re", "bl"), "in the order TILE.re TILE.gr TILE.bl"),
    ({}, ("re", "cir_gr", "bl"), "HRSC-AX products are one .dsm"),
])
def test_inputs_of_different_grids_sizes_types_refused_in_one_line(tmp_path, changes, extensions, message):
    paths = _tile(tmp_path, extensions, **changes)
    result = run_cli("ortho", *paths, "--profile", "hrsc-ax", "-o", tmp_path / "out")
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], result.stderr
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


def test_other_profiles_take_one_input(tmp_path):
    paths = _tile(tmp_path, ("re", "gr"))
    result = run_cli("ortho", *paths, "-o", tmp_path / "out")
    assert result.returncode == 2 and "takes one INPUT; 2 were given" in result.stderr


def test_threads_cap_reaches_the_encoder(tmp_path, monkeypatch):
    """A batch's share of cores (threads=N) reaches the JPEG 2000 encoder for HRSC-AX too."""
    import pdsgen.products.ortho as ortho

    seen = []
    real = ortho.write_jp2

    def spy(*args, threads=None, **kwargs):
        seen.append(threads)
        return real(*args, threads=threads, **kwargs)

    monkeypatch.setattr(ortho, "write_jp2", spy)
    write_ortho(_tile(tmp_path, ("pan",))[0], tmp_path / "out", profile="hrsc-ax", threads=1)
    assert seen == [1]
