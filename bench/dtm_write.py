"""Benchmark `pdsgen dtm` against `gdal_translate -of PDS4` (raw float32) on one input.

Usage: python bench/dtm_write.py [--size 8000] [--repeat 2] [--memory-size 16000] [--startup-repeat 5]

Both tools read the same GeoTIFF and write raw float32 image data plus a label;
pdsgen also computes VALID_MINIMUM/MAXIMUM and maps nodata in the same pass.
Target: time ratio <= 1.0 with lower peak memory. The two commands run alternately,
--repeat times each (so a change in the machine's load falls on both), each run after
its previous outputs are removed, a sync and a pause; the best of each is compared,
and every run's wall and CPU seconds are printed. With --memory-size it also
converts a larger raster and checks that pdsgen's peak RSS stays under 300 MB.

First it prints the start-up of each command: `pdsgen --version`, `--help`, a 64 x 64
DTM end to end (target <= 0.25 s) beside gdal_translate of the same raster, and
`pdsgen validate` of that product; wall and CPU seconds, best of --startup-repeat.
pdsgen's modules are byte-compiled first, as a pip install does (an environment with
PYTHONDONTWRITEBYTECODE would otherwise compile them on every start).
"""

from __future__ import annotations

import argparse
import compileall
import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import rasterio
from affine import Affine

import pdsgen

from _measure import Run, best_of, measure, print_side_by_side

CRS = "+proj=eqc +lat_ts=-5 +lon_0=180 +R=3396190 +units=m +no_defs"


def make_input(path: Path, size: int) -> Path:
    """A float32 DTM written strip by strip, so the bench itself stays small in memory."""
    profile = {"driver": "GTiff", "width": size, "height": size, "count": 1, "dtype": "float32",
               "crs": CRS, "transform": Affine(1.0, 0, 6100000.0, 0, -1.0, -560000.0),
               "nodata": -9999.0, "tiled": True, "blockxsize": 512, "blockysize": 512}
    rng = np.random.default_rng(0)
    with rasterio.open(path, "w", **profile) as dataset:
        for row in range(0, size, 512):
            rows = min(512, size - row)
            block = (-4000 + rng.normal(0, 30, (rows, size))).astype(np.float32)
            block[:, :7] = -9999.0
            dataset.write(block, 1, window=((row, row + rows), (0, size)))
    return path


def fastest(command: list[str], repeat: int, outputs: list[str] | None = None) -> Run:
    """Best of REPEAT runs (start-up: no sync or pause between runs, outputs removed)."""
    runs = []
    for _ in range(repeat):
        for path in map(Path, outputs or []):
            if path.is_dir():
                shutil.rmtree(path)
            else:
                path.unlink(missing_ok=True)
        runs.append(measure(command))
    return min(runs, key=lambda run: run.seconds)


def alternate(ours: list[str], ours_outputs: list[str], baseline: list[str], baseline_outputs: list[str],
              repeat: int) -> tuple[list[Run], list[Run]]:
    """REPEAT runs of each command, alternating (pdsgen, GDAL, pdsgen, ...), so that a change
    in the machine's load falls on both; each run as best_of treats it (its previous
    outputs removed, a sync and a pause first), the same for both tools."""
    ours_runs, baseline_runs = [], []
    for _ in range(repeat):
        ours_runs.append(best_of(ours, 1, ours_outputs))
        baseline_runs.append(best_of(baseline, 1, baseline_outputs))
    return ours_runs, baseline_runs


def fastest_run(runs: list[Run]) -> Run:
    return min(runs, key=lambda run: run.seconds)


