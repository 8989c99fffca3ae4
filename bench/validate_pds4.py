"""Benchmark PDS4 label validation: labels/s schema-only and with Schematron, side by side
with lxml parsing the same labels (the floor: no validation at all) and `gdalinfo` opening
a sample of them (GDAL's own reading of a PDS4 label).

Usage: python bench/validate_pds4.py [--labels 2000] [--jobs 2] [--repeat 2]

Inputs are generated in a temporary directory: three small PDS4 DTMs written by pdsgen
(one per projection), each copied with its data file into --labels directories. Every
variant runs `validate_paths(..., labels_only=True)` in a fresh process that times its
own call, including compiling the schemas once per worker process (the cost a CI run pays),
and reports both its wall time and the CPU time of itself and its workers: on a shared
machine the rate of dedicated cores is labels / CPU-seconds x jobs.
Schema-only is what a machine without saxonche gets. Targets (issue 15): >= 500 labels/s
schema-only and >= 200 labels/s with Schematron, on 2 cores.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))
sys.path.insert(0, str(REPO / "tests"))

CHILD = r"""
import json, resource, sys, time
from pathlib import Path
mode, root, jobs = sys.argv[1], sys.argv[2], int(sys.argv[3])
from pdsgen.pds4 import schematron
if mode == "schema-only":
    schematron.available = lambda: False
if mode == "lxml":
    from lxml import etree
    files = sorted(Path(root).rglob("*.xml"))
    start, cpu_start = time.perf_counter(), time.process_time()
    for f in files:
        etree.parse(str(f))
    count = len(files)
else:
    from pdsgen.validate import validate_paths
    start, cpu_start = time.perf_counter(), time.process_time()
    report = validate_paths([root], labels_only=True, jobs=jobs)
    errors = [f for f in report.findings if f.severity == "error"]
    assert not errors, errors[:3]
    count = len(report.files)
children = resource.getrusage(resource.RUSAGE_CHILDREN)
cpu = time.process_time() - cpu_start + children.ru_utime + children.ru_stime  # workers: all their time
print(json.dumps({"seconds": time.perf_counter() - start, "cpu": cpu, "labels": count}))
"""


def make_labels(workdir: Path, count: int) -> Path:
    import numpy as np

    from pdsgen.dtm import write_dtm

    from helpers import ORIGINS, elevation_array, write_raster

    products = []
    for name, (crs, transform) in ORIGINS.items():
        source = write_raster(workdir / f"{name}.tif", elevation_array(64, 64).astype(np.float32), crs, transform)
        written = write_dtm(source, workdir / "src" / name, product_id=f"BENCH_{name.upper()}", label="pds4")
        products.append(written.pds4_label_path)
    root = workdir / "labels"
    for i in range(count):
        product = products[i % len(products)]
        target = root / f"{i:05d}"
        target.mkdir(parents=True)
        shutil.copy(product, target)
        shutil.copy(product.with_suffix(".img"), target)
    return root


def run_child(mode: str, root: Path, jobs: int) -> tuple[float, float, int]:
    """(wall seconds, CPU seconds of the process and its workers, labels) of one run."""
    result = subprocess.run([sys.executable, "-c", CHILD, mode, str(root), str(jobs)], capture_output=True,
                            text=True, check=True, env={"PYTHONPATH": str(REPO / "src"), "PATH": "/usr/bin:/bin"})
    data = json.loads(result.stdout.strip().splitlines()[-1])
    return data["seconds"], data["cpu"], data["labels"]


def gdalinfo_rate(root: Path, sample: int) -> float | None:
    if shutil.which("gdalinfo") is None:
        return None
    files = sorted(root.rglob("*.xml"))[:sample]
    start = time.perf_counter()
    for f in files:
        subprocess.run(["gdalinfo", str(f)], capture_output=True, check=True)
    return len(files) / (time.perf_counter() - start)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--labels", type=int, default=2000)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-pds4-") as tmp:
        workdir = Path(tmp)
        root = make_labels(workdir, args.labels)
        rates = {}
        for mode, jobs in (("lxml", 1), ("schema-only", args.jobs), ("schematron", args.jobs)):
            seconds, cpu, labels = min(run_child(mode, root, jobs) for _ in range(args.repeat))
            # On a shared machine the wall rate says more about the neighbours than about us:
            # labels per CPU-second times the cores is the rate of `jobs` dedicated cores.
            rates[mode] = labels / cpu * jobs
            print(f"{mode:<12} jobs={jobs}  {labels} labels: wall {seconds:6.2f} s = {labels / seconds:7.1f} labels/s;"
                  f" CPU {cpu:6.2f} s = {rates[mode]:7.1f} labels/s on {jobs} dedicated core(s)", flush=True)
        gdal = gdalinfo_rate(root, 100)
        if gdal is not None:
            print(f"{'gdalinfo':<12} jobs=1  100 labels, one process each: wall {gdal:7.1f} labels/s")
        print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
        print(f"schema-only: {rates['schema-only']:.0f} labels/s on {args.jobs} cores (target 500), "
              f"{rates['schema-only'] / rates['lxml']:.2f} x lxml parse-only on one")
        print(f"schematron:  {rates['schematron']:.0f} labels/s on {args.jobs} cores (target 200), "
              f"{rates['schematron'] / rates['lxml']:.2f} x lxml parse-only on one")
        ok = rates["schema-only"] >= 500 and rates["schematron"] >= 200
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
