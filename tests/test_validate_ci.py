"""`pdsgen validate` made for CI, end to end through the command line (a fresh process each):
configuration, baseline, SARIF and GitHub formats, control bytes in every format, files
that are not labels, streaming and --jobs."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree

from pdsgen.validate import runner
from pdsgen.validate.runner import iter_reports

GOOD = (b'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\nOBJECT = TEXT\r\n  NOTE = "a note"\r\n'
        b"  PUBLICATION_DATE = 2020-01-01\r\n  INTERCHANGE_FORMAT = ASCII\r\nEND_OBJECT = TEXT\r\nEND\r\n")
# one error (DICT-004: a record type no reader knows, written with control bytes) and two
# warnings (DICT-001 unknown keyword, FILE-004 a 102-character line)
BAD = (b'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = "STR\x01\x1b[31mEAM\x0c"\r\nOBJECT = TEXT\r\n'
       b'  NOTE = "a note"\r\n  NOTE2 = "' + b"x" * 90 + b'"\r\nEND_OBJECT = TEXT\r\nEND\r\n')


def pdsgen(cwd: Path, *args: str) -> subprocess.CompletedProcess:
    """`python -m pdsgen validate ARGS` run in `cwd`, as a CI job would."""
    return subprocess.run([sys.executable, "-m", "pdsgen", "validate", *args], cwd=cwd, capture_output=True,
                          text=True, timeout=300)


@pytest.fixture
def delivery(tmp_path: Path) -> Path:
    (tmp_path / "new").mkdir()
    (tmp_path / "legacy").mkdir()
    (tmp_path / "new" / "good.lbl").write_bytes(GOOD)
    (tmp_path / "legacy" / "bad.lbl").write_bytes(BAD)
    return tmp_path


def _rules(result: subprocess.CompletedProcess) -> set[tuple[str, str, str]]:
    data = json.loads(result.stdout)
    return {(Path(f["path"]).name, x["rule"], x["severity"]) for f in data["files"] for x in f["findings"]}


def test_configuration_in_pyproject_selects_ignores_and_sets_severity(delivery):
    base = pdsgen(delivery, ".", "--format", "json")
    assert base.returncode == 1
    assert {("bad.lbl", "DICT-004", "error"), ("bad.lbl", "FILE-004", "warning")} <= _rules(base)
    (delivery / "pyproject.toml").write_text(
        '[project]\nname = "archive"\n\n[tool.pdsgen.validate]\nselect = ["DICT", "FILE"]\n'
        'ignore = ["DICT-001"]\nfail-on = "warning"\n'
        '[tool.pdsgen.validate.severity]\n"DICT-004" = "warning"\n'
        '[tool.pdsgen.validate.per-path-ignores]\n"legacy/**" = ["FILE-001"]\n')
    result = pdsgen(delivery, ".", "--format", "json")
    assert _rules(result) == {("bad.lbl", "DICT-004", "warning"), ("bad.lbl", "FILE-004", "warning")}
    assert result.returncode == 1  # fail-on = "warning"
    summary = json.loads(result.stdout)["summary"]
    assert summary["fail_on"] == "warning" and summary["errors"] == 0
    # the command line overrides the configuration
    flags = pdsgen(delivery, ".", "--format", "json", "--fail-on", "error", "--ignore", "FILE-004",
                   "--severity", "DICT-004=info")
    assert _rules(flags) == {("bad.lbl", "DICT-004", "info")} and flags.returncode == 0
    assert pdsgen(delivery, ".", "--no-config", "--format", "json").returncode == 1


def test_configuration_in_pdsgen_toml_and_unknown_ids_are_errors(delivery):
    (delivery / "pdsgen.toml").write_text('[validate]\nignore = ["DICT", "FILE-001"]\n')
    assert _rules(pdsgen(delivery, ".", "--format", "json")) == {("bad.lbl", "FILE-004", "warning")}
    (delivery / "pdsgen.toml").write_text('[validate]\nignore = ["DICT-999"]\n')
    result = pdsgen(delivery, ".")
    assert result.returncode == 2 and not result.stdout
    assert result.stderr.count("\n") == 1 and "unknown rule id(s) DICT-999" in result.stderr
    assert "pdsgen.toml" in result.stderr
    (delivery / "pdsgen.toml").write_text('[validate]\nfail_on = "error"\n')
    assert "unknown setting(s) fail_on" in pdsgen(delivery, ".").stderr
    (delivery / "pdsgen.toml").unlink()
    result = pdsgen(delivery, ".", "--select", "MAP-999")
    assert result.returncode == 2 and "unknown rule id(s) MAP-999" in result.stderr


def test_baseline_reports_only_new_findings(delivery):
    written = pdsgen(delivery, ".", "--write-baseline", "known.json")
    assert written.returncode == 0 and "finding(s) recorded" in written.stdout
    assert json.loads((delivery / "known.json").read_text())["pdsgen_baseline"] == 1
    again = pdsgen(delivery, ".", "--baseline", "known.json", "--strict")
    assert again.returncode == 0, again.stdout
    assert "known (baseline)" in again.stdout
    # a new problem in a new delivery is reported, the legacy ones stay quiet
    (delivery / "new" / "worse.lbl").write_bytes(BAD.replace(b"STR", b"STX"))
    new = pdsgen(delivery, ".", "--baseline", "known.json", "--format", "json")
    assert new.returncode == 1
    assert {(name, rule) for name, rule, _ in _rules(new)} == {
        ("worse.lbl", "DICT-004"), ("worse.lbl", "DICT-001"), ("worse.lbl", "FILE-001"), ("worse.lbl", "FILE-004")}
    assert pdsgen(delivery, ".", "--baseline", "missing.json").returncode == 2


def test_sarif_for_code_scanning(delivery):
    result = pdsgen(delivery, ".", "--format", "sarif", "-o", "out.sarif")
    assert result.returncode == 1 and not result.stdout
    sarif = json.loads((delivery / "out.sarif").read_text())
    assert sarif["version"] == "2.1.0" and len(sarif["runs"]) == 1
    run = sarif["runs"][0]
    rule_ids = {r["id"] for r in run["tool"]["driver"]["rules"]}
    assert {"DICT-004", "FILE-004", "MAP-003"} <= rule_ids
    by_rule = {r["ruleId"]: r for r in run["results"]}
    error = by_rule["DICT-004"]
    assert error["level"] == "error" and "\x1b" not in json.dumps(error)
    location = error["locations"][0]["physicalLocation"]
    assert location["artifactLocation"]["uri"] == "legacy/bad.lbl" and location["region"]["startLine"] == 2
    assert by_rule["FILE-004"]["level"] == "warning"


def test_github_annotations_with_file_and_line(delivery):
    result = pdsgen(delivery, ".", "--format", "github")
    lines = result.stdout.splitlines()
    error = next(line for line in lines if line.startswith("::error "))
    assert error.startswith("::error file=legacy/bad.lbl,line=2,title=DICT-004 RECORD_TYPE::")
    assert any(line.startswith("::warning file=legacy/bad.lbl,line=5,title=FILE-004::") for line in lines)
    assert "\x1b" not in result.stdout and "\x01" not in result.stdout  # escaped as \x1b
    assert lines[-1].endswith("FAILED") and result.returncode == 1


@pytest.mark.parametrize("fmt", ["junit", "json", "sarif", "text"])
def test_every_format_survives_control_bytes(delivery, fmt):
    result = pdsgen(delivery, ".", "--format", fmt, "-o", f"report.{fmt}")
    assert result.returncode == 1, result.stderr
    data = (delivery / f"report.{fmt}").read_bytes()
    if fmt == "junit":
        root = etree.fromstring(data)
        failure = root.find(".//failure")
        assert failure is not None and "\\x1b" in failure.text
    elif fmt == "text":
        assert b"\x1b" not in data and b"\\x1b" in data
    else:
        text = json.dumps(json.loads(data))
        assert "\\u001b" in text or "\\\\x1b" in text


def test_a_file_that_is_not_a_label_gets_one_finding(delivery):
    jp2 = delivery / "new" / "PRODUCT.JP2"
    jp2.write_bytes(b"\x00\x00\x00\x0cjP  \r\n\x87\n" + bytes(range(256)) * 400)
    tif = delivery / "new" / "dem.tif"
    tif.write_bytes(b"II*\x00" + bytes(range(256)) * 40)
    result = pdsgen(delivery, str(jp2), str(tif))
    lines = result.stdout.splitlines()
    assert result.returncode == 1 and len(lines) == 3, result.stdout
    assert "[FILE-013]" in lines[0] and "JPEG 2000" in lines[0] and "TIFF" in lines[1]
    walked = pdsgen(delivery, "new", "--format", "json")  # directory walks skip such files
    assert {Path(f["path"]).name for f in json.loads(walked.stdout)["files"]} == {"good.lbl"}


def test_results_stream_file_by_file(tmp_path, monkeypatch):
    """iter_reports hands on each directory's reports before it checks the next directory."""
    for i in range(4):
        (tmp_path / f"d{i}").mkdir()
        (tmp_path / f"d{i}" / "a.lbl").write_bytes(GOOD)
    checked: list[str] = []
    real = runner.validate_file
    monkeypatch.setattr(runner, "validate_file", lambda path, *a: (checked.append(path.parent.name), real(path, *a))[1])
    reports = iter_reports([tmp_path])
    assert checked == []  # nothing is checked before the first report is asked for
    first = next(reports)
    assert Path(first.path).parent.name == "d0" and len(checked) <= 2
    assert len(list(reports)) == 3 and checked == ["d0", "d1", "d2", "d3"]


