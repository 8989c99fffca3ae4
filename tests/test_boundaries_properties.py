"""Property-based tests of the inbound boundaries (issue 48): the containment rule, the bounded
reader and the count check, on arbitrary Unicode and bytes, deep and wide structures and huge
numbers. Each answers within its bounds with a value or a one-line InputError naming its
source - never another exception.

The references are the standard library's own readers (json, tomllib) and os.path: a value
the bounded reader returns is the one they return for the same text. Fixed budget, no example
database, derandomized: the same examples run in CI every time; cases found are kept as
@example regressions.
"""

from __future__ import annotations

import json
import os
import string
import struct
from pathlib import Path, PurePosixPath

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from pdsgen import bounded
from pdsgen._compat import tomllib
from pdsgen.errors import InputError
from pdsgen.storage.containment import NAME_MAX, checked_name, contained, inside, name_problem

BUDGET = settings(max_examples=150, deadline=None, derandomize=True, database=None,
                  suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _one_line(exc: InputError, source: str) -> None:
    text = str(exc)
    assert "\n" not in text and "\r" not in text and text.startswith(f"{source}: "), text


def _value_or_one_line(parse, source: str, text: str) -> None:  # noqa: ANN001 - one of bounded.parse_*
    """PARSE answers TEXT with a value, or refuses it with a one-line InputError naming SOURCE."""
    try:
        parse(source, text)
    except InputError as exc:
        _one_line(exc, source)


# -- the containment rule ------------------------------------------------------------------------

_SEGMENTS = st.one_of(st.sampled_from(["..", ".", "", "a", "b.LBL", "x" * (NAME_MAX + 1), "\x00", "é" * 128]),
                      st.text(min_size=0, max_size=12))
_NAMES = st.one_of(st.text(max_size=40), st.lists(_SEGMENTS, max_size=6).map("/".join),
                   st.lists(_SEGMENTS, max_size=6).map(lambda parts: "/" + "/".join(parts)))


@BUDGET
@given(_NAMES)
@example("../x")
@example("//abs/x")
@example("sub/../..")
@example("a" * 300)
@example("ok/\x00")
@example("DATA/\udcff.IMG")  # a Latin-1 name carried as surrogateescape
def test_checked_name_is_a_relative_path_inside_or_one_line(name):
    try:
        path = checked_name(name, "s3://bucket/key")
    except InputError as exc:
        _one_line(exc, "s3://bucket/key")
        assert name_problem(name) is not None
        return
    assert not path.is_absolute() and ".." not in path.parts and "." not in path.parts
    assert all(0 < len(part.encode("utf-8", "surrogateescape")) <= NAME_MAX for part in path.parts)
    root = "/srv/tree"
    joined = os.path.normpath(os.path.join(root, str(path)))  # the world's own join, not ours
    assert joined.startswith(root + "/")


@BUDGET
@given(name=st.lists(st.sampled_from(["a", "b", "..", "link", "up"]), min_size=1, max_size=5).map("/".join))
def test_inside_never_leaves_the_root_through_links(tmp_path_factory, name):
    base = tmp_path_factory.mktemp("tree")
    root = base / "root"
    (root / "a" / "b").mkdir(parents=True)
    (base / "outside").mkdir()
    (root / "a" / "link").symlink_to(base / "outside")  # a link leading out
    (root / "up").symlink_to(root / "a")  # a link staying in
    try:
        path = inside(root, name, "label")
    except InputError as exc:
        _one_line(exc, "label")
        return
    real = os.path.realpath(path)
    assert real == os.path.realpath(root) or real.startswith(os.path.realpath(root) + os.sep)
    assert contained(path, root) == path


# -- the bounded reader ------------------------------------------------------------------------

_JSON_LEAVES = st.one_of(st.none(), st.booleans(), st.integers(min_value=-10**130, max_value=10**130),
                         st.floats(allow_nan=False, allow_infinity=False), st.text(max_size=20))
_JSON_VALUES = st.recursive(_JSON_LEAVES, lambda inner: st.one_of(
    st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)), max_leaves=40)


def _depth(value) -> int:
    if isinstance(value, dict):
        return 1 + max(map(_depth, value.values()), default=0)
    if isinstance(value, list):
        return 1 + max(map(_depth, value), default=0)
    return 0


def _huge_int(value) -> bool:
    if isinstance(value, bool):
        return False
    if isinstance(value, int):
        return abs(value) >= 10 ** bounded.MAX_INT_DIGITS
    items = value.values() if isinstance(value, dict) else value if isinstance(value, list) else []
    return any(map(_huge_int, items))


