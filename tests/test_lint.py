"""The code base stays ruff clean (the project's style rule), checked in CI."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def test_ruff_clean():
    ruff = shutil.which("ruff") or str(Path(__import__("sys").executable).parent / "ruff")
    if not Path(ruff).exists():
        pytest.skip("ruff is not installed")
    result = subprocess.run([ruff, "check", "src", "tests", "bench", "tools"], cwd=REPO, capture_output=True,
                            text=True)
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_clean():
    """`mypy src` (configured in pyproject.toml: no unused `type: ignore`) reports nothing."""
    mypy = Path(__import__("sys").executable).parent / "mypy"
    if not mypy.exists():
        pytest.skip("mypy is not installed")
    result = subprocess.run([str(mypy), "src"], cwd=REPO, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
