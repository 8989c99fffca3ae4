"""Benchmark `pdsgen validate`: labels/s on the genuine-label regression corpus and on 10,000
copies of it (one process and --jobs), label-only rate and data-check throughput, side by side
with `pvl.load` alone, a plain read of the same files, and `gdalinfo -stats` (GDAL's own pass
over the data).

Usage: python bench/validate.py [--copies 10000] [--jobs N] [--labels 1000] [--size 8000]
                                [--repeat 3] [--corpus-only]

The corpus runs go through the streaming path the command line uses (directory walk, every
rule, a JSON report written to /dev/null); the 10,000 copies are laid out as 65 copies of the
corpus tree, so SET rules see real directories. Target (issue 9): >= 300 labels/s on 2 cores.

Inputs are generated in a temporary directory: DTM products written by pdsgen (three
projections, attached labels) copied to --labels files, and one --size x --size float32
DTM. Each variant runs in a fresh process that times its own loop (interpreter start-up and
imports are not charged to it) and reports its own peak RSS (VmHWM); gdalinfo's peak RSS
comes from /usr/bin/time.
Targets (issue 5): >= 200 labels/s label-only; data checks >= half the plain-read rate.
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

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))
sys.path.insert(0, str(REPO / "tests"))

CHILD = r"""
import json, sys, time
from pathlib import Path
mode, listing = sys.argv[1], sys.argv[2]
files = Path(listing).read_text().split("\n")
if mode.startswith("pdsgen"):
    from pdsgen.validate import validate_paths, rules
    from pdsgen.validate.report import Tally, write_stream
    from pdsgen.validate.runner import iter_reports
    rules()  # imports of every rule family, outside the timed loop
    validate_paths([files[0]], labels_only=True)  # and the dictionary, loaded once per process
elif mode == "pvl":
    import pvl
start = time.perf_counter()
if mode.startswith("pdsgen-stream"):
    jobs = int(mode.rsplit(":", 1)[1])
    with open("/dev/null", "w") as sink:
        tally = write_stream(iter_reports(files, jobs=jobs), "json", sink, Tally())
    print(json.dumps({"files": tally.files}), file=sys.stderr)
elif mode == "pdsgen-labels":
    report = validate_paths(files, labels_only=True)
    assert len(report.files) == len(files)
elif mode == "pdsgen-data":
    report = validate_paths(files)
    assert not [f for f in report.findings if f.severity == "error"], report.findings
    assert "IMG-007" not in report.rule_ids()
elif mode == "pvl":
    for f in files:
        try:
            pvl.load(f)
        except Exception:  # genuine labels pvl cannot parse (PDS2/SFDU, binary after END) still cost their read
            pass
elif mode == "read":
    for f in files:
        with open(f, "rb") as fh:
            while fh.read(8 << 20):
                pass
else:
    raise SystemExit(mode)