def _nested(depth: int) -> list:
    value: list = []
    for _ in range(depth):
        value = [value]
    return value


@BUDGET
@given(st.one_of(_JSON_VALUES, st.integers(0, 80).map(_nested)))
@example(_nested(bounded.MAX_DEPTH))
@example(_nested(bounded.MAX_DEPTH + 1))
@example(10 ** 100)
@example([-(10 ** 150)])
def test_json_is_read_as_json_reads_it_or_refused_in_one_line(value):
    text = json.dumps(value)
    try:
        read = bounded.parse_json("f.json", text)
    except InputError as exc:
        _one_line(exc, "f.json")
        assert _depth(value) > bounded.MAX_DEPTH or _huge_int(value)
        return
    assert read == json.loads(text) and _depth(value) <= bounded.MAX_DEPTH


@BUDGET
@given(st.text(max_size=300))
@example("[" * 100_000)
@example("{" * 5000 + "}" * 5000)
@example("NaN")
@example("1" * 5000)
def test_arbitrary_text_as_json_is_a_value_or_one_line(text):
    _value_or_one_line(bounded.parse_json, "f.json", text)


_TOML_KEYS = st.text(alphabet=string.ascii_letters + string.digits + "_-", min_size=1, max_size=8)
_TOML_VALUES = st.recursive(
    st.one_of(st.booleans(), st.integers(min_value=-10**120, max_value=10**120), st.text(max_size=12)),
    lambda inner: st.one_of(st.lists(inner, max_size=3), st.dictionaries(_TOML_KEYS, inner, max_size=3)),
    max_leaves=30)


