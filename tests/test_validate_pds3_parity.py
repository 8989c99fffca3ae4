"""Differences from NASA's PDS3 tools that bench/pds3_parity.py showed to be defects, each
on the label of NASA's test that shows it (tests/data/pds3_product_tools)."""

from __future__ import annotations

from pathlib import Path

from pdsgen.validate import validate_paths

DATA = Path(__file__).parent / "data" / "pds3_product_tools"


def _found(name: str, rule: str, **options) -> list[tuple[int | None, str]]:
    report = validate_paths([DATA / name], **options)
    return [(f.line, f.severity) for f in report.findings if f.rule == rule]


def test_a_padded_line_of_another_writers_label_is_a_warning():
    """attachedPadded.lbl (LineLengthTest.testAttachedPadded): lines 4 and 5 are not padded to
    RECORD_BYTES-2 = 79; NASA warns (WRONG_LINE_LENGTH), and the pointer says where the data start."""
    assert _found("attachedPadded.lbl", "FILE-005") == [(4, "warning"), (5, "warning")]
    assert _found("attachedPadded.lbl", "FILE-005", strict=True) == [(4, "error"), (5, "error")]


def test_an_sfdu_head_with_the_letter_l_for_the_digit_1_is_a_warning():
    """SFDULabel.lbl (DefaultLabelParserTest.testSFDU, a Rings Node label of 2003): its head
    CCSD3ZF0000l0000000lNJPL3IF0PDSX0000000l types l for 1; NASA's parser accepts it."""
    assert _found("SFDULabel.lbl", "FILE-006") == [(1, "warning")]
    assert not [f for f in validate_paths([DATA / "SFDULabel.lbl"]).findings if f.severity == "error"]


def test_a_based_integer_for_a_real_keyword_is_a_type_error():
    """real.lbl (RealCheckerTest.testBadReal): APXS_MECHANISM_ANGLE = 2#10001# on line 6; the
    decimal numbers of lines 4, 5 and 7 (-181, 361, 3.6e2) are of the keyword's type."""
    assert _found("real.lbl", "DICT-002") == [(3, "error"), (6, "error")]


def test_an_integer_past_64_bits_is_a_type_error():
    """sequenceValue.lbl (ElementValidatorTest.testSequence): a 59-digit integer in
    MRO:LOOKUP_CONVERSION_TABLE, an INTEGER keyword, on line 6 (its statement starts on line 5)."""
    found = [f for f in validate_paths([DATA / "sequenceValue.lbl"]).findings if f.rule == "DICT-002"]
    assert [(f.line, f.severity) for f in found] == [(4, "error"), (6, "error")]
    assert "59 digits" in found[1].message and "MRO:LOOKUP_CONVERSION_TABLE" in found[1].message


def test_a_standard_value_in_small_letters_is_a_warning():
    """manipulatedValue.lbl (ElementValidatorTest.testManipulatedValue): MISSING_PACKET_FLAG = yes
    on line 4 is the standard YES in small letters; NO on line 5 is as the dictionary has it."""
    assert _found("manipulatedValue.lbl", "DICT-004") == [(4, "warning")]
