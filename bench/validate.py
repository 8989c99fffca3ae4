"""Benchmark `pdsgen validate`: labels/s side by side with a baseline reader of the same
labels, for PDS3 and PDS4.

Usage: python bench/validate.py [--copies 10000] [--jobs N] [--labels 1000] [--size 8000]
                                [--pds4-labels 2000] [--repeat 3]
                                [--only corpus,labels,data,pds4] [--corpus-only]

Sections (all by default; --corpus-only is --only corpus):
- corpus: the 155-label genuine PDS3 regression corpus (tests/data/genuine_pds3) and
  --copies copies of it laid out as copies of the corpus tree (so SET rules see real
  directories), one process and --jobs, through the streaming path the command line uses
  (directory walk, every rule, a JSON report written to /dev/null); baseline `pvl.load` of
  the same labels. Target (issue 9): >= 300 labels/s.
- labels: label-only validation of --labels attached-label DTMs pdsgen wrote (and of copies
  of tests/data/corpus/real) against pvl.load and a plain read. Target (issue
  5): >= 200 labels/s.
- data: data checks on one --size x --size float32 DTM against a plain read of the file and
  `gdalinfo -stats`. Target (issue 5): >= half the plain-read throughput.
- pds4: --pds4-labels PDS4 DTM labels pdsgen wrote, schema-only and with Schematron, against
  lxml parsing the same labels (no validation at all) and gdalinfo opening 100 of them.
  Targets (issue 15): >= 500 labels/s schema-only and >= 200 with Schematron, on 2 cores.
- pds4-suite (with --nasa-suite CHECKOUT, a checkout of NASA-PDS/validate): every PDS4
  label of its regression suite's test data (all IM versions, tables, bundles), validated
  with their data, offline, in one process; against lxml parsing the same labels. NASA's
  validator is a Java program: each run pays a JVM start and its schema loading, which
  this machine cannot measure (no JVM here); pdsgen's figure includes its own start.

Each variant runs in a fresh process that times its own loop (interpreter start-up and
imports are not charged to it; the dictionary, rule table and PDS4 schemas are loaded once
per process, inside the loop for PDS4 as a CI run pays it) and reports its wall time, its
CPU time with its workers', and its own peak RSS (VmHWM). On a shared machine the wall rate
says more about the neighbours than about pdsgen: the CPU rate (labels per CPU-second, times
the processes) is what dedicated cores would give. The load average is printed with each
section.
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

GENUINE = REPO / "tests" / "data" / "genuine_pds3"
SECTIONS = ("corpus", "labels", "data", "pds4", "pds4-suite")

CHILD = r"""
import json, resource, sys, time
from pathlib import Path
mode, listing = sys.argv[1], sys.argv[2]
files = Path(listing).read_text().split("\n")
jobs = int(mode.rsplit(":", 1)[1]) if ":" in mode else 1
if mode.startswith("pdsgen"):
    from pdsgen.validate import validate_paths, rules
    from pdsgen.validate.report import Tally, write_stream
    from pdsgen.validate.runner import iter_reports
    rules()  # imports of every rule family, outside the timed loop
    validate_paths([files[0]], labels_only=True)  # and the dictionary, loaded once per process
elif mode == "pds4-suite":
    from pdsgen.validate import validate_paths
elif mode.startswith("pds4"):
    from pdsgen.validate.pds4 import schematron
    from pdsgen.validate import validate_paths
    if mode.startswith("pds4-schema-only"):
        schematron.available = lambda: False  # what a machine without saxonche gets
elif mode == "pvl":
    import pvl
elif mode == "lxml":
    from lxml import etree
start, cpu_start = time.perf_counter(), time.process_time()
count = len(files)
if mode.startswith("pdsgen-stream"):
    with open("/dev/null", "w") as sink:
        count = write_stream(iter_reports(files, jobs=jobs), "json", sink, Tally()).files
elif mode == "pdsgen-labels":
    report = validate_paths(files, labels_only=True)
    assert len(report.files) == len(files)
elif mode == "pdsgen-data":
    report = validate_paths(files)
    assert not [f for f in report.findings if f.severity == "error"], report.findings
    assert "IMG-007" not in report.rule_ids()
elif mode == "pds4-suite":
    # whatever the labels hold: NASA's cases are meant to fail as often as to pass
    count = len(validate_paths(files).files)
elif mode.startswith("pds4"):
    # the schemas are compiled once per worker process inside the timed call: a CI run pays it
    report = validate_paths(files, labels_only=True, jobs=jobs)
    errors = [f for f in report.findings if f.severity == "error"]
    assert not errors, errors[:3]
    count = len(report.files)
