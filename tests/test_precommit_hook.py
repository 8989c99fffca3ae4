"""The pre-commit hook this repository defines (.pre-commit-hooks.yaml), run as users run
it: a label repository's .pre-commit-config.yaml names pdsgen's repository and revision,
pre-commit installs pdsgen from it into its own environment and runs the hook on the files
it is handed.

The hook repository is a temporary git repository holding this working tree's files
(tracked and new, as they are now), committed there, so the developer's own repository
is never committed to or read at another revision. pre-commit builds the hook's environment
once per repository and revision (pdsgen and its dependencies from the package index or
pip's cache, about half a minute) and both runs below use it, as a user's commits do.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from affine import Affine

from pdsgen import write_dtm

from helpers import elevation_array, run_cli, stated_keywords, write_raster

ROOT = Path(__file__).resolve().parent.parent
PRE_COMMIT = Path(sys.executable).with_name("pre-commit")
GIT_IDENTITY = {"GIT_AUTHOR_NAME": "pdsgen tests", "GIT_AUTHOR_EMAIL": "tests@example.invalid",
                "GIT_COMMITTER_NAME": "pdsgen tests", "GIT_COMMITTER_EMAIL": "tests@example.invalid"}
BAD_LABEL = (b"PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 80\r\n"
             b"FILE_RECORDS = 2\r\nLABEL_RECORDS = 1\r\nOBJECT = IMAGE\r\nLINES = 1\r\nEND\r\n")

needs_tools = pytest.mark.skipif(not PRE_COMMIT.exists() or shutil.which("git") is None,
                                 reason="pre-commit (the test extra) or git is not installed")


def _git(cwd: Path, *args: str) -> None:
    subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True,
                   env={**os.environ, **GIT_IDENTITY})


def _hook_repository(target: Path) -> Path:
    """This working tree's files as they are now, committed in a new repository."""
    listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                            cwd=ROOT, check=True, capture_output=True).stdout.decode().split("\0")
    for name in filter(None, listed):
        source = ROOT / name
        if source.is_file():  # a file deleted in the working tree is left out, as it will be
            (target / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target / name)
    _git(target, "init", "-q")
    _git(target, "add", "-A")
    _git(target, "commit", "-q", "-m", "hook repository under test")
    return target


@pytest.fixture(scope="module")
def hook_repo(tmp_path_factory) -> Path:
    return _hook_repository(tmp_path_factory.mktemp("hook") / "pdsgen")


@pytest.fixture(scope="module")
def project(tmp_path_factory, hook_repo) -> Path:
    """A repository of labels: a good DTM (.IMG, attached label), a bad detached label,
    and files the hook is handed but must pass over (a Maven pom.xml, a bare .img); its
    .pre-commit-config.yaml names the hook repository at its commit."""
    root = tmp_path_factory.mktemp("project")
    revision = subprocess.run(["git", "rev-parse", "HEAD"], cwd=hook_repo, check=True, capture_output=True,
                              text=True).stdout.strip()
    (root / ".pre-commit-config.yaml").write_text(yaml.safe_dump(
        {"repos": [{"repo": str(hook_repo), "rev": revision, "hooks": [{"id": "pdsgen-validate"}]}]}))
    source = write_raster(root.parent / "heights.tif", elevation_array(20, 16),
                          "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs",
                          Affine(1.0, 0, 1000.0, 0, -1.0, 2000.0))
    write_dtm(source, root / "good", product_id="GOOD", params=stated_keywords())  # as a producer makes it
    (root / "bad").mkdir()
    (root / "bad" / "BAD.LBL").write_bytes(BAD_LABEL)
    (root / "pom.xml").write_text('<?xml version="1.0"?>\n<project><name>x</name></project>\n')
    (root / "raw.img").write_bytes(bytes(range(256)) * 4)
    _git(root, "init", "-q")
    _git(root, "add", "-A")
    return root