seconds = time.perf_counter() - start
# VmHWM is this process's own peak (rusage would include the forking parent's pages)
hwm = next(l for l in open("/proc/self/status") if l.startswith("VmHWM")).split()[1]
print(json.dumps({"seconds": seconds, "peak_mb": int(hwm) / 1024}))
"""


def run_child(mode: str, files: list[Path], workdir: Path) -> tuple[float, float]:
    """(seconds for the loop, peak RSS MB) of one fresh process."""
    listing = workdir / "files.txt"
    listing.write_text("\n".join(map(str, files)))
    env = dict(os.environ, PYTHONPATH=str(REPO / "src"))
    proc = subprocess.Popen([sys.executable, "-c", CHILD, mode, str(listing)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=env)
    out, err = proc.communicate()
    if proc.returncode != 0:
        raise SystemExit(f"{mode} failed:\n{err.decode(errors='replace')}")
    result = json.loads(out)
    return result["seconds"], result["peak_mb"]


def gdalinfo_stats(path: Path) -> tuple[float, float]:
    aux = Path(str(path) + ".aux.xml")
    aux.unlink(missing_ok=True)
    # /usr/bin/time measures gdalinfo's own peak RSS (a fork of this big process would not)
    start = time.perf_counter()
    proc = subprocess.run(["/usr/bin/time", "-f", "%M", "gdalinfo", "-stats", str(path)],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    aux.unlink(missing_ok=True)
    if proc.returncode != 0:
        raise SystemExit(f"gdalinfo -stats failed: {proc.stderr}")
    return seconds, int(proc.stderr.strip().splitlines()[-1]) / 1024.0


def best(fn, repeat: int):
    return min((fn() for _ in range(repeat)), key=lambda r: r[0])


def make_labels(workdir: Path, count: int) -> list[Path]:
    from test_validate_support import make_dtm

    (workdir / "src").mkdir()
    seeds = [make_dtm(workdir / "src", kind, lines=20 + i, samples=30 + i, name=f"p{i}")
             for i, kind in enumerate(("equirectangular", "polar", "sinusoidal"))]
    out = workdir / "labels"
    out.mkdir()
    files = []
    for i in range(count):
        target = out / f"P{i:05d}.IMG"
        shutil.copyfile(seeds[i % len(seeds)], target)
        files.append(target)
    return files


def copy_real_labels(workdir: Path, count: int) -> list[Path]:
    """Copies of the corpus's real mission labels (1-28 KB, many keywords), if present."""
    real = sorted((REPO.parent / "shared" / "corpus" / "real").glob("*"))
    if not real:
        return []
    out = workdir / "real"
    out.mkdir()
    files = []
    for i in range(count):
        target = out / f"{i:05d}_{real[i % len(real)].name}"
        shutil.copyfile(real[i % len(real)], target)
        files.append(target)
    return files


def make_big_dtm(workdir: Path, size: int) -> Path:
    import rasterio
    from rasterio.windows import Window

    from pdsgen.dtm import write_dtm

    from helpers import ORIGINS

    crs, transform = ORIGINS["equirectangular"]
    source = workdir / "big.tif"
    rng = np.random.default_rng(0)
    with rasterio.open(source, "w", driver="GTiff", width=size, height=size, count=1, dtype="float32",
                       crs=crs, transform=transform, nodata=-32768.0, tiled=True, blockxsize=512,
                       blockysize=512) as ds:
        step = 512
        for row in range(0, size, step):
            h = min(step, size - row)
            block = (rng.normal(-3000, 300, (h, size))).astype("float32")
            if row == 0:
                block[0, :100] = -32768.0
            ds.write(block, 1, window=Window(0, row, size, h))
    product = write_dtm(source, workdir / "big", product_id="BIG_DTM")
    source.unlink()
    return product.path


GENUINE = REPO / "tests" / "data" / "genuine_pds3"