elif mode == "pvl":
    for f in files:
        try:
            pvl.load(f)
        except Exception:  # genuine labels pvl cannot parse (PDS2/SFDU, binary after END) still cost their read
            pass
elif mode == "lxml":
    for f in files:
        etree.parse(f)
elif mode == "read":
    for f in files:
        with open(f, "rb") as fh:
            while fh.read(8 << 20):
                pass
else:
    raise SystemExit(mode)
seconds = time.perf_counter() - start
children = resource.getrusage(resource.RUSAGE_CHILDREN)  # --jobs workers, once they are reaped
cpu = time.process_time() - cpu_start + children.ru_utime + children.ru_stime
# VmHWM is this process's own peak (rusage would include the forking parent's pages)
hwm = next(l for l in open("/proc/self/status") if l.startswith("VmHWM")).split()[1]
print(json.dumps({"seconds": seconds, "cpu": cpu, "count": count, "peak_mb": int(hwm) / 1024}))
"""


class Result:
    """One child run: wall seconds, CPU seconds (with workers), items done, peak RSS."""

    def __init__(self, seconds: float, cpu: float, count: int, peak_mb: float) -> None:
        self.seconds, self.cpu, self.count, self.peak_mb = seconds, cpu, count, peak_mb

    @property
    def rate(self) -> float:
        return self.count / self.seconds

    def cpu_rate(self, processes: int) -> float:
        """Items per second on `processes` dedicated cores: per CPU-second, times the cores."""
        return self.count / self.cpu * processes if self.cpu > 0 else float("nan")


def run_child(mode: str, files: list[Path], workdir: Path) -> Result:
    """One fresh process running `mode` over `files`."""
    listing = workdir / "files.txt"
    listing.write_text("\n".join(map(str, files)))
    env = dict(os.environ, PYTHONPATH=str(REPO / "src"))
    proc = subprocess.run([sys.executable, "-c", CHILD, mode, str(listing)], capture_output=True, text=True,
                          env=env)
    if proc.returncode != 0:
        raise SystemExit(f"{mode} failed:\n{proc.stderr}")
    data = json.loads(proc.stdout.strip().splitlines()[-1])
    return Result(data["seconds"], data["cpu"], data["count"], data["peak_mb"])


def best(fn, repeat: int) -> Result:
    return min((fn() for _ in range(repeat)), key=lambda r: r.seconds)


def load_line() -> str:
    one, five, _ = os.getloadavg()
    return f"load average {one:.2f} (5 min {five:.2f}) on {os.cpu_count()} cores"


def gdalinfo_stats(path: Path) -> Result:
    aux = Path(str(path) + ".aux.xml")
    aux.unlink(missing_ok=True)
    # /usr/bin/time measures gdalinfo's own peak RSS (a fork of this big process would not)
    start = time.perf_counter()
    proc = subprocess.run(["/usr/bin/time", "-f", "%M %U %S", "gdalinfo", "-stats", str(path)],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    aux.unlink(missing_ok=True)
    if proc.returncode != 0:
        raise SystemExit(f"gdalinfo -stats failed: {proc.stderr}")
    peak_kb, user, system = proc.stderr.strip().splitlines()[-1].split()
    return Result(seconds, float(user) + float(system), 1, int(peak_kb) / 1024.0)


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
    real = sorted((REPO / "tests" / "data" / "corpus" / "real").glob("*"))
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

    from pdsgen import write_dtm

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


def make_pds4_labels(workdir: Path, count: int) -> Path:
    """`count` directories, each with one of three small PDS4 DTMs (label and data)."""
    from pdsgen import write_dtm

    from helpers import ORIGINS, elevation_array, write_raster

    products = []
    for name, (crs, transform) in ORIGINS.items():
        source = write_raster(workdir / f"{name}.tif", elevation_array(64, 64).astype(np.float32), crs, transform)
        written = write_dtm(source, workdir / "pds4src" / name, product_id=f"BENCH_{name.upper()}", label="pds4")
        products.append(written.pds4_label_path)
    root = workdir / "pds4"
    for i in range(count):
        product = products[i % len(products)]
        target = root / f"{i:05d}"
        target.mkdir(parents=True)
        shutil.copy(product, target)
        shutil.copy(product.with_suffix(".img"), target)
    return root


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


def _row(name: str, cells: list[str]) -> None:
    print(f"  {name:34s}" + "".join(f"{c:>15s}" for c in cells))


def bench_corpus(workdir: Path, copies: int, jobs: int, repeat: int) -> None:
    labels = sorted(p for p in GENUINE.rglob("*") if p.is_file() and p.suffix != ".md")
    root, made = corpus_copies(workdir, copies)
    print(f"pdsgen validate on genuine PDS3 labels (all rules, data checks on, JSON report); {load_line()}")
    print("  labels/s: wall (CPU: per CPU-second x processes, the rate of dedicated cores)")
    modes = sorted({1, jobs})
    _row("", [("one process" if j == 1 else f"--jobs {j}") for j in modes] + ["pvl.load", "pdsgen/pvl"])
    # pvl.load takes minutes for 10,000 of these labels: its rate on the corpus stands for
    # the copies too (they are the same labels)
    pvl = best(lambda: run_child("pvl", labels, workdir), repeat)
    verdicts: list[tuple[str, list[Result]]] = []
    for name, target, count in ((f"corpus ({len(labels)} labels)", GENUINE, len(labels)),
                                (f"{made} copies of it", root, made)):
        runs = [best(lambda t=target, j=j: run_child(f"pdsgen-stream:{j}", [t], workdir), repeat) for j in modes]
        verdicts.append((name, runs))
        assert all(r.count == count for r in runs), (name, [r.count for r in runs])
        cells = [f"{r.rate:.0f} ({r.cpu_rate(j):.0f})" for r, j in zip(runs, modes, strict=True)]
        cells.append(f"{pvl.rate:.1f} ({pvl.cpu_rate(1):.1f})")
        cells.append(f"{runs[0].rate / pvl.rate:.0f}x")
        _row(name, cells)
        print(f"  {'':34s}  seconds {', '.join(f'{r.seconds:.2f}' for r in runs)};"
              f" peak MB {', '.join(f'{r.peak_mb:.0f}' for r in runs)}")
    for name, runs in verdicts:
        print(f"  target >= 300 labels/s, {name}: " + ", ".join(
            f"{'one process' if j == 1 else f'--jobs {j}'} {'met' if r.rate >= 300 else 'NOT met'} "
            f"({r.rate:.0f} wall, {r.cpu_rate(j):.0f} CPU)" for r, j in zip(runs, modes, strict=True)))
    print(f"  {load_line()} (after)")


def bench_labels(workdir: Path, count: int, repeat: int) -> None:
    labels = make_labels(workdir, count)
    n = len(labels)
    ours = best(lambda: run_child("pdsgen-labels", labels, workdir), repeat)
    pvl_only = run_child("pvl", labels, workdir)  # once: pvl reads ~30 labels/s
    plain = best(lambda: run_child("read", labels, workdir), repeat)
    print(f"Label-only validation of {n} attached-label .IMG files pdsgen wrote; {load_line()}")
    _row("", ["labels/s", "CPU labels/s", "peak MB"])
    for name, r in (("pdsgen validate --labels-only", ours), ("pvl.load alone", pvl_only),
                    ("plain read of the files", plain)):
        _row(name, [f"{n / r.seconds:.0f}", f"{r.cpu_rate(1):.0f}", f"{r.peak_mb:.1f}"])
    print(f"  pdsgen/pvl.load: {pvl_only.seconds / ours.seconds:.1f}x the rate (target >= 200 labels/s: "
          f"{'met' if n / ours.seconds >= 200 else 'NOT met'})")
    real = copy_real_labels(workdir, n)
    if real:
        ours_real = best(lambda: run_child("pdsgen-labels", real, workdir), repeat)
        pvl_real = run_child("pvl", real, workdir)
        print(f"  on {n} copies of tests/data/corpus/real mission labels: pdsgen {ours_real.rate:.0f} labels/s, "
              f"pvl.load {pvl_real.rate:.0f} labels/s ({pvl_real.seconds / ours_real.seconds:.1f}x)")


def bench_data(workdir: Path, size: int, repeat: int) -> None:
    big = make_big_dtm(workdir, size)
    mb = big.stat().st_size / 1e6
    run_child("read", [big], workdir)  # warm the page cache for every variant alike
    data = best(lambda: run_child("pdsgen-data", [big], workdir), repeat)
    read = best(lambda: run_child("read", [big], workdir), repeat)
    label = best(lambda: run_child("pvl", [big], workdir), repeat)
    gdal = best(lambda: gdalinfo_stats(big), repeat)
    print(f"Data checks on a {size} x {size} float32 DTM ({mb:.0f} MB); {load_line()}")
    _row("", ["MB/s", "seconds", "peak MB"])
    for name, r in (("pdsgen validate (all rules)", data), ("plain read of the file", read),
                    ("pvl.load (label only)", label), ("gdalinfo -stats", gdal)):
        _row(name, [f"{mb / r.seconds:.0f}", f"{r.seconds:.2f}", f"{r.peak_mb:.1f}"])
    ratio = read.seconds / data.seconds
    print(f"  pdsgen / plain read throughput: {ratio:.2f}   (target >= 0.5: {'met' if ratio >= 0.5 else 'NOT met'});"
          f" pdsgen / gdalinfo -stats: {gdal.seconds / data.seconds:.2f}")


def gdalinfo_rate(root: Path, sample: int) -> float | None:
    if shutil.which("gdalinfo") is None:
        return None
    files = sorted(root.rglob("*.xml"))[:sample]
    start = time.perf_counter()
    for f in files:
        subprocess.run(["gdalinfo", str(f)], capture_output=True, check=True)
    return len(files) / (time.perf_counter() - start)


def bench_pds4(workdir: Path, count: int, jobs: int, repeat: int) -> None:
    root = make_pds4_labels(workdir, count)
    labels = sorted(root.rglob("*.xml"))
    lxml = best(lambda: run_child("lxml", labels, workdir), repeat)
    print(f"PDS4 label validation of {count} PDS4 DTM labels pdsgen wrote (--labels-only); {load_line()}")
    _row("", ["labels/s", f"CPU, {jobs} cores", "lxml parse", "pdsgen/lxml"])
    for name, mode in (("schema-only (no saxonche)", "pds4-schema-only"), ("with Schematron", "pds4-schematron")):
        r = best(lambda m=mode: run_child(f"{m}:{jobs}", [root], workdir), repeat)
        rate = r.cpu_rate(jobs)
        target = 500 if mode == "pds4-schema-only" else 200
        _row(name, [f"{r.rate:.0f}", f"{rate:.0f}", f"{lxml.cpu_rate(1):.0f}", f"{rate / lxml.cpu_rate(1):.2f}x"])
        print(f"  {'':34s}  target >= {target} labels/s on {jobs} cores: {'met' if rate >= target else 'NOT met'}")
    gdal = gdalinfo_rate(root, 100)
    if gdal is not None:
        print(f"  gdalinfo, one process per label (100 labels): {gdal:.0f} labels/s")


def bench_pds4_suite(workdir: Path, checkout: Path | None, repeat: int) -> None:
    if checkout is None:
        print("pds4-suite: skipped (give --nasa-suite PATH, a checkout of NASA-PDS/validate)")
        return
    from pdsgen.pds4.detect import is_pds4_label

    resources = checkout / "src" / "test" / "resources"
    labels = sorted(p for p in resources.rglob("*") if p.is_file() and p.suffix.lower() in (".xml", ".lblx")
                    and is_pds4_label(p))
    lxml = best(lambda: run_child("lxml", labels, workdir), repeat)
    r = best(lambda: run_child("pds4-suite", labels, workdir), repeat)
    print(f"PDS4 labels of NASA-PDS/validate's regression suite: {len(labels)} labels with their data, "
          f"offline, one process; {load_line()}")
    _row("", ["labels/s", "CPU labels/s", "lxml parse", "pdsgen/lxml"])
    _row("pdsgen validate", [f"{r.rate:.0f}", f"{r.cpu_rate(1):.0f}", f"{lxml.cpu_rate(1):.0f}",
                             f"{r.cpu_rate(1) / lxml.cpu_rate(1):.3f}x"])
    print(f"  {r.seconds:.1f} s wall, {r.cpu:.1f} s CPU, peak RSS {r.peak_mb:.0f} MB")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--copies", type=int, default=10000)
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--labels", type=int, default=1000)
    parser.add_argument("--size", type=int, default=8000)
    parser.add_argument("--pds4-labels", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--only", default=",".join(SECTIONS), help="comma-separated sections: " + ", ".join(SECTIONS))
    parser.add_argument("--corpus-only", action="store_true", help="only the genuine-corpus runs (--only corpus)")
    parser.add_argument("--nasa-suite", type=Path, help="checkout of NASA-PDS/validate (section pds4-suite)")
    args = parser.parse_args()
    sections = ["corpus"] if args.corpus_only else [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = set(sections) - set(SECTIONS)
    if unknown:
        parser.error(f"unknown section(s): {', '.join(sorted(unknown))}")
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
        workdir = Path(tmp)
        for i, section in enumerate(sections):
            if i:
                print()
            if section == "corpus":
                bench_corpus(workdir, args.copies, args.jobs, args.repeat)
            elif section == "labels":
                bench_labels(workdir, args.labels, args.repeat)
            elif section == "data":
                bench_data(workdir, args.size, args.repeat)
            elif section == "pds4":
                bench_pds4(workdir, args.pds4_labels, args.jobs, args.repeat)
            else:
                bench_pds4_suite(workdir, args.nasa_suite, args.repeat)
    return 0


if __name__ == "__main__":
    sys.exit(main())
