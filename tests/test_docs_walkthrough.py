"""The README's walk-through, run as written: every `pdsgen` command of it, in order, in one
directory holding a user's own DTM and orthoimage GeoTIFFs, and every file it shows (a
```toml block whose first line is `# NAME`) written where it says. It ends with a delivery
that validates clean under --strict, with no text left to be written, and its review page."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np

import docs_text

from helpers import ORIGINS, elevation_array, write_raster


def _pdsgen(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pdsgen", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=600)


def _steps(body: str) -> list[tuple[str, str]]:
    """('file', text) for each file shown, ('run', line) for each command, in reading order."""
    steps = []
    for language, block in re.findall(r"```(sh|toml)\n(.*?)```", body, re.S):
        if language == "toml":
            steps.append(("file", block))
        else:
            steps += [("run", line) for line in block.splitlines() if line.startswith("pdsgen ")]
    return steps


def test_the_walk_through_runs_as_written(tmp_path):
    crs, transform = ORIGINS["equirectangular"]
    write_raster(tmp_path / "my_dtm.tif", elevation_array(120, 90, seed=3), crs, transform)
    write_raster(tmp_path / "my_ortho.tif", np.random.default_rng(5).integers(1, 255, (120, 90)).astype("uint8"),
                 crs, transform)
    steps = _steps(docs_text.section(docs_text.WALK))
    commands = [line for kind, line in steps if kind == "run"]
    assert [shlex.split(line)[1] for line in commands] == [
        "params", "dtm", "ortho", "extras", "validate", "deliver", "validate", "review"]
    for kind, text in steps:
        if kind == "file":
            name = text.splitlines()[0].removeprefix("# ").strip()
            (tmp_path / name).write_text(text, encoding="utf-8")
            continue
        result = _pdsgen(shlex.split(text)[1:], tmp_path)
        assert result.returncode == 0, f"{text}\n{result.stdout}{result.stderr}"
    delivered = [p for p in (tmp_path / "delivery").rglob("*") if p.is_file()]
    left = [p for p in delivered if p.suffix.upper() in {".TXT", ".CAT", ".XML", ".LBL"}
            and "TO BE WRITTEN" in p.read_text(encoding="latin-1")]
    assert not left, left
    review = (tmp_path / "delivery" / "REVIEW.html").read_text(encoding="utf-8")
    assert "Digital terrain models of Melas Chasma" in "".join(
        p.read_text(encoding="latin-1") for p in delivered if p.suffix.upper() in {".TXT", ".CAT", ".XML"})
    assert "TO BE WRITTEN" not in review
