"""MAP-002/MAP-003 try the radius conventions genuine labels use, as they try offset
conventions: the projection's own radius, the equatorial one, the local radius of the
ellipsoid at CENTER_LATITUDE (ISIS's equirectangular maps of Mars), the mean radius.

Labels are built here with their MAP_RESOLUTION, offsets and bounds computed on one radius;
GDAL reads each one, as an independent check of what the offsets put where.
"""

from __future__ import annotations

import math
import warnings

import pytest
import rasterio
from rasterio.errors import NotGeoreferencedWarning

from pdsgen.validate import validate_paths

A_KM, C_KM = 3396.19, 3376.2  # the Mars ellipsoid as ISIS and the HiRISE/CTX labels state it
LINES, SAMPLES, SCALE = 200, 300, 100.0


def _local_km(lat: float) -> float:
    phi = math.radians(lat)
    return A_KM * C_KM / math.hypot(C_KM * math.cos(phi), A_KM * math.sin(phi))


def _write(tmp_path, projection: str, radius_km: float, center_lat: float, a_km=A_KM, c_km=C_KM):
    """An 8-bit product whose map arithmetic is on a sphere of `radius_km`."""
    r, lon0 = radius_km * 1000.0, 180.0
    top, west = center_lat + 1.0, 179.0
    y0 = r * math.radians(top)
    if projection == "EQUIRECTANGULAR":
        x0 = r * math.radians(west - lon0) * math.cos(math.radians(center_lat))
        east = lon0 + math.degrees((x0 + SAMPLES * SCALE) / (r * math.cos(math.radians(center_lat))))
    bottom = math.degrees((y0 - LINES * SCALE) / r)
    if projection == "SINUSOIDAL":  # west of the central meridian: bounds at the corners
        poleward, equatorward = sorted((top, bottom), key=abs, reverse=True)
        x0 = r * math.radians(west - lon0) * math.cos(math.radians(poleward))
        x1 = x0 + SAMPLES * SCALE
        corner = poleward if x1 > 0 else equatorward
        east = lon0 + math.degrees(x1 / (r * math.cos(math.radians(corner))))
    resolution = math.pi * r / 180.0 / SCALE
    label = "\r\n".join([
        "PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", f"RECORD_BYTES = {SAMPLES}",
        f"FILE_RECORDS = {LINES}", '^IMAGE = ("MAP.DAT", 1)',
        "OBJECT = IMAGE", f"  LINES = {LINES}", f"  LINE_SAMPLES = {SAMPLES}",
        "  SAMPLE_TYPE = UNSIGNED_INTEGER", "  SAMPLE_BITS = 8", "END_OBJECT = IMAGE",
        "OBJECT = IMAGE_MAP_PROJECTION", f'  MAP_PROJECTION_TYPE = "{projection}"',
        f"  A_AXIS_RADIUS = {a_km} <KM>", f"  B_AXIS_RADIUS = {a_km} <KM>", f"  C_AXIS_RADIUS = {c_km} <KM>",
        "  COORDINATE_SYSTEM_NAME = PLANETOCENTRIC", "  POSITIVE_LONGITUDE_DIRECTION = EAST",
        f"  CENTER_LATITUDE = {center_lat:.1f} <DEG>", f"  CENTER_LONGITUDE = {lon0:.1f} <DEG>",
        "  LINE_FIRST_PIXEL = 1", f"  LINE_LAST_PIXEL = {LINES}", "  SAMPLE_FIRST_PIXEL = 1",
        f"  SAMPLE_LAST_PIXEL = {SAMPLES}", "  MAP_PROJECTION_ROTATION = 0.0 <DEG>",
        f"  MAP_RESOLUTION = {resolution!r} <PIX/DEG>", f"  MAP_SCALE = {SCALE!r} <METERS/PIXEL>",
        f"  MAXIMUM_LATITUDE = {top!r} <DEG>", f"  MINIMUM_LATITUDE = {bottom!r} <DEG>",
        f"  LINE_PROJECTION_OFFSET = {y0 / SCALE - 0.5!r} <PIXEL>",
        f"  SAMPLE_PROJECTION_OFFSET = {-x0 / SCALE - 0.5!r} <PIXEL>",
        f"  EASTERNMOST_LONGITUDE = {east!r} <DEG>", f"  WESTERNMOST_LONGITUDE = {west!r} <DEG>",
        "END_OBJECT = IMAGE_MAP_PROJECTION", "END", ""])
    (tmp_path / "MAP.DAT").write_bytes(bytes(LINES * SAMPLES))
    path = tmp_path / "MAP.LBL"
    path.write_text(label, newline="")
    return path, (x0, y0)


