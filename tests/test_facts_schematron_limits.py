"""A Schematron that runs for ever or fills memory (issue 38: a mission dictionary given with
--schemas is trusted to be PDS's kind of file, not to be harmless, and XPath can loop without
reaching outside the label): the validator stops it at a wall-clock or memory limit, says which
Schematron was not run and why, and goes on - the next label is checked by a fresh engine."""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import PDS4_EXAMPLES_DIR
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.catalog import SchemaCatalog
from pdsgen.validate.pds4.label_checks import validate_pds4

pytestmark = pytest.mark.skipif(not schematron.available(), reason="needs saxonche")

SCH_NS = "http://purl.oclc.org/dsdl/schematron"
LABEL = PDS4_EXAMPLES_DIR / "BILQH07S314_D065_T008S02_V02.xml"  # a genuine PDS4 label (provenance in conftest)
# Four billion steps: no file, variable or URL, only time (Saxon has no limit of its own).
ENDLESS = "sum(for $i in 1 to 2000000000, $j in 1 to 2000000000 return $i * $j) = 0"
# Sixteen gigabytes of one string.
HUNGRY = ("string-length(string-join(for $i in 1 to 400000000 return "
          "'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx')) = 0")


def _schematron(test: str) -> str:
    return (f'<sch:schema xmlns:sch="{SCH_NS}" queryBinding="xslt2">'
            '<sch:ns prefix="pds" uri="http://pds.nasa.gov/pds4/pds/v1"/>'
            '<sch:pattern><sch:rule context="pds:Identification_Area">'
            f'<sch:assert test="{test}">MISSION RULE FAILED</sch:assert>'
            '</sch:rule></sch:pattern></sch:schema>')


def _delivery(tmp_path: Path, test: str) -> tuple[Path, Path]:
    """A label naming schemas/mission.sch (given with --schemas) holding one assertion."""
    schemas = tmp_path / "schemas"
    schemas.mkdir(parents=True, exist_ok=True)
    (schemas / "mission.sch").write_text(_schematron(test.replace("'", "&apos;")), encoding="utf-8")
    model = f'<?xml-model href="schemas/mission.sch" schematypens="{SCH_NS}"?>\n'
    label = tmp_path / LABEL.name
    label.write_text(LABEL.read_text(encoding="utf-8").replace("<Product_", model + "<Product_", 1), encoding="utf-8")
    return label, schemas


def _mission_findings(label: Path, schemas: Path) -> list:
    found = validate_pds4(label, SchemaCatalog.build([schemas]), labels_only=True)
    return [f for f in found if "mission.sch" in f.message or "MISSION RULE" in f.message]


def test_an_endless_schematron_is_stopped_at_the_time_limit_and_the_next_label_is_checked(tmp_path, monkeypatch):
    monkeypatch.setattr(schematron, "TIME_LIMIT", 4.0)
    label, schemas = _delivery(tmp_path / "endless", ENDLESS)
    started = time.monotonic()
    found = _mission_findings(label, schemas)
    elapsed = time.monotonic() - started
    assert [(f.rule, f.message) for f in found] == [
        ("PDS4-002", "Schematron mission.sch stopped: it ran past the time limit of 4 s; its rules not checked "
                     "for this label")]
    assert 4.0 <= elapsed < 60.0
    # The stopped engine is gone; a fresh one checks the next label's rules.
    label, schemas = _delivery(tmp_path / "plain", "false()")
    assert [(f.rule, f.message) for f in _mission_findings(label, schemas)] == [("PDS4-005", "MISSION RULE FAILED")]


def test_a_schematron_filling_memory_is_stopped_at_the_memory_limit(tmp_path, monkeypatch):
    monkeypatch.setattr(schematron, "MEMORY_LIMIT", 500 * 2**20)
    label, schemas = _delivery(tmp_path, HUNGRY)
    started = time.monotonic()
    found = _mission_findings(label, schemas)
    assert [(f.rule, f.message) for f in found] == [
        ("PDS4-002", "Schematron mission.sch stopped: it took more than the memory limit of 500 MB; its rules not "
                     "checked for this label")]
    assert time.monotonic() - started < 60.0


def test_the_command_reports_the_stopped_schematron_without_a_traceback(tmp_path):
    """`pdsgen validate` as a user runs it, with its own limits: the hungry rule is stopped,
    the run ends with a report in under a minute."""
    label, schemas = _delivery(tmp_path, HUNGRY)
    shutil.copy(label, tmp_path / "second.xml")  # a second label: the run goes on after the first
    started = time.monotonic()
    result = subprocess.run([sys.executable, "-m", "pdsgen", "validate", "--labels-only", "--schemas", str(schemas),
                             str(label), str(tmp_path / "second.xml")],
                            capture_output=True, text=True, timeout=120)
    assert time.monotonic() - started < 60.0
    streams = result.stdout + result.stderr
    assert "Traceback" not in streams, streams[-2000:]
    assert streams.count("Schematron mission.sch stopped: it took more than the memory limit of 768 MB") == 2, \
        streams[-2000:]
