"""`validate -j N`: the workers share one Saxon child, their parent's (schematron.SharedEngine),
not one each (a compiled PDS4 core Schematron and its engine are about 110 MB a child). The walls
around the engine stay: the limits are counted per label and charged to the label that reached
them, while the other worker's labels are checked by a fresh engine."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pdsgen.validate.pds4 import schematron
from pdsgen.validate.runner import ValidationJob, iter_reports
from scale_bundle import make_bundle
from test_facts_schematron_limits import ENDLESS, LABEL, SCH_NS, _schematron

pytestmark = pytest.mark.skipif(not schematron.available(), reason="needs saxonche")


def _findings(paths: list[Path], **job: object) -> list[tuple[str, str, str]]:
    return [(Path(f.file).name, f.rule, f.message) for report in iter_reports(paths, ValidationJob(**job))
            for f in report.findings]


def test_two_workers_start_one_saxon_child_and_report_what_one_process_does(tmp_path, monkeypatch):
    bundle = make_bundle(tmp_path / "bundle", 6, fault_last=True)
    started = tmp_path / "started"
    start = schematron._Worker.__init__

    def recording(self: schematron._Worker) -> None:  # a file, as the workers are other processes
        with open(started, "a", encoding="utf-8") as log:
            log.write(f"{os.getpid()}\n")
        start(self)

    one = _findings([bundle], schema_cache=None)
    running = schematron._WORKERS.pop(os.getpid(), None)  # this process's engine of the run above
    if running is not None:
        running.stop()
    monkeypatch.setattr(schematron._Worker, "__init__", recording)
    assert _findings([bundle], schema_cache=None, jobs=2) == one
    assert started.read_text(encoding="utf-8").split() == [str(os.getpid())]
    assert any(rule == "PDS4-053" for _, rule, _ in one)  # the planted fault, found by both


def _labels(directory: Path, rules: dict[str, str]) -> Path:
    """A label per Schematron file (its name -> its one assertion), each naming its own file, all
    files in one directory given with --schemas."""
    schemas = directory / "schemas"
    schemas.mkdir(parents=True)
    for name, test in rules.items():
        (schemas / f"{name}.sch").write_text(_schematron(test.replace("'", "&apos;")), encoding="utf-8")
        model = f'<?xml-model href="schemas/{name}.sch" schematypens="{SCH_NS}"?>\n'
        (directory / f"{name}.xml").write_text(
            LABEL.read_text(encoding="utf-8").replace("<Product_", model + "<Product_", 1), encoding="utf-8")
    return schemas


def test_a_label_stopping_the_shared_engine_is_charged_alone(tmp_path, monkeypatch):
    monkeypatch.setattr(schematron, "TIME_LIMIT", 4.0)
    schemas = _labels(tmp_path, {"endless": ENDLESS, "plain": "false()", "plain2": "false()"})
    found = _findings([tmp_path / f"{name}.xml" for name in ("endless", "plain", "plain2")],
                      schemas=(str(schemas),), labels_only=True, jobs=2)
    assert [(name, rule, message) for name, rule, message in found
            if "endless.sch" in message or "MISSION" in message] == [
        ("endless.xml", "PDS4-002", "Schematron endless.sch stopped: it ran past the time limit of 4 s; its rules not "
                                    "checked for this label"),
        ("plain.xml", "PDS4-005", "MISSION RULE FAILED"),
        ("plain2.xml", "PDS4-005", "MISSION RULE FAILED")]
