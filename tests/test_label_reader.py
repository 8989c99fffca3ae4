"""The one PDS3 label reader (pdsgen.label): its END rule, its file-beside look-up and the
mapping the Extras and the HRSC writer read, checked against pvl - an independent reader -
on the genuine labels in tests/data (provenance in tests/data/genuine_pds3/PROVENANCE.md)."""

from __future__ import annotations

import datetime as dt
import math
from pathlib import Path

import pvl
import pytest

from pdsgen.archive.scan import label_root as deliver_reads
from pdsgen.label.beside import find_beside
from pdsgen.label.mapping import MappedQuantity as Quantity
from pdsgen.label.mapping import label_mapping
from pdsgen.label.parser import end_of_label, has_end, parse_label, read_label_head
from pdsgen.label.read import read_pds3_label
from pdsgen.validate.context import FileContext

DATA = Path(__file__).parent / "data"
GENUINE = sorted(p for p in (DATA / "genuine_pds3").rglob("*") if p.suffix.lower() == ".lbl")


@pytest.mark.parametrize("end", [b"END", b"end", b"END;", b"END ;", b"END /* the end */", b"  END  "])
def test_every_end_line_the_validator_accepts_ends_the_label_for_every_reader(tmp_path, end):
    data = b"\x00\xff\x10" * 30000  # binary data after the label, more than one read block
    path = tmp_path / "A.IMG"
    path.write_bytes(b"PDS_VERSION_ID = PDS3\r\nRECORD_BYTES = 10\r\n" + end + b"\r\n" + data)
    assert has_end(path.read_bytes())
    head = read_label_head(path, first=16, step=16)
    assert len(head) < 100  # reading stopped at END, not at the 4 MiB limit
    label = read_pds3_label(path)
    assert label is not None and label.end_found and label.root.number("RECORD_BYTES") == 10
    root = deliver_reads(path)
    assert root is not None and root.number("RECORD_BYTES") == 10
    assert FileContext(path).label.end_found


def test_end_directly_followed_by_binary_data_ends_the_label(tmp_path):
    path = tmp_path / "A.IMG"
    path.write_bytes(b"PDS_VERSION_ID = PDS3\nEND\xf8\x01\x02" + b"\x00" * 200_000)
    head = read_label_head(path, first=64, step=64)
    assert end_of_label(head) == len(b"PDS_VERSION_ID = PDS3\nEND")
    assert not has_end(b"PDS_VERSION_ID = PDS3\nEND_OBJECT = X\nENDING = 1\n")


def test_a_file_beside_a_label_is_found_by_exact_name_first_then_by_case(tmp_path):
    (tmp_path / "a.img").write_bytes(b"x")
    (tmp_path / "B.IMG").write_bytes(b"x")
    assert find_beside(tmp_path, "B.IMG") == tmp_path / "B.IMG"
    assert find_beside(tmp_path, "b.img") == tmp_path / "B.IMG"
    assert find_beside(tmp_path, "A.IMG") == tmp_path / "a.img"
    assert find_beside(tmp_path, "C.IMG") is None


def _pvl_shape(value):
    """pvl's values with its own types replaced by plain ones, to compare with label_mapping."""
    if isinstance(value, (pvl.collections.Quantity, Quantity)):
        return ("quantity", _pvl_shape(value.value), str(value.units))
    if hasattr(value, "keys"):
        first: dict = {}
        for key, item in value.items():
            first.setdefault(key, item)
        return {key: _pvl_shape(item) for key, item in first.items()}
    if isinstance(value, (list, tuple)):
        return [_pvl_shape(item) for item in value]
    if isinstance(value, (set, frozenset)):
        return frozenset(_pvl_shape(item) for item in value)
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    return value


def _label_text(path: Path) -> str:
    head = read_label_head(path)
    end = end_of_label(head)
    return (head[:end] if end is not None else head).decode("latin-1")


def _differs_by_design(path: Path) -> str | None:
    """Why a genuine label cannot be compared with pvl's reading, or None when it can: pvl
    refuses it, or it breaks the standard (SYNTAX-001/005) or nests SFDU segments, where pvl
    stops at the first END."""
    text = _label_text(path)
    try:
        pvl.loads(text)
    except Exception:
        return "pvl cannot read it"
    label = parse_label(text)
    if any(issue.rule in ("SYNTAX-001", "SYNTAX-005") for issue in label.issues) or "SFDU_LABEL" in text[200:]:
        return "not a standard label"
    return None


UNCOMPARED = {path: why for path in GENUINE if (why := _differs_by_design(path))}


def test_nearly_every_genuine_label_is_compared_with_pvl():
    assert len(GENUINE) - len(UNCOMPARED) >= 130 and len(UNCOMPARED) <= 7


@pytest.mark.parametrize("path", [p for p in GENUINE if p not in UNCOMPARED],
                         ids=lambda p: p.relative_to(DATA).as_posix())
def test_the_label_mapping_holds_what_pvl_reads_from_genuine_labels(path):
    text = _label_text(path)
    assert _pvl_shape(label_mapping(parse_label(text))) == _pvl_shape(pvl.loads(text))


def test_label_mapping_values_have_pvls_shapes():
    text = ('PDS_VERSION_ID = PDS3\nA = "two  words\r\n   and a line-\r\n  break"\nB = NULL\nC = 16#FF7FFFFB#\n'
            "D = 2004-01-10T14:02:57.817Z\nE = 2004-010T14:02:57\nF = (1, 2) <M>\nG = 2575.0 <KM>\n"
            "H = {X, Y}\nI = 2004-01-10\nOBJECT = IMAGE\n  LINES = 3\nEND_OBJECT = IMAGE\n^IMAGE = 5\nEND\n")
    mapping = label_mapping(parse_label(text))
    assert mapping == _pvl_shape(pvl.loads(text)) | {"F": Quantity([1, 2], "M"), "G": Quantity(2575.0, "KM")}
    assert mapping["A"] == "two words and a linebreak" and mapping["B"] is None and mapping["C"] == 0xFF7FFFFB
    assert mapping["D"] == dt.datetime(2004, 1, 10, 14, 2, 57, 817000, tzinfo=dt.timezone.utc)
    assert mapping["E"] == dt.datetime(2004, 1, 10, 14, 2, 57, tzinfo=dt.timezone.utc)
    assert mapping["H"] == frozenset({"X", "Y"}) and mapping["I"] == dt.date(2004, 1, 10)
    assert mapping["IMAGE"] == {"LINES": 3} and mapping["^IMAGE"] == 5
