"""The label reader: what real archives write is read without errors, real syntax
errors are findings with their line, and values come out typed."""

from __future__ import annotations

import pvl
import pytest

from pdsgen.label.parser import date_problem, parse_label

TOLERATED = (
    "PDS_VERSION_ID = PDS3\n"  # LF-only line ends
    "Object = IMAGE\n"  # mixed case
    "  DATA_SET_ID = MEX-M-HRSC-3-RDR-V2.0\n"  # unquoted with '-' and '.'
    "  SPACECRAFT_CLOCK_START_COUNT = 1/0021823325.32303\n"  # unquoted with '/'
    "  A_AXIS_RADIUS = 2575.0<KM>\n"  # unit without a space
    "  B_AXIS_RADIUS = 1737400. <m>\n"  # real ending in '.', lower-case unit
    "  LINES = 0015  /* zero padded */\n"  # zero-padded, inline comment
    "  MISSING_CONSTANT = 16#FF7FFFFB#\n"
    "  START_TIME = 2009-02-05T03:02:16.073000\n"
    "  VECTOR = (1.0, 2.0,\n            3.0) <KM>\n"
    "  NOTE = \"two\n  lines\"\n"
    "End_Object\n"  # unnamed END_OBJECT
    "End\n"
)


def test_tolerated_archive_forms_parse_without_errors():
    label = parse_label(TOLERATED)
    errors = [i for i in label.issues if i.rule not in ("SYNTAX-003", "SYNTAX-006")]
    assert errors == []
    image = next(label.root.blocks("IMAGE"))
    assert image.value("A_AXIS_RADIUS").py == 2575.0 and image.value("A_AXIS_RADIUS").unit == "KM"
    assert image.value("B_AXIS_RADIUS").py == 1737400.0
    assert image.value("LINES").py == 15
    assert image.value("MISSING_CONSTANT").py == 0xFF7FFFFB
    assert image.value("START_TIME").kind == "date"
    assert [v.py for v in image.value("VECTOR").scalars()] == [1.0, 2.0, 3.0]
    assert all(v.unit == "KM" for v in image.value("VECTOR").scalars())
    assert image.get("NOTE").line == 12 and image.end_line == 14
    assert label.end_found and label.label_end == len(TOLERATED)


def test_values_agree_with_pvl_on_a_plain_label():
    text = ("PDS_VERSION_ID = PDS3\r\nRECORD_BYTES = 320\r\nPRODUCT_ID = \"X_1\"\r\n"
            "OBJECT = IMAGE\r\n  LINES = 60\r\n  SCALING_FACTOR = 1.0\r\n  SAMPLE_TYPE = PC_REAL\r\n"
            "END_OBJECT = IMAGE\r\nEND\r\n")
    ours = parse_label(text).root
    theirs = pvl.loads(text)
    assert ours.number("RECORD_BYTES") == theirs["RECORD_BYTES"]
    assert ours.text("PRODUCT_ID") == theirs["PRODUCT_ID"]
    image = next(ours.blocks("IMAGE"))
    assert image.number("LINES") == theirs["IMAGE"]["LINES"]
    assert image.text("SAMPLE_TYPE") == theirs["IMAGE"]["SAMPLE_TYPE"]


@pytest.mark.parametrize(
    ("text", "rule", "line"),
    [
        ("PDS_VERSION_ID = PDS3\nTARGET_NAME  \"MARS\"\nEND\n", "SYNTAX-001", 2),
        ("PDS_VERSION_ID = PDS3\nCOMMENT = THING TEST\nEND\n", "SYNTAX-001", 2),
        ("PDS_VERSION_ID = PDS3\nA =\nB = 1\nEND\n", "SYNTAX-009", 2),
        ("PDS_VERSION_ID = PDS3\nOBJECT = X\nEND\n", "SYNTAX-005", 2),
        ("PDS_VERSION_ID = PDS3\nOBJECT = X\nEND_OBJECT = Y\nEND\n", "SYNTAX-005", 3),
        ("PDS_VERSION_ID = PDS3\nEND_GROUP = X\nEND\n", "SYNTAX-005", 2),
        ("PDS_VERSION_ID = PDS3\nM = 3#12#\nEND\n", "SYNTAX-007", 2),
        ("PDS_VERSION_ID = PDS3\nT = 2000-13-01\nEND\n", "SYNTAX-008", 2),
        ("PDS_VERSION_ID = PDS3\nA_KEYWORD_THAT_IS_FAR_TOO_LONG_X = 1\nEND\n", "SYNTAX-015", 2),
        ("PDS_VERSION_ID = PDS3\nS = (1, 2\nEND\n", "SYNTAX-001", 2),
        ("PDS_VERSION_ID = PDS3\nS = \"open\nEND\n", "SYNTAX-001", 2),
        ("PDS_VERSION_ID = PDS3\nU = 1 <>\nEND\n", "SYNTAX-011", 2),
    ],
)
def test_syntax_errors_are_issues_with_lines(text, rule, line):
    issues = parse_label(text).issues
    assert (rule, line) in {(i.rule, i.line) for i in issues}, issues


def test_reading_continues_after_an_error():
    label = parse_label("PDS_VERSION_ID = PDS3\nBROKEN VALUE\nLATER = 5\nEND\n")
    assert label.root.number("LATER") == 5 and label.end_found


def test_text_after_end_is_not_label():
    label = parse_label("PDS_VERSION_ID = PDS3\r\nEND\r\n\x00\x01garbage = = =")
    assert label.issues == [] and label.label_end == len("PDS_VERSION_ID = PDS3\r\nEND\r\n")


@pytest.mark.parametrize("good", ["2000-12-22T23:59:59.999", "2000-364T23:59", "2000-12", "2000-12-22",
                                  "2000-12-22T23:59:59.888888888Z", "12:30:00"])
def test_dates_accepted(good):
    assert date_problem(good) is None


@pytest.mark.parametrize("bad", ["2000-02-30", "2000-367", "2000-12-22T24:00", "2000-1-22", "1-12-22"])
def test_dates_rejected(bad):
    assert date_problem(bad)


def test_unit_measuring_the_wrong_thing(tmp_path):
    from pdsgen.validate import validate_paths

    label = tmp_path / "U.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nOBJECT = IMAGE_MAP_PROJECTION\r\n  A_AXIS_RADIUS = 3396.19 <DEG>\r\n"
                      b"  B_AXIS_RADIUS = 3396190.0 <METERS>\r\n  MAP_SCALE = 1.0 <KM/PIXEL>\r\n"
                      b"END_OBJECT = IMAGE_MAP_PROJECTION\r\nEND\r\n")
    findings = [(f.keyword, f.line) for f in validate_paths([label]).findings if f.rule == "DICT-011"]
    assert findings == [("A_AXIS_RADIUS", 3)]
