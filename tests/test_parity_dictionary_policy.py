"""The dictionary the user names is the authority: its constraints become errors (docs/pds3-parity.md).

Labels: NASA's PDS3 tool test labels (tests/data/corpus/pds3_product_tools, copies of
NASA-PDS/pds3-product-tools src/test-data/labels; SOURCES.md), whose JUnit tests assert
each problem below as an error-severity ProblemType (UNKNOWN_KEY, OOR, SHORT_VALUE,
TYPE_MISMATCH, UNKNOWN_VALUE_TYPE, INVALID_VALUE) with NASA's own test dictionary,
testdd.full (tests/data/corpus/reference/testdd.full). Without a dictionary named, the same
labels keep pdsgen's warnings (genuine archives carry local keywords, break ranges ...).
"""

from __future__ import annotations

import pytest

from pdsgen.validate import validate_paths

# label -> (rule, line) NASA's test asserts as an error there (ElementValidatorTest,
# IntegerCheckerTest, AlphaNumericCheckerTest ... at NASA-PDS/pds3-product-tools 16f7c86)
NASA_ERRORS = {
    "unknownDefinition.lbl": ("DICT-001", 4),  # UNKNOWN_KEY
    "integer.lbl": ("DICT-003", 5),  # OOR: above the maximum
    "alphaNumeric.lbl": ("DICT-006", 3),  # SHORT_VALUE
    "typeMismatch.lbl": ("DICT-009", 4),  # TYPE_MISMATCH: DELIMITING_PARAMETER_NAME = 43
    "unknownUnits.lbl": ("DICT-007", 7),  # UNKNOWN_VALUE_TYPE: <seconds>
    "invalidValue.lbl": ("DICT-004", 5),  # INVALID_VALUE: "ASCII INTEGER" for ASCII_INTEGER
}


def _levels(path, **options) -> dict[tuple[str, int | None], str]:
    return {(f.rule, f.line): f.severity for f in validate_paths([path], **options).findings}


@pytest.mark.parametrize("name", sorted(NASA_ERRORS))
def test_an_error_against_the_dictionary_named(corpus_dir, name):
    label = corpus_dir / "pds3_product_tools" / name
    testdd = corpus_dir / "reference" / "testdd.full"
    found = NASA_ERRORS[name]
    assert _levels(label, dictionaries=[testdd]).get(found) == "error"
    plain = _levels(label)  # without --dictionary: a deviation (or a keyword only testdd.full defines)
    assert [level for (rule, line), level in plain.items() if rule.startswith("DICT") and line == found[1]] in (
        ["warning"], ["info"])


def test_a_lower_case_standard_value_stays_a_warning(corpus_dir):
    """MISSING_PACKET_FLAG = yes: NASA's MANIPULATED_VALUE is a warning, with their dictionary too."""
    label = corpus_dir / "pds3_product_tools" / "manipulatedValue.lbl"
    levels = _levels(label, dictionaries=[corpus_dir / "reference" / "testdd.full"])
    assert [level for (rule, _), level in levels.items() if rule == "DICT-004"] == ["warning"]


def test_a_local_dictionary_makes_its_own_limits_hard(tmp_path):
    """A mission's local dictionary, in the PSDD form: its range is a rule; a keyword neither it
    nor the built-in dictionary defines is an error; a unit no list knows is an error."""
    dictionary = tmp_path / "local.full"
    dictionary.write_text("OBJECT = ELEMENT_DEFINITION\n  NAME = MY_COUNT\n  GENERAL_DATA_TYPE = INTEGER\n"
                          "  UNIT_ID = NONE\n  STANDARD_VALUE_TYPE = RANGE\n  MINIMUM = 0\n  MAXIMUM = 10\n"
                          "END_OBJECT = ELEMENT_DEFINITION\n")
    label = tmp_path / "X.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nMY_COUNT = 12\r\nMY_OTHER = 1\r\n"
                      b"EXPOSURE_DURATION = 10 <FORTNIGHTS>\r\nEND\r\n")
    named = _levels(label, dictionaries=[dictionary])
    assert named[("DICT-003", 2)] == named[("DICT-001", 3)] == named[("DICT-007", 4)] == "error"
    plain = _levels(label)
    assert plain[("DICT-001", 2)] == plain[("DICT-001", 3)] == plain[("DICT-007", 4)] == "warning"


def test_the_built_in_dictionary_keeps_genuine_labels_free_of_dictionary_errors(corpus_dir):
    """The genuine mission labels (tests/data/corpus/real) against the built-in dictionary: no
    DICT error of the kinds the policy makes errors only for a dictionary the user names."""
    report = validate_paths([corpus_dir / "real"], labels_only=True)
    hard = {"DICT-001", "DICT-003", "DICT-006", "DICT-007", "DICT-009"}
    assert [f for f in report.findings if f.rule in hard and f.severity == "error"] == []
