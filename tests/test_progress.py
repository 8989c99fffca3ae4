"""Progress on long work: a bar under a terminal, nothing when piped, --quiet or --json
(real `pdsgen dtm` / `pdsgen ortho` processes; the terminal is a pseudo-terminal)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from affine import Affine

from pdsgen import progress

from helpers import (
    CRS_EQUIRECTANGULAR,
    elevation_array,
    stated_params,
    stderr_on_a_terminal,
    write_raster,
)

SIDE = 2048  # 4.2 million pixels: large work (progress.LARGE_WORK_PIXELS)
TRANSFORM = Affine(1.0, 0, 6099776.0, 0, -1.0, -563110.0)


@pytest.fixture(scope="module")
def large(tmp_path_factory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("large")
    assert progress.is_large(SIDE * SIDE)
    dtm, ortho = folder / "dtm.tif", folder / "ortho.tif"
    write_raster(dtm, elevation_array(SIDE, SIDE)[None], CRS_EQUIRECTANGULAR, TRANSFORM)
    image = np.random.default_rng(3).integers(1, 255, (1, SIDE, SIDE)).astype("uint8")
    write_raster(ortho, image, CRS_EQUIRECTANGULAR, TRANSFORM)
    return {"dtm": dtm, "ortho": ortho, "params": stated_params(folder)}


@pytest.mark.parametrize("command, unit", [("dtm", "lines"), ("ortho", "tiles")])
def test_a_bar_on_a_terminal_and_nothing_when_piped(large, tmp_path, command, unit):
    code, shown = stderr_on_a_terminal(*[command, str(large[command]), "-o", str(tmp_path / "tty"),
                                         "--params", str(large["params"])])
    assert code == 0, shown
    assert "100%" in shown and f" {unit}" in shown and "[#" in shown
    assert shown.endswith("\r\033[K")  # the bar is cleared; the result line follows on stdout
    piped = subprocess.run([sys.executable, "-m", "pdsgen", command, str(large[command]), "-o",
                            str(tmp_path / "piped"), "--params", str(large["params"])], capture_output=True, text=True)
    assert piped.returncode == 0 and piped.stderr == ""


def test_extras_of_several_products_count_them_on_a_terminal(large, tmp_path):
    code, shown = stderr_on_a_terminal(*["extras", str(large["dtm"]), str(large["ortho"]), "-o",
                                         str(tmp_path / "extras")])
    assert code == 0, shown
    assert "2/2 products" in shown or "1/2 products" in shown


@pytest.mark.parametrize("flag", ["--quiet", "--json"])
def test_no_bar_with_quiet_or_json(large, tmp_path, flag):
    code, shown = stderr_on_a_terminal(*["ortho", str(large["ortho"]), "-o", str(tmp_path / "out"), flag,
                                         "--params", str(large["params"])])
    assert code == 0 and shown == ""


def test_the_library_reports_only_to_an_installed_reporter(large, tmp_path):
    from pdsgen import write_ortho

    seen: list[tuple[int, int, str]] = []
    write_ortho(large["ortho"], tmp_path / "silent")  # no reporter: nothing to call, nothing printed
    with progress.reporting(lambda done, total, unit: seen.append((done, total, unit))):
        write_ortho(large["ortho"], tmp_path / "reported")
    assert seen[-1] == (16, 16, "tiles") and [d for d, _, _ in seen] == list(range(1, 17))


def test_a_bar_of_unknown_total_is_a_count_and_every_bar_is_one_drawing():
    """Validation finds files while it checks them: the line is a count until the end."""
    import io

    shown = io.StringIO()
    bar = progress.TerminalBar(shown)
    bar(1, 0, "files checked")
    bar(2, 0, "files checked")  # within a tenth of a second: not redrawn
    assert shown.getvalue() == "\r\033[K1 files checked" and bar.visible
    bar.close()
    assert shown.getvalue().endswith("\r\033[K") and not bar.visible
    assert progress.bar_text(3, 4) == "[" + "#" * 22 + "." * 8 + "]" and progress.bar_text(9, 4).count("#") == 30


def test_validate_counts_files_on_a_terminal_and_clears_the_count(tmp_path):
    from pdsgen import write_dtm

    for name in ("A", "B"):
        source = write_raster(tmp_path / f"{name}.tif", elevation_array(64, 48)[None], CRS_EQUIRECTANGULAR,
                              TRANSFORM)
        write_dtm(source, tmp_path / "set", product_id=f"DTM_{name}")
    code, shown = stderr_on_a_terminal(*["validate", str(tmp_path / "set")])
    assert code == 0, shown
    assert "1 file(s) checked" in shown and shown.endswith("\r\033[K")
    quiet_code, quiet = stderr_on_a_terminal(*["validate", "--quiet", str(tmp_path / "set")])
    assert quiet_code == 0 and quiet == ""
