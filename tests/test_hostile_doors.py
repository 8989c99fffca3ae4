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

import os
import re
import shutil
import signal
import struct
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from pdsgen.cli import main
from pdsgen.formats.geojp2 import GEOJP2_UUID
from pdsgen.formats.jp2 import jp2_boxes
from pdsgen.validate import validate_paths

from helpers import demo_products, run_cli

BUDGET = settings(max_examples=25, deadline=None, derandomize=True, database=None,
                  suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
SECONDS = 15.0  # a few-MB input answered in seconds; generous for two shared cores
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


class Stuck(BaseException):
    """A command still running at its deadline: a BaseException, so that no `except Exception`
    of the command (a check that 'could not run') swallows it and waits on."""


@contextmanager
def _deadline(seconds: float) -> Iterator[None]:
    """A command that would wait for ever (a FIFO opened) is stopped by SIGALRM after SECONDS
    and the test fails with Stuck, rather than the suite hanging."""
    def stop(signum, frame):  # noqa: ANN001 - signal's handler signature
        raise Stuck(f"still running after {seconds:.0f} s")

    previous = signal.signal(signal.SIGALRM, stop)
    signal.alarm(int(seconds))
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _run(args: list[str], seconds: float = SECONDS):
    """ARGS through the command line in-process: (exit status, stdout, stderr), after checking the
    contract every command keeps whatever its input."""
    started = time.monotonic()
    with _deadline(seconds):
        outcome = CliRunner().invoke(main, [str(arg) for arg in args])
    took = time.monotonic() - started
    assert outcome.exception is None or isinstance(outcome.exception, SystemExit), (
        f"{args[0]}: {type(outcome.exception).__name__}: {outcome.exception}")
    assert outcome.exit_code in (0, 1, 2), (args[0], outcome.exit_code, outcome.output)
    if outcome.exit_code == 2:
        # one line per refusal; migrate refuses a product in one line per obstacle (all that stands
        # in its way at once), at most Refused.SHOWN and a count; warnings of other files before it
        lines = [line for line in outcome.stderr.splitlines() if line.strip()]
        refusals = [line for line in lines if line.startswith("pdsgen: ")]
        assert refusals and all(line.startswith(("pdsgen: ", "warning: ")) for line in lines), outcome.stderr
        assert len(refusals) == 1 or (args[0] == "migrate" and len(refusals) <= 2 + 20), outcome.stderr
    assert "could not run" not in outcome.output, outcome.output
    assert took < seconds, f"{args[0]} took {took:.1f} s"
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


# -- numbers a label states, as large, small or odd as text can make them ---------------------------

_HUGE = st.sampled_from(["0", "-5", "4294967297", "999999999999", "99999999999999999999", "1" * 99])
_DTM = "DTEEC_008669_1705_009025_1705_U01"


def _restated(path: Path, key: str, value: str) -> Path:
    """PATH with the first `KEY = number` statement stating VALUE instead."""
    data = path.read_bytes()
    changed = re.sub(rb"(\n *" + key.encode() + rb" *= *)\d+", rb"\g<1>" + value.encode(), data, count=1)
    assert changed != data, key
    path.write_bytes(changed)
    return path


def _no_check_failed(paths: list[Path]) -> list:
    report = validate_paths(paths, download_schemas=False)
    assert not [f"{f.rule}: {f.message}" for f in report.findings if "could not run" in f.message]
    return report.findings


@BUDGET
@given(key=st.sampled_from(["RECORD_BYTES", "FILE_RECORDS", "LABEL_RECORDS", "LINES", "LINE_SAMPLES",
                            "SAMPLE_BITS", "BANDS"]), value=_HUGE)
@example(key="RECORD_BYTES", value="999999999999")  # the END-to-data gap read whole: MemoryError
@example(key="RECORD_BYTES", value="0")  # REC-008 divided by it
@example(key="LINE_SAMPLES", value="999999999999")  # a block buffer of a terabyte
@example(key="SAMPLE_BITS", value="999999999999")  # 1 << SAMPLE_BITS
@example(key="SAMPLE_BITS", value="-5")
def test_a_pds3_label_stating_any_number_is_checked_to_the_end(delivery, tmp_path_factory, key, value):
    """The DTM (label attached to its data) and the orthoimage's detached label, each stating
    a count of any size: every check runs to a finding, none allocates what the label claims."""
    where = tmp_path_factory.mktemp("numbers")
    dtm = shutil.copy(delivery / "DATA" / f"{_DTM}.IMG", where / f"{_DTM}.IMG")
    for suffix in (".LBL", ".JP2", ".img"):
        shutil.copy(delivery / "DATA" / f"{ORTHO}{suffix}", where / f"{ORTHO}{suffix}")
    started = time.monotonic()
    _no_check_failed([_restated(Path(dtm), key, value), _restated(where / f"{ORTHO}.LBL", key, value)
                      if key != "LABEL_RECORDS" else where / f"{ORTHO}.LBL"])
    assert time.monotonic() - started < SECONDS


_PDS4_NUMBERS = st.sampled_from(["99999999999999999999", "-5", "1e400", "0", "1" * 99])


@BUDGET
@given(tag=st.sampled_from(["offset", "elements", "records", "record_length", "fields", "file_size"]),
       value=_PDS4_NUMBERS, which=st.sampled_from([f"{ORTHO}.xml", f"{_DTM}.xml", "collection_data.xml"]))
@example(tag="offset", value="99999999999999999999", which="collection_data.xml")  # could not be sought
@example(tag="offset", value="-5", which="collection_data.xml")
@example(tag="elements", value="1e400", which=f"{ORTHO}.xml")  # int(inf)
def test_a_pds4_label_stating_any_number_is_checked_to_the_end(delivery, tmp_path_factory, tag, value, which):
    where = tmp_path_factory.mktemp("pds4numbers")
    for name in (f"{ORTHO}.xml", f"{ORTHO}.img", f"{ORTHO}.JP2", f"{_DTM}.xml", f"{_DTM}.IMG",
                 "collection_data.xml", "collection_data_inventory.csv"):
        shutil.copy(delivery / "DATA" / name, where / name)
    label = where / which
    data = label.read_bytes()
    label.write_bytes(re.sub(rb"(<" + tag.encode() + rb"(?:\s[^>]*)?>)[^<]*", lambda m: m.group(1) + value.encode(),
                             data, count=1))
    _no_check_failed([label])


def test_a_pds4_file_name_no_file_system_holds_is_not_found(delivery, tmp_path):
    """A file_name of 300 bytes (ENAMETOOLONG from the file system) is a file not found, not an
    OSError out of every data check."""
    for suffix in (".xml", ".img", ".JP2"):
        shutil.copy(delivery / "DATA" / f"{ORTHO}{suffix}", tmp_path / f"{ORTHO}{suffix}")
    label = tmp_path / f"{ORTHO}.xml"
    label.write_text(label.read_text().replace(f"<file_name>{ORTHO}.img</file_name>",
                                               f"<file_name>{'x' * 300}.img</file_name>"))
    findings = _no_check_failed([label])
    assert [f for f in findings if f.rule == "PDS4-010" and "x" * 300 in f.message]


@pytest.mark.parametrize("entity", [
    '<!ENTITY x SYSTEM "file:///etc/passwd">',
    '<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY x "&b;&b;&b;&b;&b;&b;&b;&b;">',
])
def test_a_pds4_label_referring_to_its_own_entities_is_not_checked(delivery, tmp_path, entity):
    """An entity the label's own DOCTYPE declares, used in its text: PDS4-001, never expanded (an
    unexpanded one stopped the XML Schema check: 'could not run')."""
    for suffix in (".xml", ".img", ".JP2"):
        shutil.copy(delivery / "DATA" / f"{ORTHO}{suffix}", tmp_path / f"{ORTHO}{suffix}")
    label = tmp_path / f"{ORTHO}.xml"
    text = re.sub(r"^<\?xml[^>]*\?>", "", label.read_text())
    label.write_text(f'<?xml version="1.0"?><!DOCTYPE Product_Observational [{entity}]>'
                     + text.replace("<title>", "<title>&x;", 1))
    findings = _no_check_failed([label])
    assert [f for f in findings if f.rule == "PDS4-001" and "&x;" in f.message]
    assert not [f for f in findings if "root:" in f.message]  # /etc/passwd's first line never read


# -- the commands, on a copy of the delivery with one file damaged -----------------------------------

def _copy(delivery: Path, where: Path) -> Path:
    shutil.copytree(delivery, where / "dlv", symlinks=True)
    return where / "dlv"


def _outside_untouched(where: Path, before: set[str]) -> None:
    assert set(p.name for p in where.iterdir()) <= before | {"out", "page.html", "mig", "ext", "d2"}


@pytest.mark.parametrize("key, value, commands", [
    ("LINES", "99999999999999999999", ("review", "migrate")),  # past int64: numpy could not cast it
    ("LINES", "999999999999", ("review",)),  # latitudes past the pole: a graticule of 10^9 lines, unending
    ("LINE_SAMPLES", "999999999999", ("review", "migrate")),  # numpy could not cast it
])
def test_a_grid_claimed_past_the_body_is_answered_in_seconds(delivery, tmp_path, key, value, commands):
    dlv = _copy(delivery, tmp_path)
    _restated(dlv / "DATA" / f"{ORTHO}.LBL", key, value)
    if "review" in commands:
        code, _, _ = _run(["review", dlv, "-o", tmp_path / "page.html"])
        assert code in (0, 1) and (tmp_path / "page.html").is_file()
    if "migrate" in commands:
        _run(["migrate", dlv / "DATA" / f"{ORTHO}.LBL", "-o", tmp_path / "mig"])


def test_an_index_label_with_columns_past_its_rows(delivery, tmp_path):
    """INDEX.LBL's START_BYTE of 10^12 (the review page's index header) and ROW_BYTES of 10^12
    (migrate's first-record check): a page and a one-line refusal, no traceback."""
    dlv = _copy(delivery, tmp_path)
    _restated(dlv / "INDEX" / "INDEX.LBL", "START_BYTE", "999999999999")
    code, _, _ = _run(["review", dlv, "-o", tmp_path / "page.html"])
    assert code in (0, 1)
    _restated(dlv / "INDEX" / "INDEX.LBL", "ROW_BYTES", "999999999999")
    code, _, err = _run(["migrate", dlv / "INDEX" / "INDEX.LBL", "-o", tmp_path / "mig"])
    assert code == 2 and "ROW_BYTES = 999999999999" in err
    assert not (tmp_path / "mig").exists() or not any((tmp_path / "mig").rglob("*.xml"))


def _objects_label(path: Path, objects: int) -> Path:
    """A PDS3 image label (4 x 4 bytes beside it) carrying OBJECTS empty objects before its IMAGE."""
    path.with_suffix(".IMG").write_bytes(bytes(16))
    path.write_bytes(b"PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 4\r\nFILE_RECORDS = 4\r\n"
                     b'^IMAGE = ("' + path.with_suffix(".IMG").name.encode() + b'", 1)\r\n'
                     + b"OBJECT = X\r\nA = 1\r\nEND_OBJECT = X\r\n" * objects
                     + b"OBJECT = IMAGE\r\nLINES = 4\r\nLINE_SAMPLES = 4\r\nSAMPLE_TYPE = UNSIGNED_INTEGER\r\n"
                       b"SAMPLE_BITS = 8\r\nEND_OBJECT = IMAGE\r\nEND\r\n")
    return path


@pytest.mark.parametrize("command", ["extras", "dtm"])
def test_a_label_of_more_objects_than_gdal_reads_in_time_is_refused(tmp_path, command):
    """GDAL's PDS reader takes time growing with the square of a label's objects (20,000: two
    minutes; 100,000, a 3 MB label, made extras run without end): a label of more than
    MAX_GDAL_LABEL_BLOCKS is refused in one line before GDAL sees it; nothing is written."""
    from pdsgen.formats.raster import MAX_GDAL_LABEL_BLOCKS

    label = _objects_label(tmp_path / "MANY.LBL", MAX_GDAL_LABEL_BLOCKS + 1)
    code, _, err = _run([command, label, "-o", tmp_path / "out"])
    assert code == 2 and f"{MAX_GDAL_LABEL_BLOCKS + 2} objects and groups" in err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_label_of_as_many_objects_as_gdal_reads_in_time_still_opens(tmp_path):
    """The bound is on objects and groups, counted as pdsgen reads the label: the IMAGE and
    MAX_GDAL_LABEL_BLOCKS - 1 others pass to GDAL, one more does not."""
    from pdsgen.formats.raster import MAX_GDAL_LABEL_BLOCKS, gdal_label_problem

    label = _objects_label(tmp_path / "MANY.LBL", MAX_GDAL_LABEL_BLOCKS - 1)
    assert gdal_label_problem(label) is None
    assert gdal_label_problem(_objects_label(tmp_path / "MORE.LBL", MAX_GDAL_LABEL_BLOCKS)) is not None


# -- any file of the delivery damaged, through every command that reads it ----------------------------

_FILES = [f"DATA/{ORTHO}.LBL", f"DATA/{ORTHO}.xml", f"DATA/{ORTHO}.JP2", f"DATA/{_DTM}.IMG", f"DATA/{_DTM}.xml",
          "DATA/JP2INFO.TXT", "DATA/collection_data.xml", "DATA/collection_data_inventory.csv",
          "INDEX/INDEX.LBL", "INDEX/INDEX.TAB", "MD5SUMS.TXT", "EXTRAS/README.TXT", "VOLDESC.CAT",
          "bundle_hostile.xml"]
_CLIMBING = [b"../../../../etc/passwd", b"%2e%2e/%2e%2e/x.img", b"..\\..\\x.img", b"C:\\x.img", b"C:x.img",
             b"/etc/passwd", b"", b"x" * 300, b"DATA/../../x", b"\\\\server\\share\\x", b"\xe9.IMG"]
_INSERTED = [b"\x00", b"\r", b"\xe9", b"\xff\xfe", b"\xef\xbb\xbf", b"\n", b'"', b"<", b"&", b"]]>",
             b"OBJECT = X\r\n" * 3, b"END_OBJECT\r\n", b"<!DOCTYPE x [<!ENTITY e SYSTEM 'file:///etc/passwd'>]>"]
_NUMBERS = [b"999999999999999999999", b"-1", b"0", b"4294967296", b"1" * 99, b"1E308", b"NaN", b"1e-300"]
_NAME = re.compile(rb"[A-Za-z0-9_]+\.(?:IMG|JP2|LBL|TAB|xml|img|TXT|csv|jpg|CAT)")

_DAMAGE = st.lists(st.one_of(
    st.tuples(st.just("cut"), st.floats(0, 1)),
    st.tuples(st.just("flip"), st.floats(0, 1), st.integers(0, 255)),
    st.tuples(st.just("insert"), st.floats(0, 1), st.sampled_from(_INSERTED)),
    st.tuples(st.just("number"), st.integers(0, 10_000), st.sampled_from(_NUMBERS)),
    st.tuples(st.just("name"), st.integers(0, 10_000), st.sampled_from(_CLIMBING)),
), min_size=1, max_size=4)


def _damaged(data: bytes, damage: list[tuple]) -> bytes:
    """DATA with each DAMAGE done in turn: cut short, a byte flipped, bytes inserted, a number made
    huge or odd, a file name made to climb out, be absolute, empty or foreign."""
    out = bytearray(data)
    for kind, where, *what in damage:
        if kind in ("number", "name"):
            found = list(re.finditer(rb"\d+(?:\.\d+)?", bytes(out)) if kind == "number" else _NAME.finditer(bytes(out)))
            if found:
                match = found[where % len(found)]
                out[match.start():match.end()] = what[0]
            continue
        at = int(where * len(out))
        if kind == "cut":
            del out[at:]
        elif kind == "flip" and out:
            out[min(at, len(out) - 1)] = what[0]
        elif kind == "insert":
            out[at:at] = what[0]
    return bytes(out)


_COMMANDS = {
    "validate": lambda dlv, target, out: ["validate", "--offline", dlv],
    "validate-file": lambda dlv, target, out: ["validate", "--offline", target],
    "migrate": lambda dlv, target, out: ["migrate", target, "-o", out / "mig"],
    "review": lambda dlv, target, out: ["review", dlv, "-o", out / "page.html"],
    "extras": lambda dlv, target, out: ["extras", target, "-o", out / "ext"],
    "deliver": lambda dlv, target, out: ["deliver", dlv / "DATA", "-o", out / "d2", "--volume-id", "X_1",
                                         "--label", "pds3"],
}


@settings(BUDGET, max_examples=30)
@given(file=st.sampled_from(_FILES), damage=_DAMAGE, command=st.sampled_from(sorted(_COMMANDS)))
@example(file=f"DATA/{ORTHO}.LBL", damage=[("number", 9, b"999999999999")], command="review")
@example(file=f"DATA/{ORTHO}.xml", damage=[("name", 0, b"x" * 300)], command="validate-file")
@example(file="INDEX/INDEX.LBL", damage=[("number", 40, b"999999999999")], command="review")
def test_any_damaged_file_is_answered_within_the_contract(delivery, tmp_path_factory, file, damage, command):
    """One file of a delivery damaged, handed to one command in-process: exit 0, 1 or 2, no
    traceback, a refusal in one line, no check that could not run, seconds not minutes, and
    nothing written beside the delivery but where -o says."""
    where = tmp_path_factory.mktemp("damaged")
    dlv = _copy(delivery, where)
    target = dlv / file
    target.write_bytes(_damaged(target.read_bytes(), damage))
    _run(_COMMANDS[command](dlv, target, where))
    assert {p.name for p in where.iterdir()} <= {"dlv", "mig", "page.html", "ext", "d2"}


def test_a_product_of_endless_obstacles_is_refused_in_bounded_lines(delivery, tmp_path):
    """A label of 20,000 pointers naming nothing: migrate tells the first obstacles and counts the
    rest (it printed 20,000 lines)."""
    from pdsgen.migrate.described import Refused

    label = tmp_path / "P.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 10\r\n"
                      + b"".join(b'^IMAGE%d = ("P.LBL", %d)\r\n' % (i, i + 1) for i in range(20_000)) + b"END\r\n")
    code, _, err = _run(["migrate", label, "-o", tmp_path / "mig"])
    lines = err.splitlines()
    assert code == 2 and len(lines) <= Refused.SHOWN + 2, len(lines)
    assert "more obstacle(s)" in err


