"""GEO rules on JPEG 2000 products: JP2 written by GDAL's JP2OpenJPEG driver (GeoJP2 box),
detached label written here from the geometry pdsgen's own writer computes."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest
import rasterio
from affine import Affine

from pdsgen.geo.geometry import describe_geometry
from pdsgen.label.values import format_real
from pdsgen.validate import validate_paths
from pdsgen.validate.geojp2 import GEOJP2_UUID, read_jp2

from helpers import CRS_EQUIRECTANGULAR

TRANSFORM = Affine(0.5, 0, 6123456.0, 0, -0.5, -563210.0)
LINES, SAMPLES = 48, 64


def write_jp2(path: Path, transform: Affine = TRANSFORM, lines: int = LINES, samples: int = SAMPLES) -> Path:
    data = (np.arange(lines * samples).reshape(lines, samples) % 1000 + 3).astype("uint16")
    with rasterio.open(path, "w", driver="JP2OpenJPEG", width=samples, height=lines, count=1,
                       dtype="uint16", crs=CRS_EQUIRECTANGULAR, transform=transform, NBITS=10,
                       QUALITY=100, REVERSIBLE="YES") as ds:
        ds.write(data, 1)
    return path


def write_label(path: Path, jp2_name: str, lines: int = LINES, samples: int = SAMPLES,
                storage: int | None = None) -> Path:
    g = describe_geometry(rasterio.crs.CRS.from_string(CRS_EQUIRECTANGULAR), TRANSFORM, SAMPLES, LINES)
    img_name = jp2_name.rsplit(".", 1)[0] + ".IMG"
    record_bytes = samples * 2
    storage = record_bytes * lines if storage is None else storage
    text = f"""PDS_VERSION_ID = PDS3
PRODUCT_ID = "{jp2_name.rsplit('.', 1)[0]}"
TARGET_NAME = MARS
OBJECT = IMAGE_MAP_PROJECTION
  MAP_PROJECTION_TYPE = "{g.projection_type}"
  A_AXIS_RADIUS = {format_real(g.a_axis_km)} <KM>
  B_AXIS_RADIUS = {format_real(g.b_axis_km)} <KM>
  C_AXIS_RADIUS = {format_real(g.c_axis_km)} <KM>
  COORDINATE_SYSTEM_NAME = PLANETOCENTRIC
  POSITIVE_LONGITUDE_DIRECTION = EAST
  CENTER_LATITUDE = {format_real(g.center_latitude)} <DEG>
  CENTER_LONGITUDE = {format_real(g.center_longitude)} <DEG>
  LINE_FIRST_PIXEL = 1
  LINE_LAST_PIXEL = {lines}
  SAMPLE_FIRST_PIXEL = 1
  SAMPLE_LAST_PIXEL = {samples}
  MAP_PROJECTION_ROTATION = 0.0 <DEG>
  MAP_RESOLUTION = {format_real(g.map_resolution)} <PIX/DEG>
  MAP_SCALE = {format_real(g.map_scale)} <METERS/PIXEL>
  MAXIMUM_LATITUDE = {format_real(g.maximum_latitude)} <DEG>
  MINIMUM_LATITUDE = {format_real(g.minimum_latitude)} <DEG>
  LINE_PROJECTION_OFFSET = {format_real(g.line_projection_offset)} <PIXEL>
  SAMPLE_PROJECTION_OFFSET = {format_real(g.sample_projection_offset)} <PIXEL>
  EASTERNMOST_LONGITUDE = {format_real(g.easternmost_longitude)} <DEG>
  WESTERNMOST_LONGITUDE = {format_real(g.westernmost_longitude)} <DEG>
END_OBJECT = IMAGE_MAP_PROJECTION
OBJECT = COMPRESSED_FILE
  FILE_NAME = "{jp2_name}"
  RECORD_TYPE = UNDEFINED
  ENCODING_TYPE = "JP2"
  ENCODING_TYPE_VERSION_NAME = "ISO/IEC15444-1:2004"
  INTERCHANGE_FORMAT = BINARY
  UNCOMPRESSED_FILE_NAME = "{img_name}"
  REQUIRED_STORAGE_BYTES = {storage} <BYTES>
END_OBJECT = COMPRESSED_FILE
OBJECT = UNCOMPRESSED_FILE
  FILE_NAME = "{img_name}"
  RECORD_TYPE = FIXED_LENGTH
  RECORD_BYTES = {record_bytes} <BYTES>
  FILE_RECORDS = {lines}
  ^IMAGE = "{img_name}"
  OBJECT = IMAGE
    LINES = {lines}
    LINE_SAMPLES = {samples}
    BANDS = 1
    SAMPLE_TYPE = MSB_UNSIGNED_INTEGER
    SAMPLE_BITS = 16
    SAMPLE_BIT_MASK = 2#0000001111111111#
    SCALING_FACTOR = 1.0
    OFFSET = 0.0
    BAND_STORAGE_TYPE = BAND_SEQUENTIAL
  END_OBJECT = IMAGE
