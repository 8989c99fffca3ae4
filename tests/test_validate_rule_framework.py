"""One rule framework: PDS4 is a rule family like the others (one Rule type, one severity
table, one finding type, one report), and a validation run is one ValidationJob.

The PDS4 labels are genuine cases of NASA's validator regression suite (provenance in
tests/data/nasa_validate/SOURCES.md), whose verdicts are NASA's, not pdsgen's."""

from __future__ import annotations

from pathlib import Path

import pytest

from pdsgen.validate import RuleSettings, ValidationJob, rules, validate_file, validate_paths
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.label_checks import validate_pds4
from pdsgen.validate.registry import Rule

CASES = Path(__file__).parent / "data" / "nasa_validate"
TABLE_FAIL = CASES / "github292/table_character/invalid/minimal_test_product_lf.xml"
SHARED = [CASES / "github681/ff_char.xml", CASES / "github681/ff_del.xml"]


def test_every_pds4_rule_is_a_registry_rule_run_by_a_check_or_across_the_run():
    pds4 = [rule for rule in rules().values() if rule.family == "PDS4"]
    assert len(pds4) == 38 and all(isinstance(rule, Rule) and rule.target == "pds4" for rule in pds4)
    assert all((rule.check is None) != (rule.run_check is None) for rule in pds4)
    assert {rule.id for rule in pds4 if rule.run_check is not None} == {"PDS4-007", "PDS4-060"}


def test_a_pds4_label_gets_the_same_findings_from_the_family_and_from_validate_pds4():
    """NASA's verdict on 292-7 (CR LF records where the label says LF) through both doors:
    the same findings, with the registry's severities, in the same order."""
    alone = validate_pds4(TABLE_FAIL)
    report, summary = validate_file(TABLE_FAIL)
    assert summary is None and report.findings == alone
    assert {"PDS4-051", "PDS4-052"} <= {f.rule for f in alone}
    assert all(f.severity == rules()[f.rule].severity for f in alone)


def test_configuration_sets_the_severity_of_pds4_findings_as_of_any_other():
    settings = RuleSettings(severity={"PDS4-052": "warning"}, ignore=frozenset({"PDS4-051"}))
    found = {f.rule: f.severity for f in validate_paths([TABLE_FAIL], settings=settings).findings}
    assert found.get("PDS4-052") == "warning" and "PDS4-051" not in found


def test_the_schematron_note_is_one_finding_per_run_and_configuration_drops_it(monkeypatch):
    monkeypatch.setattr(schematron, "available", lambda: False)  # as on an install without saxonche
    notes = [f for f in validate_paths(SHARED).findings if f.rule == "PDS4-007"]
    assert len(notes) == 1 and notes[0].file == str(SHARED[0]) and notes[0].severity == "warning"
    ignored = validate_paths(SHARED, settings=RuleSettings(ignore=frozenset({"PDS4-007"})))
    assert "PDS4-007" not in {f.rule for f in ignored.findings}


def test_a_job_or_its_options_by_keyword_give_the_same_run():
    options = {"labels_only": True, "settings": RuleSettings(ignore=frozenset({"PDS4-004"}))}
    by_keywords = validate_paths(SHARED, **options)
    by_job = validate_paths(SHARED, ValidationJob(**options))
    assert by_job.findings == by_keywords.findings and by_job.fail_on == by_keywords.fail_on
    assert any(f.rule == "PDS4-060" for f in by_job.findings)  # the run check ran in both
    assert ValidationJob(strict=True).fail_on == "warning" and ValidationJob().fail_on == "error"
    assert ValidationJob(schema_cache=None, download_schemas=True).download_schemas is False  # no cache, no download
    with pytest.raises(TypeError, match="not both"):
        validate_paths(SHARED, ValidationJob(), strict=True)
    with pytest.raises(TypeError):
        validate_paths(SHARED, stirct=True)