def _map_findings(path):
    return {f.rule: f for f in validate_paths([path]).findings if f.rule.startswith("MAP")}


def test_equirectangular_on_the_local_radius_at_the_centre_latitude(tmp_path):
    path, (x0, y0) = _write(tmp_path, "EQUIRECTANGULAR", _local_km(30.0), 30.0)
    found = _map_findings(path)
    assert "MAP-003" not in found
    assert found["MAP-002"].severity == "warning"
    assert "local radius at CENTER_LATITUDE 30" in found["MAP-002"].message
    assert f"{_local_km(30.0):.6f} km" in found["MAP-002"].message
    assert "local radius at CENTER_LATITUDE 30" in found["MAP-004"].message  # offsets fit it too
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotGeoreferencedWarning)
        with rasterio.open(path) as dataset:  # GDAL: the offsets' metres, on the sphere of A
            assert dataset.transform.c == pytest.approx(x0) and dataset.transform.f == pytest.approx(y0)
            assert dataset.crs.to_dict()["R"] == pytest.approx(A_KM * 1000.0)


def test_local_radius_is_isis_value(tmp_path):
    """ISIS's scaled radius for Mars at 45 degrees is 3386150.74700337 m (USGS ISIS_contrib,
    ISIS_scaledRadiusEquirectangular_Mars/README.md); the validator names the same."""
    path, _ = _write(tmp_path, "EQUIRECTANGULAR", 3386.15074700337, 45.0)
    assert "= 3386.150747 km" in _map_findings(path)["MAP-002"].message


def test_sinusoidal_on_the_mean_radius(tmp_path):
    mean = (2 * A_KM + C_KM) / 3
    path, _ = _write(tmp_path, "SINUSOIDAL", mean, -20.0)
    found = _map_findings(path)
    assert found["MAP-002"].severity == "warning" and "mean radius" in found["MAP-002"].message
    assert "MAP-003" not in found and "mean radius" in found["MAP-004"].message


def test_the_projections_own_radius_is_not_named(tmp_path):
    path, _ = _write(tmp_path, "EQUIRECTANGULAR", A_KM, 30.0)
    found = _map_findings(path)
    assert "MAP-002" not in found and "MAP-003" not in found
    assert " on " not in found["MAP-004"].message


def test_a_sphere_has_one_radius_and_no_other_convention_rescues_a_wrong_one(tmp_path):
    path, _ = _write(tmp_path, "EQUIRECTANGULAR", 3390.0, 30.0, a_km=3396.0, c_km=3396.0)
    found = _map_findings(path)
    assert found["MAP-002"].severity == "error" and "other radius" not in found["MAP-002"].message
    assert found["MAP-003"].severity == "error"


def test_no_convention_fits_is_an_error_naming_what_was_tried(tmp_path):
    path, _ = _write(tmp_path, "EQUIRECTANGULAR", 3000.0, 30.0)
    found = _map_findings(path)
    assert found["MAP-002"].severity == "error"
    assert "local radius at CENTER_LATITUDE 30" in found["MAP-002"].message
    assert "mean radius" in found["MAP-002"].message and found["MAP-003"].severity == "error"