END_OBJECT = UNCOMPRESSED_FILE
END
"""
    path.write_bytes(text.replace("\n", "\r\n").encode("ascii"))
    return path


def _product(tmp_path: Path, transform: Affine = TRANSFORM) -> Path:
    write_jp2(tmp_path / "ORTHO_TEST.JP2", transform)
    return write_label(tmp_path / "ORTHO_TEST.LBL", "ORTHO_TEST.JP2")


def _errors(path: Path) -> dict[str, str]:
    return {f.rule: f.message for f in validate_paths([path]).findings if f.severity == "error"}


def test_clean_jp2_product_has_no_problems(tmp_path):
    label = _product(tmp_path)
    info = read_jp2(tmp_path / "ORTHO_TEST.JP2")
    assert (info.height, info.width, info.bands, info.bits) == (LINES, SAMPLES, 1, 10)
    assert [ref.source for ref in info.georefs] == ["GeoJP2"]
    report = validate_paths([label], strict=True)
    assert [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"] == []


def test_geojp2_moved_by_one_pixel(tmp_path):
    moved = TRANSFORM @ Affine.translation(1, 0)
    label = _product(tmp_path, moved)
    errors = _errors(label)
    assert "GEO-004" in errors
    assert "+1.0000 px (x)" in errors["GEO-004"]
    assert validate_paths([label]).exit_code == 1


def test_missing_jp2(tmp_path):
    label = write_label(tmp_path / "ORTHO_TEST.LBL", "ORTHO_TEST.JP2")
    assert "GEO-001" in _errors(label)


def test_not_a_jp2(tmp_path):
    (tmp_path / "ORTHO_TEST.JP2").write_bytes(b"\x00" * 100)
    label = write_label(tmp_path / "ORTHO_TEST.LBL", "ORTHO_TEST.JP2")
    assert "GEO-001" in _errors(label)


def test_header_disagreeing_with_label(tmp_path):
    write_jp2(tmp_path / "ORTHO_TEST.JP2")
    label = write_label(tmp_path / "ORTHO_TEST.LBL", "ORTHO_TEST.JP2", lines=LINES + 2)
    assert "GEO-002" in _errors(label)


def test_required_storage_bytes(tmp_path):
    write_jp2(tmp_path / "ORTHO_TEST.JP2")
    label = write_label(tmp_path / "ORTHO_TEST.LBL", "ORTHO_TEST.JP2", storage=SAMPLES * LINES)
    assert "REC-004" in _errors(label)


def _patch_geokeys(path: Path, renames: dict[int, int]) -> None:
    """Rename GeoKey ids inside the GeoJP2 box's TIFF (same length, same values)."""
    data = bytearray(path.read_bytes())
    at = data.index(GEOJP2_UUID.bytes) + 16
    tiff = bytes(data[at:])
    order = "<" if tiff[:2] == b"II" else ">"
    (ifd,) = struct.unpack_from(order + "I", tiff, 4)
    (count,) = struct.unpack_from(order + "H", tiff, ifd)
    for i in range(count):
        tag, typ, n, offset = struct.unpack_from(order + "HHII", tiff, ifd + 2 + 12 * i)
        if tag == 34735:
            for k in range(4, n, 4):
                pos = at + offset + 2 * k
                (key,) = struct.unpack_from(order + "H", data, pos)
                if key in renames:
                    struct.pack_into(order + "H", data, pos, renames[key])
    path.write_bytes(bytes(data))


def test_standard_parallel_in_center_latitude_key(tmp_path):
    label = _product(tmp_path)
    jp2 = tmp_path / "ORTHO_TEST.JP2"
    assert read_jp2(jp2).georefs[0].keys[3078] == pytest.approx(-5.0)
    _patch_geokeys(jp2, {3089: 3090, 3078: 3089})  # the HiRISE writer's defect (GDAL #2706)
    keys = read_jp2(jp2).georefs[0].keys
    assert 3078 not in keys and keys[3089] == pytest.approx(-5.0)
    assert "GEO-006" in _errors(label)


def test_central_meridian_disagreeing(tmp_path):
    label = _product(tmp_path)
    text = label.read_bytes().replace(b"CENTER_LONGITUDE = 180.0", b"CENTER_LONGITUDE = 170.0")
    label.write_bytes(text)
    errors = _errors(label)
    assert "GEO-005" in errors and "central meridian" in errors["GEO-005"]