# -- files that are not files: FIFOs named like labels and data, links to devices and outside ---------

def _fifo(path: Path) -> None:
    path.unlink(missing_ok=True)
    os.mkfifo(path)


def _link(path: Path, to: str) -> None:
    path.unlink(missing_ok=True)
    path.symlink_to(to)


_NOT_FILES = {
    "FIFO named like a label": ("DATA/F.LBL", _fifo),
    "FIFO named like a PDS4 label": ("DATA/F.xml", _fifo),
    "FIFO for the ortho's data": (f"DATA/{ORTHO}.img", _fifo),
    "FIFO for the ortho's JP2": (f"DATA/{ORTHO}.JP2", _fifo),
    "FIFO for MD5SUMS.TXT": ("MD5SUMS.TXT", _fifo),
    "FIFO for INDEX.TAB": ("INDEX/INDEX.TAB", _fifo),
    "FIFO for an inventory": ("DATA/collection_data_inventory.csv", _fifo),
    "FIFO for README.TXT": ("EXTRAS/README.TXT", _fifo),
    "FIFO for JP2INFO.TXT": ("DATA/JP2INFO.TXT", _fifo),
    "/dev/zero as a label": ("DATA/Z.LBL", lambda p: _link(p, "/dev/zero")),
    "/dev/zero as the ortho's data": (f"DATA/{ORTHO}.img", lambda p: _link(p, "/dev/zero")),
    "/dev/zero as MD5SUMS.TXT": ("MD5SUMS.TXT", lambda p: _link(p, "/dev/zero")),
    "/dev/zero as an inventory": ("DATA/collection_data_inventory.csv", lambda p: _link(p, "/dev/zero")),
    "a label leading outside": ("DATA/OUT.LBL", lambda p: _link(p, "/etc/passwd")),
    "the ortho's data leading outside": (f"DATA/{ORTHO}.img", lambda p: _link(p, "/etc/passwd")),
    "a link to itself": ("DATA/LOOP.LBL", lambda p: _link(p, "LOOP.LBL")),
    "a directory named like a label": ("DATA/DIR.LBL", lambda p: p.mkdir()),
}