def test_jobs_give_the_same_report(delivery):
    one = pdsgen(delivery, ".", "--format", "json")
    two = pdsgen(delivery, ".", "--format", "json", "--jobs", "2")
    assert json.loads(one.stdout) == json.loads(two.stdout)


def test_list_rules_states_the_severity_policy():
    result = subprocess.run([sys.executable, "-m", "pdsgen", "validate", "--list-rules"], capture_output=True,
                            text=True, timeout=120)
    assert result.stdout.startswith("Severity policy: ERROR = a reader would misread the data")
    assert "Data dictionary: pdscat1r102 (generated 2017-09-25)" in result.stdout
    assert "warning for labels pdsgen did not write" in result.stdout


@pytest.mark.parametrize("fmt", ["sarif", "json", "junit", "github", "text"])
def test_a_report_written_to_a_file_still_says_why_the_run_failed_on_stderr(delivery, fmt):
    """The CI recipe (--format sarif --output pdsgen.sarif): without code scanning the job's log
    is all a user sees, so the summary line goes to stderr, failing and passing; -q drops it."""
    failing = pdsgen(delivery, ".", "--no-config", "--format", fmt, "--output", "report.out")
    assert failing.returncode == 1 and failing.stdout == ""
    assert failing.stderr.splitlines() == ["report.out: 2 file(s) checked: 2 error(s), 2 warning(s), 0 info - FAILED"]
    assert (delivery / "report.out").stat().st_size > 0
    passing = pdsgen(delivery, "new", "--no-config", "--strict", "--format", fmt, "--output", "ok.out")
    assert passing.returncode == 0 and passing.stdout == ""
    assert passing.stderr.splitlines() == ["ok.out: 1 file(s) checked: 0 error(s), 0 warning(s), 0 info (strict) - OK"]
    quiet = pdsgen(delivery, ".", "--no-config", "-q", "--format", fmt, "--output", "quiet.out")
    assert (quiet.returncode, quiet.stdout, quiet.stderr) == (1, "", "")
