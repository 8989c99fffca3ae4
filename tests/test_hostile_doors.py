"""Hostile inputs through doors the boundary suites do not name (round 3).

A small delivery pdsgen makes itself (a HiRISE DTM and orthoimage, PDS3 and PDS4 labels,
Extras, INDEX, MD5SUMS.TXT, inventories) is damaged file by file - bytes flipped, cut short,
numbers made huge, names climbing out of the tree, control and foreign characters, deep and
wide structures, XML entities - and handed to validate, migrate, review, extras and deliver
in-process through the command line's own entry point (click's runner: what a user sees, without
a process per example). Whatever the input, each answers with exit 0, 1 or 2; never a traceback;
a refusal is one line on stderr; the validator never says a check "could not run"; nothing is
written outside -o; and each run takes seconds, not minutes.

The references are the world's: the contract's exit statuses, the file system itself (what is
on disk outside -o), and GeoTIFF's own tag types for the GeoJP2 box. Fixed budgets,
derandomized, no example database; cases found are kept as @example regressions.
"""

from __future__ import annotations

import shutil
import struct
import time
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from pdsgen.cli import main
from pdsgen.formats.geojp2 import GEOJP2_UUID
from pdsgen.formats.jp2 import jp2_boxes
from pdsgen.validate import validate_paths

from helpers import demo_products

