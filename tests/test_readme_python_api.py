"""The README's Python API example runs as written, with the one import path each name has."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np

import docs_text

from helpers import ORIGINS, elevation_array, write_raster


def _python_blocks(section: str) -> list[str]:
    body = docs_text.section(section)
    return re.findall(r"```python\n(.*?)```", body, re.S)


def test_python_api_example_runs_as_written(tmp_path):
    crs, transform = ORIGINS["equirectangular"]
    write_raster(tmp_path / "my_dtm.tif", elevation_array(40, 30, seed=4), crs, transform)
    image = np.linspace(0.05, 0.25, 40 * 30, dtype=np.float32).reshape(40, 30)
    write_raster(tmp_path / "my_ortho.tif", image, crs, transform)
    docs_text.walkthrough_params(tmp_path)  # the params file the example names, as the walk-through writes it
    (example,) = _python_blocks("Python API")
    result = subprocess.run([sys.executable, "-c", example], cwd=tmp_path, capture_output=True, text=True,
                            timeout=300)
    assert result.returncode == 0, result.stderr
    summary_line, report_line = result.stdout.splitlines()
    assert summary_line.startswith(str(Path("delivery") / "MY_DTM.IMG")) and "40 x 30" in summary_line
    assert "0 error(s), 0 warning(s)" in report_line
    written = {p.name for p in (tmp_path / "delivery").iterdir()}
    assert {"MY_DTM.IMG", "MY_ORTHO.JP2", "MY_ORTHO.LBL", "extras"} <= written