def startup(work: Path, repeat: int) -> None:
    """Start-up of each command, and a 64 x 64 DTM end to end beside gdal_translate."""
    compileall.compile_dir(str(Path(pdsgen.__file__).parent), quiet=1)
    source = make_input(work / "tiny.tif", 64)
    pdsgen_cmd = [sys.executable, "-m", "pdsgen"]
    rows = [
        ("pdsgen --version", fastest([*pdsgen_cmd, "--version"], repeat)),
        ("pdsgen --help", fastest([*pdsgen_cmd, "--help"], repeat)),
        ("pdsgen dtm 64 x 64", fastest([*pdsgen_cmd, "dtm", str(source), "-o", str(work / "tiny"), "-q"], repeat,
                                       [str(work / "tiny")])),
        ("gdal_translate -of PDS4 64 x 64", fastest(["gdal_translate", "-q", "-of", "PDS4", "-co",
                                                     "IMAGE_FORMAT=RAW", str(source), str(work / "tiny.xml")],
                                                    repeat, [str(work / "tiny.xml"), str(work / "tiny.img")])),
        ("pdsgen validate (that .IMG)", fastest([*pdsgen_cmd, "validate", str(work / "tiny" / "TINY.IMG"), "-q"],
                                                repeat)),
    ]
    print(f"Start-up, best of {repeat} (load average {os.getloadavg()[0]:.1f})")
    print(f"  {'':32s} {'wall s':>8s} {'CPU s':>8s}")
    for name, run in rows:
        print(f"  {name:32s} {run.seconds:8.3f} {run.cpu_seconds:8.3f}")
    dtm = rows[2][1]
    print(f"  pdsgen dtm 64 x 64 end to end: {dtm.seconds:.3f} s "
          f"(target <= 0.25 s: {'met' if dtm.seconds <= 0.25 else 'NOT met'})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=8000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--memory-size", type=int, default=0, help="also check peak RSS on SIZE x SIZE")
    parser.add_argument("--startup-repeat", type=int, default=5, help="runs of each start-up (0: skip)")
    args = parser.parse_args()
    if shutil.which("gdal_translate") is None:
        raise SystemExit("gdal_translate not found: install GDAL's command-line tools (Debian: gdal-bin)")
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
        work = Path(tmp)
        if args.startup_repeat:
            startup(work, args.startup_repeat)
        source = make_input(work / "dtm.tif", args.size)
        ours_runs, gdal_runs = alternate(
            [sys.executable, "-m", "pdsgen", "dtm", str(source), "-o", str(work / "ours"), "--product-id", "BENCH"],
            [str(work / "ours")],
            ["gdal_translate", "-q", "-of", "PDS4", "-co", "IMAGE_FORMAT=RAW", str(source), str(work / "gdal.xml")],
            [str(work / "gdal.xml"), str(work / "gdal.img")],
            args.repeat)
        ours, baseline = fastest_run(ours_runs), fastest_run(gdal_runs)
        print_side_by_side(f"DTM write, {args.size} x {args.size} float32 "
                           f"({args.size * args.size * 4 / 2**20:.0f} MiB), best of {args.repeat} alternating runs",
                           ours, baseline, "gdal_translate -of PDS4")
        print(f"  CPU s: pdsgen {ours.cpu_seconds:.2f}, gdal_translate {baseline.cpu_seconds:.2f}, "
              f"ratio {ours.cpu_seconds / baseline.cpu_seconds:.2f} (load average {os.getloadavg()[0]:.1f}: "
              "on a shared machine the CPU ratio is the steadier figure)")
        print("  every run, wall/CPU s: pdsgen " + ", ".join(f"{r.seconds:.2f}/{r.cpu_seconds:.2f}" for r in ours_runs)
              + "; gdal_translate " + ", ".join(f"{r.seconds:.2f}/{r.cpu_seconds:.2f}" for r in gdal_runs))
        if args.memory_size:
            (work / "dtm.tif").unlink()
            shutil.rmtree(work / "ours", ignore_errors=True)
            big = make_input(work / "big.tif", args.memory_size)
            big_ours = best_of([sys.executable, "-m", "pdsgen", "dtm", str(big), "-o", str(work / "big"),
                                "--product-id", "BIG"], 1, [str(work / "big")])
            big_gdal = best_of(["gdal_translate", "-q", "-of", "PDS4", "-co", "IMAGE_FORMAT=RAW", str(big),
                                str(work / "big.xml")], 1, [str(work / "big.xml"), str(work / "big.img")])
            print_side_by_side(f"DTM write, {args.memory_size} x {args.memory_size} float32 "
                               f"({args.memory_size ** 2 * 4 / 2**20:.0f} MiB)", big_ours, big_gdal,
                               "gdal_translate -of PDS4")
            verdict = "OK" if big_ours.peak_mb < 300 else "OVER the 300 MB target"
            print(f"  pdsgen peak RSS {big_ours.peak_mb:.0f} MB at {args.memory_size} x {args.memory_size} "
                  f"({verdict}; {ours.peak_mb:.0f} MB at {args.size} x {args.size})")


if __name__ == "__main__":
    main()