BUDGET = settings(max_examples=25, deadline=None, derandomize=True, database=None,
                  suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
SECONDS = 20.0  # a few-MB input answered in seconds; generous for two shared cores
ORTHO = "PSP_008669_1705_RED_C_01_ORTHO"


@pytest.fixture(scope="module")
def delivery(tmp_path_factory) -> Path:
    """A whole delivery of two small products, PDS3 and PDS4, made once for the module."""
    root = tmp_path_factory.mktemp("made")
    products = demo_products(root, width=48, height=64)
    outcome = CliRunner().invoke(main, ["deliver", str(products), "-o", str(root / "dlv"), "--volume-id",
                                        "MROHR_1001", "--label", "both", "--bundle-lid", "urn:nasa:pds:hostile"])
    assert outcome.exit_code == 0, outcome.output
    return root / "dlv"


def _run(args: list[str]):
    """ARGS through the command line in-process: (exit status, stdout, stderr), after checking the
    contract every command keeps whatever its input."""
    started = time.monotonic()
    outcome = CliRunner().invoke(main, [str(arg) for arg in args])
    took = time.monotonic() - started
    assert outcome.exception is None or isinstance(outcome.exception, SystemExit), (
        f"{args[0]}: {type(outcome.exception).__name__}: {outcome.exception}")
    assert outcome.exit_code in (0, 1, 2), (args[0], outcome.exit_code, outcome.output)
    if outcome.exit_code == 2:
        lines = [line for line in outcome.stderr.splitlines() if line.strip()]
        assert len(lines) == 1 and lines[0].startswith("pdsgen: "), outcome.stderr
    assert "could not run" not in outcome.output, outcome.output
    assert took < SECONDS, f"{args[0]} took {took:.1f} s"
    return outcome.exit_code, outcome.stdout, outcome.stderr


# -- a GeoJP2 box that is there but malformed (issue 48 left it as "no GeoJP2 box") ---------------

def _tiff(entries: list[tuple[int, int, int, bytes]]) -> bytes:
    """A little-endian classic TIFF of one directory: (tag, type, count, value bytes) each, a
    value over four bytes placed after the directory, as the TIFF 6.0 layout has it."""
    data_at = 8 + 2 + 12 * len(entries) + 4
    directory, values = struct.pack("<H", len(entries)), b""
    for tag, kind, count, raw in entries:
        if len(raw) <= 4:
            directory += struct.pack("<HHI", tag, kind, count) + raw.ljust(4, b"\0")
        else:
            directory += struct.pack("<HHII", tag, kind, count, data_at + len(values))
            values += raw
    return b"II*\0" + struct.pack("<I", 8) + directory + b"\0\0\0\0" + values


def _doubles(*values: float) -> bytes:
    return struct.pack(f"<{len(values)}d", *values)


def _shorts(*values: int) -> bytes:
    return struct.pack(f"<{len(values)}H", *values)


def _with_geotiff(delivery: Path, where: Path, geotiff: bytes) -> Path:
    """The delivery's orthoimage (its JP2, PDS3 and PDS4 labels) copied to WHERE, the JP2's GeoJP2
    box holding GEOTIFF instead of the one written."""
    where.mkdir(parents=True, exist_ok=True)
    source = delivery / "DATA" / f"{ORTHO}.JP2"
    data = source.read_bytes()
    for kind, offset, length in jp2_boxes(source):
        if kind == b"uuid" and data[offset + 8:offset + 24] == GEOJP2_UUID.bytes:
            payload = GEOJP2_UUID.bytes + geotiff
            data = data[:offset] + struct.pack(">I4s", 8 + len(payload), b"uuid") + payload + data[offset + length:]
    (where / source.name).write_bytes(data)
    for suffix in (".LBL", ".xml", ".img"):
        shutil.copy(delivery / "DATA" / f"{ORTHO}{suffix}", where / f"{ORTHO}{suffix}")
    return where


_SCALE = (33550, 12, 3, _doubles(1.0, 1.0, 0.0))
_TIE = (33922, 12, 6, _doubles(0, 0, 0, 6099776.0, -563110.0, 0))
MALFORMED = {
    "not a TIFF": (None, "cannot be read (not a TIFF)"),
    "no grid tags": ([], "has no ModelPixelScale"),
    "scale as text": ([(33550, 2, 8, b"1.0\x001.0\x00"), _TIE], "ModelPixelScale (33550) holds"),
    "scale of one SHORT": ([(33550, 3, 1, _shorts(1)), _TIE], "ModelPixelScale (33550) holds (1,)"),
    "scale NaN": ([(33550, 12, 3, _doubles(float("nan"), 1.0, 0.0)), _TIE], "ModelPixelScale (33550) holds (nan"),
    "tie point infinite": ([_SCALE, (33922, 12, 6, _doubles(0, 0, 0, float("inf"), 0, 0))], "ModelTiepoint"),
    "GeoKey past its doubles": ([_SCALE, _TIE, (34735, 3, 8, _shorts(1, 1, 0, 1, 3078, 34736, 1, 500)),
                                 (34736, 12, 1, _doubles(1.0))], "GeoKey 3078 lies past the end"),
    "standard parallel as text": ([_SCALE, _TIE, (34735, 3, 12, _shorts(1, 1, 0, 2, 3075, 0, 1, 17, 3078, 34737, 3, 0)),
                                   (34737, 2, 4, b"ab|\0")], "GeoKey 3078 holds 'ab'"),
    "projection code as text": ([_SCALE, _TIE, (34735, 3, 8, _shorts(1, 1, 0, 1, 3075, 34737, 3, 0)),
                                 (34737, 2, 4, b"ab|\0")], "GeoKey 3075 holds 'ab'"),
    "scale factor of two values": ([_SCALE, _TIE, (34735, 3, 8, _shorts(1, 1, 0, 1, 3092, 34736, 2, 0)),
                                    (34736, 12, 2, _doubles(0.0, 1.0))], "GeoKey 3092 holds (0.0, 1.0)"),
    "directory of doubles": ([_SCALE, _TIE, (34735, 12, 4, _doubles(1, 1, 0, 0))], "does not hold SHORT values"),
}


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_a_malformed_geojp2_box_is_a_finding_of_its_own(delivery, tmp_path, case):
    """Each malformed GeoJP2 box is GEO-007 (PDS3) and PDS4-040 (PDS4) saying what is wrong
    with it - not GEO-003's "no GeoJP2 box", not a check that could not run, never a pass."""
    entries, said = MALFORMED[case]
    where = _with_geotiff(delivery, tmp_path, b"XXXXXXXXXXXXXXXX" if entries is None else _tiff(entries))
    report = validate_paths([where / f"{ORTHO}.LBL", where / f"{ORTHO}.xml"], download_schemas=False)
    found = {(f.rule, f.message) for f in report.findings}
    assert not [m for _, m in found if "could not run" in m]
    assert not [m for _, m in found if "no GeoJP2" in m]
    assert [m for rule, m in found if rule == "GEO-007" and said in m and m.startswith(f"{ORTHO}.JP2: GeoJP2 box")]
    assert [m for rule, m in found if rule == "PDS4-040" and said in m]


def test_a_jp2_without_a_geojp2_box_is_still_geo_003(tmp_path):
    """The finding of a box that is absent is unchanged (GEO-003 warning), and GEO-007 says
    nothing of a box that is not there."""
    from pdsgen.formats.jp2 import box
    from test_validate_geo import write_label

    jp2 = tmp_path / "G.JP2"
    ihdr = box(b"ihdr", struct.pack(">IIHBBBB", 48, 64, 1, 9, 7, 0, 0))
    jp2.write_bytes(box(b"jP  ", b"\r\n\x87\n") + box(b"ftyp", b"jp2 \0\0\0\0jp2 ") + box(b"jp2h", ihdr)
                    + box(b"jp2c", b"\xff\x4f\xff\xd9"))
    label = write_label(tmp_path / "G.LBL", "G.JP2")
    rules = {f.rule for f in validate_paths([label]).findings}
    assert "GEO-003" in rules and "GEO-007" not in rules


_TAGS = st.sampled_from([33550, 33922, 34735, 34736, 34737, 34264, 256])
_TYPES = st.sampled_from([1, 2, 3, 4, 5, 11, 12, 16])


@BUDGET
@given(entries=st.lists(st.tuples(_TAGS, _TYPES, st.integers(0, 12), st.binary(max_size=96)), max_size=5))
@example(entries=[(33550, 5, 3, struct.pack("<6I", 1, 0, 1, 0, 0, 0)), _TIE])
@example(entries=[_SCALE, _TIE, (34735, 3, 4, _shorts(1, 1, 0, 65535))])
def test_any_geojp2_box_is_read_or_a_finding(delivery, tmp_path_factory, entries):
    """Whatever GeoTIFF a GeoJP2 box holds, the GEO checks and PDS4-040 run to the end: a
    value, or GEO-007 / PDS4-040 naming the box, never a check that could not run."""
    where = _with_geotiff(delivery, tmp_path_factory.mktemp("geo"),
                          _tiff([(tag, kind, count, raw) for tag, kind, count, raw in entries]))
    report = validate_paths([where / f"{ORTHO}.LBL", where / f"{ORTHO}.xml"], download_schemas=False)
    assert not [f.message for f in report.findings if "could not run" in f.message]
