"""A run that finds no label fails, as NASA's validator's does (error.execution.no_products_found):
a CI job pointed at the wrong directory must not pass. Labels are found by content, PDS3 and
PDS4 (.xml, .lblx or any name), so the message names both. Named files under
--skip-non-labels are the pre-commit hook's case: a commit that changes only ordinary .xml
files has nothing to check and passes; a named directory never does."""

from __future__ import annotations

import shutil
from pathlib import Path

from helpers import run_cli

BUNDLE = Path(__file__).parent / "data" / "nasa_validate" / "github482" / "bundle2"


def test_a_directory_of_data_without_labels_is_an_error(tmp_path):
    """github482's data_spectra without its labels: a CSV and an empty foo.xml."""
    data = tmp_path / "data_spectra"
    data.mkdir()
    shutil.copy(BUNDLE / "data_spectra" / "kgrs_calibrated_spectra_per1.csv", data)
    shutil.copy(BUNDLE / "data_spectra" / "foo.xml", data)
    result = run_cli("validate", "--offline", data)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.strip() == f"pdsgen: error: no PDS3 or PDS4 label found under {data}"


def test_pds4_labels_of_any_name_are_found(tmp_path):
    """The same bundle with .lblx labels (github482's bundle1 layout) is checked, not empty."""
    copy = Path(shutil.copytree(BUNDLE, tmp_path / "bundle1"))
    for label in copy.rglob("*.xml"):
        if label.stat().st_size:
            label.rename(label.with_suffix(".lblx"))
    result = run_cli("validate", "--offline", "--labels-only", copy)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "3 file(s) checked" in result.stdout


def test_named_non_labels_under_skip_non_labels_pass(tmp_path):
    shutil.copy(BUNDLE / "data_spectra" / "foo.xml", tmp_path / "foo.xml")
    result = run_cli("validate", "--skip-non-labels", tmp_path / "foo.xml")
    assert result.returncode == 0 and "0 file(s) checked" in result.stdout
