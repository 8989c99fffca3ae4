"""bench/pds3_parity.py, the comparison with NASA's PDS3 tool tests, on a few of their labels
(tests/data/pds3_product_tools, laid out as a checkout of NASA-PDS/pds3-product-tools)."""

from __future__ import annotations

import importlib.util
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data" / "pds3_product_tools"
LABELS = ("numberExceedsMax.lbl", "real.lbl", "SFDULabel.lbl", "attachedPadded.lbl", "sequenceValue.lbl",
          "manipulatedValue.lbl")


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("pds3_parity", ROOT / "bench" / "pds3_parity.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["pds3_parity"] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def checkout(tmp_path_factory):
    """The copied labels and dictionaries where a checkout of NASA's repository has them."""
    root = tmp_path_factory.mktemp("pds3-product-tools")
    labels = root / "src" / "test-data" / "labels"
    labels.mkdir(parents=True)
    for name in LABELS:
        shutil.copy(DATA / name, labels / name)
    shutil.copy(DATA / "testdd.full", labels.parent / "testdd.full")
    shutil.copy(DATA / "pdsdd_excerpt.full", labels.parent / "pdsdd.full")
    return root


def test_case_table_format(bench):
    doc, cases = bench.read_cases()
    assert doc["repository"] == "NASA-PDS/pds3-product-tools" and doc["commit"] == bench.PINNED_COMMIT
    assert len({c.id for c in cases}) == len(cases) >= 100
    for case in cases:
        assert case.test.startswith("src/test/gov/nasa/pds/tools/") and case.test.endswith(".java"), case.id
        assert case.id.split(".")[0] == Path(case.test).stem and case.run in ("validate", "default", "parse")
        assert case.count is None or case.count >= len(case.problems), case.id
        for problem in case.problems:
            assert problem["type"] in bench.NASA_SEVERITY and problem["type"] in bench.MAPPING, (case.id, problem)
            assert problem["line"] is None or problem["line"] >= 1
    # every NASA type maps to rules pdsgen has, with a reason
    from pdsgen.validate import rules

    for kind, (mapped, levels, why) in bench.MAPPING.items():
        assert why and levels <= {"error", "warning", "info"}, kind
        assert all(rule in rules() or rule == "USAGE" for rule in mapped), kind


def _outcomes(bench, checkout, labels):
    _, cases = bench.read_cases()
    chosen = [c for c in cases if c.label in labels]
    outcomes, lines, _ = bench.run_all(checkout, chosen)
    return {o.case.id: o for o in outcomes}, lines


def test_a_range_broken_against_the_dictionary_given_is_an_error(bench, checkout):
    """The tests run with their own dictionary, the authority the user names with --dictionary:
    DECLINATION = 91 breaks its range, an error as for NASA (a warning without --dictionary)."""
    outcomes, lines = _outcomes(bench, checkout, {"numberExceedsMax.lbl"})
    outcome = outcomes["ElementValidatorTest.testNumericExceedsMax"]
    assert outcome.status == "agree" and [f.rule for f in outcome.ours] == ["DICT-003"]
    assert lines == [("numberExceedsMax.lbl", "OOR", 4, "error", "error")]


def test_cases_agree_and_checks_of_the_data_are_by_design(bench, checkout):
    outcomes, lines = _outcomes(bench, checkout, set(LABELS))
    for case in ("RealCheckerTest.testBadReal", "RealCheckerTest.testNumErrors", "DefaultLabelParserTest.testSFDU",
                 "ElementValidatorTest.testSequence", "ElementValidatorTest.testManipulatedValue"):
        assert outcomes[case].status == "agree", (case, outcomes[case])
    padded = outcomes["LineLengthTest.testAttachedPadded"]  # FILE_RECORDS 2 x 81 bytes; the file has 729
    assert padded.status == "false-error" and [f.rule for f in padded.ours] == ["REC-002"]
    assert padded.reason.startswith("by design: pdsgen checks RECORD_BYTES x FILE_RECORDS")
    # the 59-digit integer: NASA's line 5 (the statement's), pdsgen's line 6 (the number's)
    assert ("sequenceValue.lbl", "INVALID_TYPE", 5, "error", "error") in lines
    assert all(row[4] is not None for row in lines), lines


def test_nasa_severities_are_pdsgen_severity_settings(bench, checkout):
    from pdsgen.validate import rules

    assert set(bench.NASA_LEVELS) <= set(rules())
    _, cases = bench.read_cases()
    chosen = [c for c in cases if c.label == "numberExceedsMax.lbl"]
    outcomes, _, _ = bench.run_all(checkout, chosen, levels=bench.NASA_LEVELS)
    assert [o.status for o in outcomes] == ["agree"]