def _not_files():
    for command in ("validate", "review", "deliver", "migrate"):
        for case in sorted(_NOT_FILES):
            yield pytest.param(command, case, id=f"{command}-{case}")


@pytest.mark.parametrize("command, case", list(_not_files()))
def test_what_is_not_a_regular_file_is_never_waited_on(delivery, tmp_path, case, command):
    """A FIFO, a device or a link out of the tree where a label, data, manifest, index,
    inventory or Extras text should be: every command answers within the contract (a FIFO
    opened would block it for ever) and writes nothing but its output."""
    dlv = _copy(delivery, tmp_path)
    name, make = _NOT_FILES[case]
    make(dlv / name)
    label = dlv / "DATA" / f"{ORTHO}.LBL"
    args = {"validate": ["validate", "--offline", dlv], "review": ["review", dlv, "-o", tmp_path / "page.html"],
            "deliver": ["deliver", dlv / "DATA", "-o", tmp_path / "d2", "--volume-id", "X_1", "--label", "pds3"],
            "migrate": ["migrate", label, "-o", tmp_path / "mig"]}[command]
    _run(args, SECONDS)
    assert {p.name for p in tmp_path.iterdir()} <= {"dlv", "mig", "page.html", "d2"}


@pytest.mark.parametrize("case", ["FIFO named like a label", "/dev/zero as the ortho's data"])
def test_the_installed_command_never_waits_on_what_is_not_a_file(delivery, tmp_path, case):
    """The same through `python -m pdsgen`, as a user runs it: the process ends, in one line or a
    report, never a traceback."""
    dlv = _copy(delivery, tmp_path)
    name, make = _NOT_FILES[case]
    make(dlv / name)
    done = run_cli("validate", "--offline", dlv)
    assert done.returncode in (0, 1, 2) and "Traceback" not in done.stderr, done.stderr
    done = run_cli("extras", dlv / "DATA" / f"{ORTHO}.LBL", "-o", tmp_path / "ext")
    assert done.returncode in (0, 2) and "Traceback" not in done.stderr, done.stderr
    if done.returncode == 2:
        assert len(done.stderr.strip().splitlines()) == 1 and not (tmp_path / "ext").exists()
