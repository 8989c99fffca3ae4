"""--quiet and --verbose on `pdsgen validate` and `pdsgen batch`, through real processes."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

GOOD = b'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = UNDEFINED\r\nPRODUCT_ID = "A"\r\nEND\r\n'
BAD = b'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nPRODUCT_ID = "B"\r\nlowercase_key = 1\r\nEND\r\n'


def pdsgen(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pdsgen", *args], capture_output=True, text=True, cwd=cwd)


@pytest.fixture()
def labels(tmp_path) -> Path:
    folder = tmp_path / "labels"
    folder.mkdir()
    (folder / "A.LBL").write_bytes(GOOD)
    (folder / "B.LBL").write_bytes(BAD)
    return folder


def test_validate_quiet_prints_only_what_fails_the_run(labels):
    full = pdsgen("validate", "--no-config", str(labels))
    quiet = pdsgen("validate", "--no-config", "--quiet", str(labels))
    assert quiet.returncode == full.returncode == 1 and quiet.stderr == ""
    errors = [line for line in full.stdout.splitlines() if ": error [" in line]
    assert errors and quiet.stdout.splitlines() == errors  # no warnings, no summary line
    assert any(": warning [" in line for line in full.stdout.splitlines())
    strict = pdsgen("validate", "--no-config", "--quiet", "--strict", str(labels))
    assert any(": warning [" in line for line in strict.stdout.splitlines())  # warnings fail it now
    clean = pdsgen("validate", "--no-config", "-q", str(labels / "A.LBL"))
    assert (clean.returncode, clean.stdout, clean.stderr) == (0, "", "")


def test_validate_quiet_keeps_a_report_asked_for(labels, tmp_path):
    as_json = pdsgen("validate", "--no-config", "--quiet", "--format", "json", str(labels))
    assert json.loads(as_json.stdout)["summary"]["files"] == 2
    report = tmp_path / "report.txt"
    pdsgen("validate", "--no-config", "--quiet", "--output", str(report), str(labels))
    assert report.read_text() == pdsgen("validate", "--no-config", str(labels)).stdout


def test_validate_verbose_tells_what_it_reads_and_how_long_it_took(labels):
    verbose = pdsgen("validate", "--no-config", "--verbose", str(labels))
    assert verbose.stdout == pdsgen("validate", "--no-config", str(labels)).stdout  # the report unchanged
    told = verbose.stderr
    for expected in ("configuration: none", "data dictionary: pdscat1r102", "rules: ", "baseline: none",
                     "checked 2 file(s) in "):
        assert expected in told, told
    both = pdsgen("validate", "-q", "-v", str(labels))
    assert both.returncode == 2 and len(both.stderr.strip().splitlines()) == 1


def test_batch_quiet_and_verbose(labels, tmp_path):
    manifest = tmp_path / "jobs.toml"
    manifest.write_text(f'[batch]\noutdir = "{tmp_path / "out"}"\n\n[[validate]]\nid = "check"\n'
                        f'inputs = ["{labels / "A.LBL"}"]\nformat = "json"\noutput = "report.json"\n')
    quiet = pdsgen("batch", str(manifest), "--workers", "1", "--quiet")
    assert (quiet.returncode, quiet.stdout, quiet.stderr) == (0, "", ""), quiet.stderr
    verbose = pdsgen("batch", str(manifest), "--workers", "1", "--verbose", "-o", str(tmp_path / "again"))
    assert verbose.returncode == 0, verbose.stderr
    assert "1 job(s) on a local cluster of 1 worker(s)" in verbose.stderr
    assert "check" in verbose.stderr and "1 jobs in " in verbose.stderr  # the plan, the job line, the summary
