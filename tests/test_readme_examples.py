"""The README's HRSC and iMars shell examples run as written, on small synthetic inputs (issue 10)."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys

import numpy as np
from affine import Affine

import docs_text

from helpers import elevation_array, write_raster

SINUSOIDAL = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"
GRID = Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0)


def _examples(section: str) -> list[str]:
    body = docs_text.section(section)
    blocks = re.findall(r"```sh\n(.*?)```", body, re.S)
    return [line for block in blocks for line in block.splitlines() if line.startswith("pdsgen ")]


def test_hrsc_and_imars_examples_run_as_written(tmp_path):
    write_raster(tmp_path / "heights.tif", elevation_array(120, 100, seed=7), SINUSOIDAL, GRID)
    write_raster(tmp_path / "nadir.tif", np.linspace(0.02, 0.3, 120 * 100, dtype=np.float32).reshape(120, 100),
                 SINUSOIDAL, GRID)
    lons, lats = np.arange(69.0, 71.0001, 0.05), np.arange(-16.0, -18.0001, -0.05)
    areoid = (250.0 + 12.5 * lons[None, :] - 40.0 * lats[:, None]).astype(np.float32)
    write_raster(tmp_path / "areoid.tif", areoid, "+proj=longlat +R=3396000 +no_defs",
                 Affine(0.05, 0, lons[0] - 0.025, 0, -0.05, lats[0] + 0.025))
    examples = _examples("HRSC and iMars products")
    assert len(examples) >= 4
    for example in examples:
        args = shlex.split(example)[1:]
        result = subprocess.run([sys.executable, "-m", "pdsgen", *args], cwd=tmp_path, capture_output=True,
                                text=True, timeout=300)
        assert result.returncode == 0, f"{example}\n{result.stderr}"
    written = {p.name for p in (tmp_path / "out").iterdir()}
    assert {"h1234_0000_dt4.img", "h1234_0000_da4.img", "h1234_0000_nd4.img", "h1234_0000_da4_ucl.tif"} <= written


def test_pds4_examples_run_as_written(tmp_path):
    from helpers import ORIGINS

    crs, transform = ORIGINS["equirectangular"]
    write_raster(tmp_path / "my_dtm.tif", elevation_array(40, 30, seed=3), crs, transform)
    write_raster(tmp_path / "ortho_red.tif", np.random.default_rng(5).integers(1, 255, (40, 30)).astype("uint8"),
                 crs, transform)
    write_raster(tmp_path / "hrsc_dtm.tif", elevation_array(40, 30, seed=8), SINUSOIDAL, GRID)
    examples = _examples("PDS4 products")
    assert len(examples) >= 4
    for example in examples:  # in order, as printed: none may need --overwrite
        args = shlex.split(example.split("#", 1)[0])[1:]
        result = subprocess.run([sys.executable, "-m", "pdsgen", *args], cwd=tmp_path,
                                capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, f"{example}\n{result.stderr}"
    pds4 = {p.name for p in (tmp_path / "pds4").iterdir()}
    both = {p.name for p in (tmp_path / "both").iterdir()}
    assert {"MY_DTM.img", "MY_DTM.xml"} <= pds4 and any(name.endswith(".JP2") for name in pds4)
    assert {"MY_DTM.IMG", "MY_DTM.xml", "h1234_0000_dt4.img", "h1234_0000_dt4.xml"} <= both
