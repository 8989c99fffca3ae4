"""Ctrl-C: SIGINT to a real `pdsgen` process mid-work exits 130, leaves nothing partial,
and the same command run again (without --overwrite) succeeds."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

from helpers import CRS_EQUIRECTANGULAR, ORIGINS, elevation_array, run_cli, write_raster


def _dtm(path: Path, size: int) -> Path:
    return write_raster(path, elevation_array(size, size), CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1])


def _staging(path: Path) -> bool:
    return path.name.endswith(".part")


def _interrupt_when(args: list[str], outdir: Path, seen: Callable[[Path], bool] = _staging,
                    ) -> subprocess.CompletedProcess:
    """Start `python -m pdsgen ARGS`; send SIGINT once a file in OUTDIR is `seen` (by default
    a staged .part file: it is writing)."""
    process = subprocess.Popen([sys.executable, "-m", "pdsgen", *args], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and process.poll() is None:
        if outdir.is_dir() and any(seen(p) for p in outdir.iterdir()):
            break
        time.sleep(0.005)
    assert process.poll() is None, "finished before it could be interrupted; make the input larger"
    process.send_signal(signal.SIGINT)
    stdout, stderr = process.communicate(timeout=120)
    return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)


def _assert_interrupted(result: subprocess.CompletedProcess, outdir: Path) -> None:
    assert result.returncode == 130, result.stderr
    assert result.stderr.splitlines() == ["pdsgen: interrupted (no partial output left)"], result.stderr
    assert sorted(p.name for p in outdir.iterdir()) == []  # no temporary file, no half set


def test_interrupted_dtm_leaves_nothing_and_reruns(tmp_path):
    source = _dtm(tmp_path / "big.tif", 3000)
    outdir = tmp_path / "out"
    args = ["dtm", str(source), "-o", str(outdir)]
    _assert_interrupted(_interrupt_when(args, outdir), outdir)
    again = run_cli(*args)
    assert again.returncode == 0, again.stderr
    assert [p.suffix for p in outdir.iterdir()] == [".IMG"]


def test_interrupted_extras_leaves_no_half_set(tmp_path):
    """Interrupted once the first product's previews are published, while the second
    renders: they are taken back, so the re-run without --overwrite is not refused."""
    first, second = _dtm(tmp_path / "first.tif", 400), _dtm(tmp_path / "second.tif", 3000)
    outdir = tmp_path / "extras"
    args = ["extras", str(first), str(second), "-o", str(outdir)]

    def first_published(path: Path) -> bool:
        return path.name.startswith("first.") and path.name.endswith(".jpg")

    _assert_interrupted(_interrupt_when(args, outdir, first_published), outdir)
    again = run_cli(*args)
    assert again.returncode == 0, again.stderr
    names = sorted(p.name for p in outdir.iterdir())
    assert "README.TXT" in names, names
    assert {n.split(".")[0] for n in names if n.endswith(".jpg")} == {"first", "second"}, names
