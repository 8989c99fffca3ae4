"""The CI recipes of docs/ci.md, installed and run as they are written, on a label set with
PDS4 labels checked under --strict: the GitHub Actions workflow's install and validate steps
(pdsgen from its own source in the repository, with the pds4 extra, in a fresh environment),
and the pre-commit configuration (pre-commit installing the hook's repository with its
additional dependencies). Without the pds4 extra, --strict fails every PDS4 label
(PDS4-007: Schematron could not run), so a clean run shows the extra is installed.

Each installs pdsgen and its dependencies into a new environment (a minute or more; pip's
cache keeps repeated runs short), from the package index pip is configured with."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

import docs_text
from test_precommit_hook import GIT_IDENTITY, PRE_COMMIT, _git, _hook_repository

from helpers import ORIGINS, elevation_array, write_raster

ROOT = Path(__file__).resolve().parents[1]
WORKFLOW = ROOT / "docs" / "github-actions-validate.yml"


def _label_set(root: Path, with_data: bool) -> Path:
    """root/delivery: a DTM and an orthoimage with PDS3 and PDS4 labels, made by pdsgen, with their
    Extras; without data, only the labels (.LBL, .xml) stay, as in a repository of labels."""
    crs, transform = ORIGINS["equirectangular"]
    source = root.parent / f"{root.name}-inputs"
    source.mkdir()
    write_raster(source / "my_dtm.tif", elevation_array(40, 30, seed=3), crs, transform)
    write_raster(source / "my_ortho.tif", elevation_array(40, 30, seed=4, dtype="uint8") % 200 + 20, crs, transform)
    params = docs_text.walkthrough_params(source)
    for command in ("dtm", "ortho"):
        made = subprocess.run([sys.executable, "-m", "pdsgen", command, str(source / f"my_{command}.tif"),
                               "-o", str(root / "delivery"), "--label", "both", "--params", str(params)],
                              capture_output=True, text=True, timeout=300)
        assert made.returncode == 0, made.stderr
    if with_data:  # with their Extras, as a delivery has them (the set checks look for them)
        extras = subprocess.run([sys.executable, "-m", "pdsgen", "extras", str(root / "delivery" / "MY_DTM.IMG"),
                                 str(root / "delivery" / "MY_ORTHO.LBL"), "-o", str(root / "delivery" / "extras"),
                                 "--params", str(params)], capture_output=True, text=True, timeout=300)
        assert extras.returncode == 0, extras.stderr
    else:
        for path in (root / "delivery").iterdir():
            if path.suffix.upper() not in {".LBL", ".XML"}:
                path.unlink()
    return root / "delivery"


def _clean_env(bin_dir: Path | None = None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    if bin_dir is not None:
        env["PATH"] = f"{bin_dir}{os.pathsep}{env['PATH']}"
    return env


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_the_actions_workflow_installs_pdsgen_with_pds4_and_validates_a_label_repository(tmp_path):
    workflow = yaml.safe_load(WORKFLOW.read_text())
    (job,) = workflow["jobs"].values()
    runs = [step for step in job["steps"] if "run" in step]
    assert [step["name"] for step in runs][:1] == ["Install pdsgen with its PDS4 extra (Schematron)"]
    repository = tmp_path / "labels"
    _hook_repository((repository / workflow["env"]["PDSGEN_SOURCE"]).resolve())  # the submodule's files
    _label_set(repository, with_data=False)
    venv = tmp_path / "runner-python"
    made = subprocess.run([sys.executable, "-m", "venv", str(venv)], capture_output=True, text=True, timeout=120)
    assert made.returncode == 0, made.stderr
    env = {**_clean_env(venv / "bin"), **{k: str(v) for k, v in workflow["env"].items()}}
    def run(step: dict) -> subprocess.CompletedProcess:  # as the runner's bash runs a step, in the checkout
        return subprocess.run(["bash", "-e", "-c", step["run"]], cwd=repository, env=env, capture_output=True,
                              text=True, timeout=1500)

    for step in runs:
        result = run(step)
        assert result.returncode == 0, f"{step['name']}\n{result.stdout[-3000:]}{result.stderr[-3000:]}"
    assert (venv / "bin" / "pdsgen").exists()
    results = json.loads((repository / "pdsgen.sarif").read_text())["runs"][0]["results"]
    assert not [r for r in results if r["level"] in {"error", "warning"}]
    assert "PDS4-007" not in {r["ruleId"] for r in results}  # Schematron ran (--strict would fail else)
    (validate,) = [step for step in runs if "--output pdsgen.sarif" in step["run"]]
    passed = run(validate)  # the job's log says the run passed, and the failing run's why
    assert passed.stderr.strip().endswith("(strict) - OK") and passed.stderr.startswith("pdsgen.sarif: ")
    broken = b"PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nEND\r\n"  # no RECORD_BYTES: an error
    (repository / "delivery" / "BROKEN.LBL").write_bytes(broken)
    failed = run(validate)
    assert failed.returncode == 1 and failed.stdout == ""
    assert re.fullmatch(r"pdsgen\.sarif: \d+ file\(s\) checked: [1-9]\d* error\(s\), .* - FAILED\n", failed.stderr)


@pytest.mark.skipif(not PRE_COMMIT.exists() or shutil.which("git") is None,
                    reason="pre-commit (the test extra) or git is not installed")
def test_the_pre_commit_configuration_installs_the_hook_with_pds4_and_passes_a_label_set(tmp_path):
    (block,) = re.findall(r"```yaml\n(.*?)```", docs_text.section("pre-commit"), re.S)
    config = yaml.safe_load(block)
    hook_repo = _hook_repository(tmp_path / "pdsgen")
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=hook_repo, capture_output=True, text=True).stdout.strip()
    config["repos"][0].update(repo=str(hook_repo), rev=head)  # the two values the comments say are yours
    project = tmp_path / "project"
    _label_set(project, with_data=True)
    (project / ".pre-commit-config.yaml").write_text(yaml.safe_dump(config))
    _git(project, "init", "-q")
    _git(project, "add", "-A")
    result = subprocess.run([str(PRE_COMMIT), "run", "--all-files", "--verbose", "--color", "never"], cwd=project,
                            capture_output=True, text=True, timeout=1500,
                            env={**_clean_env(), **GIT_IDENTITY, "PRE_COMMIT_HOME": str(tmp_path / "home")})
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "--strict" in config["repos"][0]["hooks"][0]["args"]
    assert "file(s) checked: 0 error(s), 0 warning(s)" in result.stdout and "PDS4-007" not in result.stdout
