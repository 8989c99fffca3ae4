"""Benchmark: `pdsgen batch` of 16 small sets on 1 worker vs one worker per core.

Each set is a DTM, an orthoimage and their Extras (three jobs), from generated
rasters, in its own directory as in an archive release. The same manifest runs
twice into fresh directories, through the CLI as a user runs it: `--workers 1`,
then `--workers <cores>`. Printed side by side: wall time, jobs per minute, the
speed-up (the target is at least 0.8 x cores), and per worker the peak memory of
its own process and of the largest job it ran (each job runs in a child process;
its peak RSS is recorded in summary.json).

Run: .venv/bin/python bench/batch.py [--sets 16] [--size 512]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pdsgen.synthetic import make_scene, write_geotiff


def write_sets(folder: Path, sets: int, size: int) -> Path:
    """SETS scenes of SIZE x SIZE posts and the manifest that turns each into a DTM, ortho and Extras."""
    (folder / "input").mkdir(parents=True)
    entries = ['[batch]\nmemory = "1 GB"\n']
    for n in range(sets):
        scene = make_scene(size, size, seed=n)
        elevation = np.where(np.isnan(scene.elevation), np.nanmean(scene.elevation), scene.elevation)
        write_geotiff(folder / "input" / f"dtm{n}.tif", elevation.astype("float32"), scene.transform, scene.crs, None)
        write_geotiff(folder / "input" / f"ortho{n}.tif", scene.reflectance, scene.transform, scene.crs, None)
        entries.append(f"""
[[dtm]]
input = "input/dtm{n}.tif"
product_id = "SET{n}_DTM"
outdir = "set{n}"
[[ortho]]
input = "input/ortho{n}.tif"
product_id = "SET{n}_ORTHO"
outdir = "set{n}"
[[extras]]
id = "set{n}_extras"
after = ["SET{n}_DTM", "SET{n}_ORTHO"]
outdir = "set{n}/extras"
""")
    manifest = folder / "batch.toml"
    manifest.write_text("".join(entries), encoding="utf-8")
    return manifest


def run_batch(manifest: Path, outdir: Path, workers: int) -> tuple[float, dict]:
    start = time.perf_counter()
    proc = subprocess.run([Path(sys.executable).parent / "pdsgen", "batch", manifest, "-o", outdir,
                           "--workers", str(workers)], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"pdsgen batch failed:\n{proc.stderr}")
    summary = json.loads((outdir / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    return seconds, summary


def per_worker(summary: dict) -> list[tuple[str, float, float, int]]:
    """(worker, its process's peak MB, its largest job's peak MB, jobs run) per worker."""
    rows: dict[str, list] = {}
    for job in summary["jobs"]:
        row = rows.setdefault(job["worker"], [0.0, 0.0, 0])
        row[0] = max(row[0], job["worker_peak_mb"])
        row[1] = max(row[1], job["peak_mb"])
        row[2] += 1
    return [(worker, *values) for worker, values in sorted(rows.items())]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sets", type=int, default=16)
    parser.add_argument("--size", type=int, default=512, help="posts per side of each raster")
    args = parser.parse_args()
    cores = os.cpu_count() or 1
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-batch-") as tmp:
        manifest = write_sets(Path(tmp), args.sets, args.size)
        results = {workers: run_batch(manifest, Path(tmp) / f"out{workers}", workers) for workers in (1, cores)}
    jobs = len(results[1][1]["jobs"])
    print(f"pdsgen batch: {args.sets} sets of {args.size} x {args.size} (DTM + ortho + Extras = {jobs} jobs)")
    print(f"  machine: {cores} cores, load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after "
          "(other processes' load lowers the speed-up)")
    print(f"  {'workers':>8s} {'wall s':>9s} {'jobs/min':>9s}")
    for workers, (seconds, _) in results.items():
        print(f"  {workers:8d} {seconds:9.2f} {jobs / seconds * 60:9.1f}")
    speedup = results[1][0] / results[cores][0]
    print(f"  speed-up with {cores} workers: {speedup:.2f} x ({speedup / cores:.2f} x cores; target >= 0.80)")
    for workers, (_, summary) in results.items():
        print(f"  peak memory per worker, {workers} worker(s): worker process MB / largest job MB / jobs")
        for worker, own, job, count in per_worker(summary):
            print(f"    {worker:28s} {own:8.1f} {job:8.1f} {count:5d}")


if __name__ == "__main__":
    main()
