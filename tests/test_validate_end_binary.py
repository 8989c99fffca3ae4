"""Attached labels whose END is followed directly by the binary data, with no line end
(ISIS and several mission pipelines write `End` so): the label ends at END.

Each product is built here byte by byte; the data start with bytes a tokenizer could take
for word characters (0xF8, then a vertical tab, '(' and 'Q'), so a reader that glues END
to them reads on into the data.
"""

from __future__ import annotations

import pytest

from pdsgen.errors import PdsgenError
from pdsgen.label.parser import parse_label
from pdsgen.validate import validate_paths

DATA = (b"\xf8\x0b(\x0bQ" * 40)[:128]  # 2 lines x 64 samples, 8-bit
WORDLIKE_DATA = (b"Q\xf8\x0b(\x0b" * 40)[:128]  # the first data byte is itself a letter


def _undefined_bytes(end_word: str, data: bytes = DATA) -> bytes:
    """RECORD_TYPE UNDEFINED with a <BYTES> pointer to the byte right after END."""
    for width in range(1, 6):
        lines = ["PDS_VERSION_ID = PDS3", "RECORD_TYPE = UNDEFINED",
                 f"^IMAGE = {'0' * width} <BYTES>", "OBJECT = IMAGE", "  LINES = 2",
                 "  LINE_SAMPLES = 64", "  SAMPLE_TYPE = UNSIGNED_INTEGER", "  SAMPLE_BITS = 8",
                 "END_OBJECT = IMAGE", end_word]
        label = "\r\n".join(lines).encode("ascii")
        start = len(label) + 1
        if len(str(start)) == width:
            return label.replace(b"0" * width + b" <BYTES>", str(start).encode() + b" <BYTES>") + data
    raise AssertionError("unreachable")


def _fixed_length(end_word: str, data: bytes = DATA) -> bytes:
    """FIXED_LENGTH records: the label is exactly one record, END its last bytes, and the
    image two records of one byte per sample."""
    for record in range(200, 400):
        lines = ["PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", f"RECORD_BYTES = {record}",
                 "FILE_RECORDS = 3", "LABEL_RECORDS = 1", "^IMAGE = 2", "OBJECT = IMAGE", "  LINES = 2",
                 f"  LINE_SAMPLES = {record}", "  SAMPLE_TYPE = UNSIGNED_INTEGER", "  SAMPLE_BITS = 8",
                 "END_OBJECT = IMAGE", end_word]
        label = "\r\n".join(lines).encode("ascii")
        if len(label) == record:
            return label + (data * (2 * record // len(data) + 1))[: 2 * record]
    raise AssertionError("unreachable")


FORMS = {"undefined": _undefined_bytes, "fixed": _fixed_length}


@pytest.mark.parametrize("form", sorted(FORMS))
@pytest.mark.parametrize("end_word", ["END", "End", "end"])
@pytest.mark.parametrize("data", [DATA, WORDLIKE_DATA], ids=["binary", "letter-first"])
def test_label_ends_at_end_followed_by_data(tmp_path, form, end_word, data):
    product = FORMS[form](end_word, data)
    path = tmp_path / "PRODUCT.IMG"
    path.write_bytes(product)
    label_end = product.index(end_word.encode() + data[:2]) + len(end_word)

    parsed = parse_label(product.decode("latin-1"))
    assert parsed.end_found and parsed.label_end == label_end
    assert next(parsed.root.blocks("IMAGE")).number("SAMPLE_BITS") == 8

    report = validate_paths([path])
    findings = report.files[0].findings
    assert not [f for f in findings if f.severity == "error"], findings
    assert len(findings) <= 3  # at most: keyword case, one long line, its padding
    last_line = product[:label_end].count(b"\n") + 1
    assert all(f.line is None or f.line <= last_line for f in findings)
    assert all(f.message.isascii() and "\\x" not in f.message for f in findings)
    assert not [f for f in findings if f.rule in ("FILE-001", "FILE-007", "SYNTAX-001", "SYNTAX-002")]


def test_a_keyword_starting_with_end_is_still_a_keyword():
    """ENDING_TIME, END_OBJECT and a value with binary after '=' are not END."""
    label = parse_label("PDS_VERSION_ID = PDS3\r\nENDING_TIME = 2001-01-01\r\nOBJECT = IMAGE\r\n"
                        "  NOTE = X\r\nEND_OBJECT = IMAGE\r\nEND\r\n")
    assert label.root.text("ENDING_TIME") == "2001-01-01" and label.end_found and not label.issues
    broken = parse_label("PDS_VERSION_ID = PDS3\r\nENDX = \xf8\x0b\r\nEND\r\n")
    assert broken.end_found and broken.label_end == len(broken.text)


@pytest.mark.parametrize("close_object, close_group", [("END_OBJECT", "END_GROUP"),
                                                      ("End_Object", "End_Group"),
                                                      ("end_object", "end_group")])
def test_closing_keywords_in_any_case(close_object, close_group):
    """ODL keywords are case-insensitive: named and unnamed closings close their blocks."""
    text = ("PDS_VERSION_ID = PDS3\r\nObject = IMAGE\r\n  Group = G\r\n    A = 1\r\n"
            f"  {close_group} = G\r\n  B = 2\r\n{close_object}\r\nGROUP = H\r\n  C = 3\r\n"
            f"{close_group}\r\nEnd")
    label = parse_label(text + "\xf8\x0b(")
    assert label.end_found and label.label_end == len(text)
    assert {i.rule for i in label.issues} <= {"SYNTAX-003", "SYNTAX-006"}  # case, unnamed closing
    image = next(label.root.blocks("IMAGE"))
    assert image.number("B") == 2 and next(image.blocks("G")).number("A") == 1
    assert next(label.root.blocks("H")).number("C") == 3


def test_extras_read_the_label_that_ends_at_end(tmp_path):
    """Extras read the same label (pvl, cut at END), so the error is GDAL's - which does not
    read such a file - not a label that cannot be parsed."""
    from pdsgen.extras.product_source import _find_label, open_product

    path = tmp_path / "PRODUCT.IMG"
    path.write_bytes(_undefined_bytes("End"))
    label_path, label = _find_label(path)
    assert label_path == path and label["IMAGE"]["LINE_SAMPLES"] == 64
    with pytest.raises(PdsgenError, match="not a raster GDAL can read"):
        open_product(path)