def _run_hook(project: Path, *files: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(PRE_COMMIT), "run", "pdsgen-validate", "--color", "never", "--files", *files],
        cwd=project, capture_output=True, text=True, timeout=900,
        env={**os.environ, **GIT_IDENTITY, "PRE_COMMIT_HOME": str(project.parent / "pre-commit-home")},
    )


def test_hook_definition_names_the_label_suffixes_and_one_serial_run():
    (hook,) = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text())
    assert hook["id"] == "pdsgen-validate" and hook["language"] == "python"
    assert hook["entry"] == "pdsgen validate --skip-non-labels"
    assert hook["require_serial"] is True  # the set checks see every changed file of a directory
    pattern = re.compile(hook["files"])
    for name in ("a/B.LBL", "b.lbl", "h1234_0000_dt4.img", "X.IMG", "label.xml"):
        assert pattern.search(name), name
    for name in ("in.tif", "notes.txt", "x.jp2"):
        assert not pattern.search(name), name


@needs_tools
def test_a_good_label_passes_the_hook_and_non_labels_are_passed_over(project):
    result = _run_hook(project, "good/GOOD.IMG", "pom.xml", "raw.img")
    output = result.stdout + result.stderr
    assert result.returncode == 0, output
    assert "pdsgen validate" in output and "Passed" in output


@needs_tools
def test_a_bad_label_fails_the_hook_with_its_findings_shown(project):
    result = _run_hook(project, "bad/BAD.LBL", "good/GOOD.IMG", "pom.xml")
    output = result.stdout + result.stderr
    assert result.returncode == 1, output
    assert "Failed" in output
    assert "bad/BAD.LBL:6: error [SYNTAX-005]" in output
    good = [line for line in output.splitlines() if line.startswith("good/GOOD.IMG")]
    assert good and not [line for line in good if " error " in line or " warning " in line]
    assert "pom.xml" not in output.split("Failed", 1)[1]  # passed over, not reported
    assert "2 file(s) checked" in output


def test_skip_non_labels_passes_over_what_a_directory_search_passes_over(project):
    """What the hook relies on, without pre-commit: named non-labels are skipped (only with
    the option), labels are checked, and a run with nothing left passes."""
    plain = run_cli("validate", project / "pom.xml", project / "raw.img")
    assert plain.returncode == 1 and "pom.xml" in plain.stdout and "raw.img" in plain.stdout
    skipped = run_cli("validate", "--skip-non-labels", project / "pom.xml", project / "raw.img")
    assert skipped.returncode == 0, skipped.stdout + skipped.stderr
    assert skipped.stdout.strip() == "0 file(s) checked: 0 error(s), 0 warning(s), 0 info - OK"
    mixed = run_cli("validate", "--skip-non-labels", "--format", "sarif", project / "pom.xml",
                    project / "bad" / "BAD.LBL", project / "good" / "GOOD.IMG")
    assert mixed.returncode == 1
    import json

    results = json.loads(mixed.stdout)["runs"][0]["results"]
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in results}
    assert any(uri.endswith("BAD.LBL") for uri in uris) and not any(uri.endswith("pom.xml") for uri in uris)
    # a named directory without labels is still a usage error: a CI job pointed at nothing must not pass
    (project.parent / "empty").mkdir(exist_ok=True)
    empty = run_cli("validate", "--skip-non-labels", project.parent / "empty")
    assert empty.returncode == 2 and "no PDS3 or PDS4 label found" in empty.stderr


def test_skip_non_labels_keeps_pds4_labels(tmp_path):
    source = write_raster(tmp_path / "heights.tif", elevation_array(20, 16),
                          "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs",
                          Affine(1.0, 0, 1000.0, 0, -1.0, 2000.0))
    product = write_dtm(source, tmp_path / "out", product_id="PDS4_DTM", label="pds4")
    assert product.pds4_label_path is not None
    result = run_cli("validate", "--skip-non-labels", product.pds4_label_path)
    assert "1 file(s) checked" in result.stdout, result.stdout + result.stderr
