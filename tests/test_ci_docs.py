"""The CI recipes the documentation gives (docs/ci.md) work as written: its pre-commit
configuration names the hook this repository defines, its hook command runs, and the GitHub
Actions workflow in docs/ validates a label set and leaves the SARIF file its upload step sends.
tests/test_docs_ci_recipes.py installs each recipe's pdsgen, with the pds4 extra, as it does."""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from affine import Affine

import docs_text
from pdsgen import write_dtm

from helpers import elevation_array, write_raster

ROOT = Path(__file__).resolve().parent.parent
WORKFLOW = ROOT / "docs" / "github-actions-validate.yml"
SECTION = "pre-commit"
BAD_LABEL = (b"PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 80\r\n"
             b"FILE_RECORDS = 2\r\nLABEL_RECORDS = 1\r\nOBJECT = IMAGE\r\nLINES = 1\r\nEND\r\n")


def _section() -> str:
    return docs_text.section(SECTION)


@pytest.fixture
def delivery(tmp_path) -> Path:
    """tmp_path/delivery: a good DTM product; BAD.LBL and pom.xml are added by the tests."""
    source = write_raster(tmp_path / "heights.tif", elevation_array(20, 16),
                          "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs",
                          Affine(1.0, 0, 1000.0, 0, -1.0, 2000.0))
    write_dtm(source, tmp_path / "delivery", product_id="GOOD", params=docs_text.walkthrough_params(tmp_path))
    return tmp_path / "delivery"


def _add_bad(delivery: Path) -> None:
    (delivery / "BAD.LBL").write_bytes(BAD_LABEL)
    (delivery.parent / "pom.xml").write_text('<?xml version="1.0"?>\n<project/>\n')


def test_readme_pre_commit_configuration_uses_the_hook_this_repository_defines():
    (block,) = re.findall(r"```yaml\n(.*?)```", _section(), re.S)
    config = yaml.safe_load(block)
    (repo,) = config["repos"]
    defined = {hook["id"] for hook in yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text())}
    assert [hook["id"] for hook in repo["hooks"]] == ["pdsgen-validate"]
    assert set(hook["id"] for hook in repo["hooks"]) <= defined and repo["rev"]


def test_readme_hook_command_runs_as_written(delivery):
    _add_bad(delivery)
    (example,) = [line for block in re.findall(r"```sh\n(.*?)```", _section(), re.S)
                  for line in block.splitlines() if line.startswith("pdsgen ")]
    args = shlex.split(example.split("#", 1)[0])[1:]
    result = subprocess.run([sys.executable, "-m", "pdsgen", *args], cwd=delivery.parent,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 1, result.stderr
    assert "delivery/BAD.LBL:6: error [SYNTAX-005]" in result.stdout and "pom.xml" not in result.stdout


def _validate_step() -> tuple[dict, dict, list[dict]]:
    workflow = yaml.safe_load(WORKFLOW.read_text())
    (job,) = workflow["jobs"].values()
    return workflow, job, job["steps"]


def _run_workflow_validation(cwd: Path) -> subprocess.CompletedProcess:
    """The workflow's validate step, as the runner's bash runs it with the workflow's env."""
    workflow, _, steps = _validate_step()
    (step,) = [s for s in steps if "pdsgen validate" in s.get("run", "")]
    env = {**os.environ, **{k: str(v) for k, v in workflow["env"].items()},
           "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    return subprocess.run(["bash", "-e", "-c", step["run"]], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


def test_workflow_validates_the_set_and_writes_the_sarif_it_uploads(delivery):
    workflow, job, steps = _validate_step()
    assert workflow["permissions"]["security-events"] == "write"
    assert workflow["env"]["LABELS"] == "delivery" and "--labels-only" in workflow["env"]["CHECKS"]
    (install,) = [s for s in steps if s.get("run", "").startswith("python -m pip install")]
    assert "${PDSGEN_SOURCE}[pds4]" in install["run"] and "OWNER" not in WORKFLOW.read_text()
    (upload,) = [s for s in steps if s.get("uses", "").startswith("github/codeql-action/upload-sarif@")]
    assert "always()" in upload["if"] and f"hashFiles('{upload['with']['sarif_file']}')" in upload["if"]

    clean = _run_workflow_validation(delivery.parent)
    assert clean.returncode == 0, clean.stderr
    sarif = json.loads((delivery.parent / upload["with"]["sarif_file"]).read_text())
    assert sarif["version"] == "2.1.0"
    assert not [r for r in sarif["runs"][0]["results"] if r["level"] == "error"]

    _add_bad(delivery)
    failed = _run_workflow_validation(delivery.parent)
    assert failed.returncode == 1  # the job fails; upload still runs (if: always())
    results = json.loads((delivery.parent / upload["with"]["sarif_file"]).read_text())["runs"][0]["results"]
    bad = [r for r in results if r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"].endswith("BAD.LBL")]
    assert {r["ruleId"] for r in bad if r["level"] == "error"} >= {"SYNTAX-005", "IMG-001"}
    # the line a finding names reaches code scanning (the label's first findings by line may be
    # about the whole label: IDN-001, no PRODUCT_ID, at line 1)
    syntax = next(r for r in bad if r["ruleId"] == "SYNTAX-005")
    assert syntax["locations"][0]["physicalLocation"]["region"]["startLine"] == 6