def _toml_value(value) -> str:
    """VALUE written as TOML (inline tables and arrays), by the specification's grammar."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)  # a JSON string of BMP text is a TOML basic string
    if isinstance(value, list):
        return "[" + ", ".join(map(_toml_value, value)) + "]"
    return "{" + ", ".join(f'"{k}" = {_toml_value(v)}' for k, v in value.items()) + "}"


@BUDGET
@given(st.dictionaries(_TOML_KEYS, _TOML_VALUES, max_size=4))
@example({"a": _nested(bounded.MAX_DEPTH + 5)})
@example({"big": 10 ** 200})
def test_toml_is_read_as_tomllib_reads_it_or_refused_in_one_line(table):
    text = "".join(f'"{key}" = {_toml_value(value)}\n' for key, value in table.items())
    try:
        expected = tomllib.loads(text)
    except (tomllib.TOMLDecodeError, ValueError, RecursionError):
        expected = None
    try:
        read = bounded.parse_toml("p.toml", text)
    except InputError as exc:
        _one_line(exc, "p.toml")
        assert expected is None or _depth(table) > bounded.MAX_DEPTH or _huge_int(table)
        return
    assert read == expected


@BUDGET
@given(st.text(max_size=300))
@example("a = " + "[" * 5000 + "]" * 5000)
@example("x = " + "9" * 5000)
@example('a = """\x00"""')
@example("[a]\n[a]\n")
def test_arbitrary_text_as_toml_is_a_value_or_one_line(text):
    _value_or_one_line(bounded.parse_toml, "p.toml", text)


@BUDGET
@given(st.text(max_size=300))
@example("GROUP = A\n" * 40 + "END_GROUP = A\n" * 40 + "END")
@example("X = " + "(" * 3000 + ")" * 3000)
@example("X = " + "9" * 5000 + "\nEND")
@example("OBJECT = 'unterminated")
@example("X = 16#FFFF")
def test_arbitrary_text_as_pvl_is_a_value_or_one_line(text):
    _value_or_one_line(bounded.parse_pvl, "p.pvl", text)


@BUDGET
@given(data=st.binary(max_size=600), limit=st.integers(0, 700))
def test_read_bytes_returns_the_file_or_refuses_past_the_cap(tmp_path_factory, data, limit):
    path = tmp_path_factory.mktemp("bytes") / "file"
    path.write_bytes(data)
    try:
        read = bounded.read_bytes(path, limit)
    except InputError as exc:
        _one_line(exc, str(path))
        assert len(data) > limit
        return
    assert read == data and len(data) <= limit


@pytest.mark.parametrize("special", ["/dev/zero", "/dev/null", "directory", "fifo"])
def test_read_bytes_refuses_what_is_not_a_regular_file_at_once(tmp_path, special):
    path = Path(special) if special.startswith("/") else tmp_path / special
    if special == "directory":
        path.mkdir()
    elif special == "fifo":
        os.mkfifo(path)
    with pytest.raises(InputError) as refused:
        bounded.read_bytes(path)
    _one_line(refused.value, str(path))


# -- the .full dictionary reader -------------------------------------------------------------

_PSDD_LINES = st.sampled_from(["OBJECT = ELEMENT_DEFINITION", "END_OBJECT = ELEMENT_DEFINITION",
                               "OBJECT = GENERIC_OBJECT_DEFINITION", "END_OBJECT", "  NAME = X_Y",
                               "  GENERAL_DATA_TYPE = INTEGER", "OBJECT = UNIT_LIST", "END_OBJECT = UNIT_LIST",
                               "  UNIT_ID = {('m','METER')}", "/* Generated: Mon Sep 25 14:04:29 2017 */", ""])


@BUDGET
@given(st.lists(st.one_of(_PSDD_LINES, st.text(max_size=30)), max_size=60))
@example(["OBJECT = ELEMENT_DEFINITION", "  NAME = LOST"] * 30)
def test_a_dictionary_is_read_whole_objects_only(lines):
    from pdsgen.errors import PdsgenError
    from pdsgen.validate.psdd import parse_psdd

    try:
        found = parse_psdd(Path("d.full"), "\n".join(lines))
    except PdsgenError as exc:
        assert "\n" not in str(exc)
        return
    closed = sum(1 for line in lines if line.startswith("END_OBJECT = ELEMENT_DEFINITION"))
    assert len(found["elements"]) <= closed


# -- counts against the bytes there ---------------------------------------------------------------

@BUDGET
@given(count=st.integers(-5, 2**40), item=st.integers(0, 16), available=st.integers(-5, 10**6))
def test_checked_count_allows_exactly_what_the_bytes_hold(count, item, available):
    try:
        assert bounded.checked_count("f", "a count", count, item, available) == count
    except InputError as exc:
        _one_line(exc, "f")
        assert count < 0 or count * item > max(available, 0)
        return
    assert count >= 0 and count * item <= max(available, 0)


def _tiff(entries: list[tuple[int, int, int, bytes]], tail: bytes) -> bytes:
    body = struct.pack("<H", len(entries)) + b"".join(struct.pack("<HHI4s", *e) for e in entries) + b"\0" * 4
    return b"II" + struct.pack("<HI", 42, 8) + body + tail


@BUDGET
@given(entries=st.lists(st.tuples(st.integers(0, 65535), st.integers(0, 17), st.integers(0, 2**32 - 1),
                                  st.binary(min_size=4, max_size=4)), max_size=6),
       tail=st.binary(max_size=64))
@example(entries=[(33550, 12, 2**32 - 1, struct.pack("<I", 26))], tail=b"\0" * 24)
@example(entries=[(34735, 3, 2**31, struct.pack("<I", 0))], tail=b"")
def test_a_geotiff_directory_is_read_within_its_bytes(entries, tail):
    from pdsgen.formats.geojp2 import geokeys_of, tiff_tags

    data = _tiff(entries, tail)
    try:
        tags = tiff_tags(data, "x.jp2")
    except InputError as exc:
        _one_line(exc, "x.jp2")
        return
    except (ValueError, struct.error):  # not a TIFF: the validator's "no georeferencing"
        return
    assert sum(len(v) for v in tags.values()) <= len(data)
    geokeys_of(tags)


@BUDGET
@given(st.binary(max_size=200))
@example(b"\0\0\0\x01jP  " + b"\0" * 8)  # an extended length of 0
@example(b"\0\0\0\x05abcd")  # shorter than its header
@example(b"\xff\xff\xff\xffjp2c")  # past the end of the file
def test_jp2_boxes_are_read_within_the_file(tmp_path_factory, data):
    from pdsgen.formats.jp2 import jp2_boxes

    path = tmp_path_factory.mktemp("jp2") / "x.jp2"
    path.write_bytes(data)
    try:
        boxes = jp2_boxes(path)
    except InputError as exc:
        _one_line(exc, str(path))
        return
    assert sum(length for _, _, length in boxes) == len(data)


def test_the_properties_run_without_an_example_database():
    assert BUDGET.database is None and BUDGET.derandomize
    assert PurePosixPath("a") == checked_name("a/", "x")
