"""Benchmark `pdsgen batch`: per-job overhead on tiny jobs, and speed-up on small sets.

Tiny jobs (--tiny 200): that many DTM jobs of 64 x 64 posts through `pdsgen batch
--workers 2` (a LocalCluster), where a job's work is a few tens of ms and the rest is
overhead. Printed side by side: resident job processes (the default) against a new
process per job (`--child-jobs 1`, how every job ran before), in jobs/s (target >= 15)
and CPU seconds of the whole run (client, workers and job processes); then the
per-job overhead: wall time per job on 1 worker less the work time its job process
measured (`work_seconds` in summary.json).

Sets (--sets 16): each set is a DTM, an orthoimage and their Extras (three jobs), from generated
rasters, in its own directory as in an archive release. The same manifest runs
twice into fresh directories, through the CLI as a user runs it: `--workers 1`,
then `--workers <cores>`. Printed side by side: wall time, jobs per minute, the
speed-up (the target is at least 0.8 x cores), and per worker the peak memory of
its own process and of the largest job it ran (each job runs in a child process;
its peak RSS is recorded in summary.json).

Run: .venv/bin/python bench/batch.py [--tiny 200] [--sets 16] [--size 512]   (0 skips a part)
"""

from __future__ import annotations

import argparse
import json
import os
import resource
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


def write_tiny(folder: Path, jobs: int) -> Path:
    """One 64 x 64 DTM and a manifest of JOBS DTM jobs made from it, 20 to a directory."""
    (folder / "input").mkdir(parents=True)
    scene = make_scene(64, 64, seed=1)
    elevation = np.where(np.isnan(scene.elevation), np.nanmean(scene.elevation), scene.elevation)
    write_geotiff(folder / "input" / "dtm.tif", elevation.astype("float32"), scene.transform, scene.crs, None)
    entries = ['[batch]\nmemory = "256 MB"\n']
    entries += [f'[[dtm]]\nid = "d{n}"\ninput = "input/dtm.tif"\nproduct_id = "TINY{n}"\noutdir = "set{n // 20}"\n'
                for n in range(jobs)]
    manifest = folder / "tiny.toml"
    manifest.write_text("\n".join(entries), encoding="utf-8")
    return manifest


def run_batch(manifest: Path, outdir: Path, workers: int, *options: str) -> tuple[float, dict]:
    return timed_batch(manifest, outdir, workers, *options)[:2]


def timed_batch(manifest: Path, outdir: Path, workers: int, *options: str) -> tuple[float, dict, float]:
    """(wall seconds, summary.json, CPU seconds of the run and every process it waited for)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run([Path(sys.executable).parent / "pdsgen", "batch", manifest, "-o", outdir,
                           "--workers", str(workers), *options], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"pdsgen batch failed:\n{proc.stderr}")
    summary = json.loads((outdir / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return seconds, summary, cpu


def tiny_jobs(jobs: int) -> None:
    """Resident job processes vs a process per job on JOBS tiny DTM jobs; per-job overhead."""
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-tiny-") as tmp:
        manifest = write_tiny(Path(tmp), jobs)
        load = os.getloadavg()[0]
        resident = timed_batch(manifest, Path(tmp) / "resident", 2)
        fresh = timed_batch(manifest, Path(tmp) / "fresh", 2, "--child-jobs", "1")
        one = timed_batch(manifest, Path(tmp) / "one", 1)
    print(f"pdsgen batch: {jobs} DTM jobs of 64 x 64 posts, --workers 2 (LocalCluster start included); "
          f"load average {load:.1f} before, {os.getloadavg()[0]:.1f} after")
    print(f"  {'':34s} {'wall s':>8s} {'jobs/s':>8s} {'CPU s':>8s}")
    rows = (("resident job processes", resident), ("a process per job (--child-jobs 1)", fresh))
    for name, (seconds, _, cpu) in rows:
        print(f"  {name:34s} {seconds:8.2f} {jobs / seconds:8.1f} {cpu:8.2f}")
    print(f"  ratio resident/per-job: time {resident[0] / fresh[0]:.2f}, CPU {resident[2] / fresh[2]:.2f}; "
          f"target >= 15 jobs/s: {'met' if jobs / resident[0] >= 15 else 'NOT met'}")
    seconds, summary, _ = one
    work = [j["work_seconds"] for j in summary["jobs"] if j.get("work_seconds") is not None]
    mean_work = sum(work) / len(work)
    print(f"  1 worker: {jobs / seconds:.1f} jobs/s, {seconds / jobs * 1000:.0f} ms a job, of which the job's "
          f"own work {mean_work * 1000:.0f} ms: overhead {(seconds / jobs - mean_work) * 1000:.0f} ms a job "
          f"(cluster start and the first job process's imports spread over {jobs} jobs)")


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
    parser.add_argument("--tiny", type=int, default=200, help="tiny DTM jobs (0: skip)")
    parser.add_argument("--sets", type=int, default=16, help="sets of DTM + ortho + Extras (0: skip)")
    parser.add_argument("--size", type=int, default=512, help="posts per side of each raster")
    args = parser.parse_args()
    if args.tiny:
        tiny_jobs(args.tiny)
    if args.sets:
        sets(args.sets, args.size)


def sets(count: int, size: int) -> None:
    cores = os.cpu_count() or 1
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-batch-") as tmp:
        manifest = write_sets(Path(tmp), count, size)
        results = {workers: run_batch(manifest, Path(tmp) / f"out{workers}", workers) for workers in (1, cores)}
    jobs = len(results[1][1]["jobs"])
    print(f"pdsgen batch: {count} sets of {size} x {size} (DTM + ortho + Extras = {jobs} jobs)")
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
