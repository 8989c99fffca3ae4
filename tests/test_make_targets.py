"""The Makefile's test targets name what exists: `make check`'s subset is files of this suite,
and the README names both targets as a new user meets them."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _variable(name: str) -> list[str]:
    text = (ROOT / "Makefile").read_text().replace("\\\n", " ")
    (value,) = re.findall(rf"^{name} :=(.*)$", text, re.M)
    return value.split()


def test_the_quick_check_names_test_files_of_the_suite():
    quick = _variable("QUICK")
    assert len(quick) >= 6
    for name in quick:
        assert (ROOT / name).is_file() and name.startswith("tests/test_"), name


def test_both_targets_run_the_suite_the_same_way_and_the_readme_names_them():
    assert _variable("TEST_RUN")[:3] == ["$(PY)", "-m", "pytest"]
    readme = (ROOT / "README.md").read_text()
    assert "make test" in readme and "make check" in readme
