"""A user's install: the wheel in a fresh virtual environment, without test extras.

`make test` installs pdsgen with its test extras, which pull in packages that a
plain `pip install .` does not (glymur's undeclared `packaging` hid that way).
These tests install the built wheel the way a user does and run the commands a
user runs first. They need the package index pip is configured with; pip's cache
keeps repeated runs short.
"""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.transform import from_origin

import docs_text

REPO = Path(__file__).resolve().parents[1]
PIP_TIMEOUT = 600


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    build = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(out), str(REPO)],
        capture_output=True, text=True, timeout=PIP_TIMEOUT,
    )
    assert build.returncode == 0, build.stderr
    return next(out.glob("pdsgen-*.whl"))


def _plain_install(python: str, wheel: Path, where: Path) -> Path:
    """A fresh venv from `python` with only the wheel and what it declares; returns its bin/."""
    made = subprocess.run([python, "-m", "venv", str(where)], capture_output=True, text=True, timeout=120)
    assert made.returncode == 0, made.stderr
    pip = subprocess.run(
        [str(where / "bin" / "python"), "-m", "pip", "install", "-q", "--disable-pip-version-check", str(wheel)],
        capture_output=True, text=True, timeout=PIP_TIMEOUT,
    )
    assert pip.returncode == 0, pip.stderr[-2000:]
    return where / "bin"


def _run(command: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {key: value for key, value in os.environ.items() if not key.startswith(("PYTHON", "VIRTUAL_ENV"))}
    return subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=600, env=env)


def _assert_clean(result: subprocess.CompletedProcess[str]) -> None:
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert "Traceback" not in result.stderr, result.stderr


def test_plain_wheel_install_runs_demo_and_validate(wheel, tmp_path):
    bin_dir = _plain_install(sys.executable, wheel, tmp_path / "venv")
    pip_list = _run([str(bin_dir / "python"), "-m", "pip", "list", "--format=freeze"], tmp_path).stdout.lower()
    assert "pytest" not in pip_list and "pdr==" not in pip_list  # really no test extras
    _assert_clean(_run([str(bin_dir / "pdsgen"), "demo", "demo"], tmp_path))
    validated = _run([str(bin_dir / "pdsgen"), "validate", "--strict", "demo"], tmp_path)
    _assert_clean(validated)
    assert "0 error(s)" in validated.stdout


def _oldest_supported_python() -> str | None:
    """A Python 3.10 interpreter on this machine (the floor requires-python claims), if any."""
    found = shutil.which("python3.10")
    candidates = ([found] if found else []) + sorted(glob.glob("/root/.pyenv/versions/3.10*/bin/python"))
    for candidate in candidates:
        probe = subprocess.run([candidate, "-c", "import sys, venv; print(sys.version_info[:2])"],
                               capture_output=True, text=True)
        if probe.returncode == 0 and probe.stdout.strip() == "(3, 10)":
            return candidate
    return None


def test_python_floor_3_10_installs_and_writes_a_product(wheel, tmp_path):
    python = _oldest_supported_python()
    if python is None:
        pytest.skip("no Python 3.10 interpreter on this machine: the floor is not tested here")
    bin_dir = _plain_install(python, wheel, tmp_path / "venv310")
    dtm = tmp_path / "dtm.tif"
    heights = np.linspace(-4000, -3900, 64 * 48, dtype=np.float32).reshape(48, 64)
    with rasterio.open(dtm, "w", driver="GTiff", width=64, height=48, count=1, dtype="float32",
                       crs="+proj=eqc +R=3396190 +units=m +no_defs",
                       transform=from_origin(1000.0, -2000.0, 2.0, 2.0)) as dataset:
        dataset.write(heights, 1)
    # the README walk-through's params.toml, as a user writes it: its TOML exercises tomli (the 3.10
    # stand-in for tomllib), and it states every identification keyword, so --strict passes
    params = docs_text.walkthrough_params(tmp_path)
    made = _run([str(bin_dir / "pdsgen"), "dtm", str(dtm), "-o", "out", "--product-id", "FLOOR_TEST",
                 "--params", str(params)], tmp_path)
    _assert_clean(made)
    _assert_clean(_run([str(bin_dir / "pdsgen"), "validate", "--strict", "out"], tmp_path))
    label = (tmp_path / "out" / "FLOOR_TEST.IMG").read_bytes()[:4000]
    assert b'PRODUCER_FULL_NAME' in label and b"JANE DOE" in label


def test_missing_openjpeg_is_one_line_and_leaves_nothing(tmp_path):
    """glymur told (through its own configuration file) that there is no OpenJPEG."""
    config = tmp_path / "config" / "glymur"
    config.mkdir(parents=True)
    (config / "glymurrc").write_text("[library]\nopenjp2: None\n")
    image = tmp_path / "ortho.tif"
    with rasterio.open(image, "w", driver="GTiff", width=32, height=32, count=1, dtype="uint8",
                       crs="+proj=eqc +R=3396190 +units=m +no_defs",
                       transform=from_origin(0.0, 0.0, 1.0, 1.0)) as dataset:
        dataset.write(np.full((32, 32), 100, np.uint8), 1)
    env = {**os.environ, "XDG_CONFIG_HOME": str(tmp_path / "config")}
    for command in (["ortho", str(image), "-o", str(tmp_path / "out"), "--product-id", "X"],
                    ["demo", str(tmp_path / "demo")]):
        result = subprocess.run([sys.executable, "-m", "pdsgen", *command], capture_output=True, text=True,
                                env=env, cwd=tmp_path, timeout=120)
        assert result.returncode == 2, result.stderr
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and "OpenJPEG" in lines[0] and "libopenjp2-7" in lines[0], result.stderr
        assert not (tmp_path / "out").exists() and not (tmp_path / "demo").exists()
