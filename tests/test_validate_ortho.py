"""Orthoimages pdsgen writes (JP2 + detached label) validate clean, and one defect at a time
in them is reported with its rule id: GeoJP2 moved by a pixel, JP2 missing, label edits."""

from __future__ import annotations

import itertools
import struct
from pathlib import Path

import numpy as np
import pytest

from pdsgen import write_ortho
from pdsgen.validate import validate_paths
from pdsgen.validate.geojp2 import GEOJP2_UUID, read_jp2

from helpers import ORIGINS, stated_keywords, write_raster

VARIANTS = [(8, 1, "uint8"), (10, 1, "float32"), (16, 3, "uint16"), (10, 3, "uint16")]
CASES = [(kind, *variant, gml) for (kind, variant), gml in
         zip(itertools.product(ORIGINS, VARIANTS), itertools.cycle((False, True)), strict=False)]


def make_ortho(tmp_path: Path, kind: str = "equirectangular", bits: int = 10, bands: int = 1,
               dtype: str = "uint16", gmljp2: bool = False, shape=(45, 61)):
    rng = np.random.default_rng(bits + bands)
    data = rng.random((bands, *shape)) * (200 if dtype == "uint8" else 900) + 5
    data = (data / 1000 if dtype == "float32" else data).astype(dtype)
    crs, transform = ORIGINS[kind]
    source = write_raster(tmp_path / f"in_{kind}.tif", data if bands == 3 else data[0], crs, transform)
    return write_ortho(source, tmp_path / "out", bits=bits, gmljp2=gmljp2, params=stated_keywords())


@pytest.mark.parametrize(("kind", "bits", "bands", "dtype", "gml"), CASES)
def test_generated_orthos_are_clean(tmp_path, kind, bits, bands, dtype, gml):
    product = make_ortho(tmp_path, kind, bits, bands, dtype, gml)
    info = read_jp2(product.jp2_path)
    assert (info.bits, info.bands) == (bits, bands)
    assert {r.source for r in info.georefs} == ({"GeoJP2", "GMLJP2"} if gml else {"GeoJP2"})
    report = validate_paths([product.label_path], strict=True)
    assert [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"] == []


def move_geojp2(jp2: Path, pixels: float, pixel_size: float) -> None:
    """Shift the GeoJP2 tie point east by `pixels` (same bytes otherwise)."""
    data = bytearray(jp2.read_bytes())
    at = data.index(GEOJP2_UUID.bytes) + 16
    order = "<" if data[at:at + 2] == b"II" else ">"
    (ifd,) = struct.unpack_from(order + "I", data, at + 4)
    (count,) = struct.unpack_from(order + "H", data, at + ifd)
    for i in range(count):
        tag, _, n, offset = struct.unpack_from(order + "HHII", data, at + ifd + 2 + 12 * i)
        if tag == 33922:  # ModelTiepoint: i, j, k, x, y, z
            pos = at + offset + 3 * 8
            (x,) = struct.unpack_from(order + "d", data, pos)
            struct.pack_into(order + "d", data, pos, x + pixels * pixel_size)
    jp2.write_bytes(bytes(data))


def test_geojp2_moved_by_one_pixel_in_a_generated_product(tmp_path):
    product = make_ortho(tmp_path)
    move_geojp2(product.jp2_path, 1.0, product.geometry.map_scale)
    errors = {f.rule: f.message for f in validate_paths([product.label_path]).findings if f.severity == "error"}
    assert "GEO-004" in errors and "+1.0000 px (x)" in errors["GEO-004"]
    assert validate_paths([product.label_path]).exit_code == 1


def test_missing_jp2_of_a_generated_product(tmp_path):
    product = make_ortho(tmp_path)
    product.jp2_path.unlink()
    report = validate_paths([product.label_path])
    assert "GEO-001" in report.rule_ids("error") and report.exit_code == 1


def test_band_count_forgotten_in_uncompressed_records(tmp_path):
    product = make_ortho(tmp_path, bands=3)
    text = product.label_path.read_bytes()
    lines = product.geometry.lines
    product.label_path.write_bytes(text.replace(f"FILE_RECORDS = {3 * lines}\r".encode(),
                                                f"FILE_RECORDS = {lines}\r".encode()))
    assert {"REC-007", "REC-004"} <= validate_paths([product.label_path]).rule_ids("error")


def test_hirise_ortho_alone_is_clean_and_its_dtm_reference_is_checked_in_a_set(tmp_path):
    rng = np.random.default_rng(9)
    crs, transform = ORIGINS["equirectangular"]
    irb = (rng.random((3, 40, 50)) * 900 + 3).astype("uint16")
    source = write_raster(tmp_path / "irb.tif", irb, crs, transform)
    product = write_ortho(source, tmp_path / "out", profile="hirise", bits=10, sequence=41,
                          observation_id="ESP_042252_1930", source_dtm_id="DTEEC_042252_1930_042753_1930_U01",
                          params=stated_keywords("hirise"))
    assert product.label_path.name == "ESP_042252_1930_IRB_C_41_ORTHO.LBL"  # 1 m: scale letter C
    report = validate_paths([product.label_path.parent], strict=True)
    assert [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"] == []
    (product.label_path.parent / "extras").mkdir()  # now a delivery set: the DTM must be in it
    errors = validate_paths([product.label_path.parent]).findings
    assert any(f.rule == "SET-003" and "DTEEC_042252_1930_042753_1930_U01" in f.message for f in errors)