def corpus_copies(workdir: Path, count: int) -> tuple[Path, int]:
    """`count` labels as whole copies of the corpus tree (the last copy cut short)."""
    labels = sorted(p for p in GENUINE.rglob("*") if p.is_file() and p.suffix != ".md")
    root = workdir / "copies"
    made = 0
    for copy in range(-(-count // len(labels))):
        for path in labels:
            if made == count:
                return root, made
            target = root / f"copy{copy:03d}" / path.relative_to(GENUINE)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(path, target)
            made += 1
    return root, made


def bench_corpus(workdir: Path, copies: int, jobs: int, repeat: int) -> None:
    n = sum(1 for p in GENUINE.rglob("*") if p.is_file() and p.suffix != ".md")
    root, made = corpus_copies(workdir, copies)
    print(f"pdsgen validate on genuine PDS3 labels (all rules, data checks on, JSON report), {os.cpu_count()} cores")
    print(f"  {'':42s} {'labels/s':>10s} {'seconds':>9s} {'peak MB':>9s}")
    rates = []
    for name, target, count in ((f"regression corpus ({n} labels)", GENUINE, n),
                                (f"{made} copies of it", root, made)):
        for j in sorted({1, jobs}):
            sec, peak = best(lambda t=target, j=j: run_child(f"pdsgen-stream:{j}", [t], workdir), repeat)
            label = f"{name}, {'one process' if j == 1 else f'--jobs {j}'}"
            print(f"  {label:42s} {count / sec:10.0f} {sec:9.2f} {peak:9.1f}")
            rates.append((count, j, count / sec))
    # pvl.load is slow on the copies' largest labels (minutes for 10,000): the baseline runs on
    # the corpus itself, and the ratio compares rates
    files = sorted(p for p in GENUINE.rglob("*") if p.is_file() and p.suffix != ".md")
    sec, peak = best(lambda: run_child("pvl", files, workdir), repeat)
    pvl_rate = n / sec
    print(f"  {'pvl.load alone on the corpus (baseline)':42s} {pvl_rate:10.0f} {sec:9.2f} {peak:9.1f}")
    for count, j, rate in rates:
        where = "corpus" if count == n else "copies"
        print(f"  pdsgen rate / pvl.load rate, {where}, {'one process' if j == 1 else f'--jobs {j}'}: "
              f"{rate / pvl_rate:.2f}x")
    best_rate = max(r for c, _, r in rates if c == made)
    print(f"  target >= 300 labels/s on 2 cores: {'met' if best_rate >= 300 else 'NOT met'} "
          f"({best_rate:.0f} labels/s on the copies)")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--copies", type=int, default=10000)
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--labels", type=int, default=1000)
    parser.add_argument("--size", type=int, default=8000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--corpus-only", action="store_true", help="only the genuine-corpus runs")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
        workdir = Path(tmp)
        bench_corpus(workdir, args.copies, args.jobs, args.repeat)
        if args.corpus_only:
            return 0
        print()
        labels = make_labels(workdir, args.labels)
        n = len(labels)
        ours = best(lambda: run_child("pdsgen-labels", labels, workdir), args.repeat)
        pvl_only = run_child("pvl", labels, workdir)  # once: pvl reads ~30 labels/s
        plain = best(lambda: run_child("read", labels, workdir), args.repeat)
        print(f"Label-only validation of {n} labels (attached-label .IMG files)")
        print(f"  {'':30s} {'labels/s':>10s} {'peak MB':>9s}")
        for name, (sec, mb) in (("pdsgen validate --labels-only", ours), ("pvl.load alone", pvl_only),
                                ("plain read of the files", plain)):
            print(f"  {name:30s} {n / sec:10.0f} {mb:9.1f}")
        print(f"  ratio pdsgen/pvl.load: {pvl_only[0] / ours[0]:.2f}x the rate   (target: >= 200 labels/s: "
              f"{'met' if n / ours[0] >= 200 else 'NOT met'})")
        real = copy_real_labels(workdir, n)
        if real:
            ours_real = best(lambda: run_child("pdsgen-labels", real, workdir), args.repeat)
            pvl_real = run_child("pvl", real, workdir)
            print(f"  on {n} copies of the corpus's real mission labels: pdsgen {n / ours_real[0]:.0f} labels/s, "
                  f"pvl.load {n / pvl_real[0]:.0f} labels/s")

        big = make_big_dtm(workdir, args.size)
        mb = big.stat().st_size / 1e6
        run_child("read", [big], workdir)  # warm the page cache for every variant alike
        data = best(lambda: run_child("pdsgen-data", [big], workdir), args.repeat)
        read = best(lambda: run_child("read", [big], workdir), args.repeat)
        label = best(lambda: run_child("pvl", [big], workdir), args.repeat)
        gdal = best(lambda: gdalinfo_stats(big), args.repeat)
        print(f"\nData checks on a {args.size} x {args.size} float32 DTM ({mb:.0f} MB)")
        print(f"  {'':30s} {'MB/s':>10s} {'seconds':>9s} {'peak MB':>9s}")
        for name, (sec, peak) in (("pdsgen validate (all rules)", data), ("plain read of the file", read),
                                  ("pvl.load (label only)", label), ("gdalinfo -stats", gdal)):
            print(f"  {name:30s} {mb / sec:10.0f} {sec:9.2f} {peak:9.1f}")
        ratio = read[0] / data[0]
        print(f"  pdsgen / plain read throughput: {ratio:.2f}   (target >= 0.5: "
              f"{'met' if ratio >= 0.5 else 'NOT met'}); pdsgen / gdalinfo -stats: {gdal[0] / data[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
