"""Benchmark validation at archive scale: bundles of 1k-100k table products and single
tables of millions of records, in one process, with -j 2 and on a Dask cluster.

Usage: python bench/validate_scale.py [--products 1000[,10000,100000]]
                                      [--records 1000000[,10000000]] [--only bundle,table]
                                      [--modes one,j2,cluster] [--bundle-name bundle_scale.xml]
                                      [--workdir DIR] [--keep]

The bundle (tests/scale_bundle.py): copies of an IM 1.24 Table_Character product of 304
records x 16 fields (the shape of the NASA test product issue 51 was measured on; made
here, not copied), 1,000 to a directory, one data collection and its inventory, the
bundle label named --bundle-name. Its last product has a value out of its Field_Statistics
range and is missing from the inventory: each run must report both (a planted fault in the
last product found). The table: one product of --records records of the same 16 fields.

Each run is the command line (`pdsgen validate --offline`, a JSON report to /dev/null)
in a fresh process. Reported: wall time; CPU time (user + system) of the command and its
worker processes - the figure to compare on a machine others share; peak memory summed
over the processes (the client, the -j workers, each validating process's Schematron
child, the Dask scheduler and workers) as proportional set size (a page shared by forked
workers counted once), sampled every 0.1 s from /proc; and, for the bundle, the growth from the smallest to the largest
size (CPU per product; 1.00 is linear), with what each kind of process held at the summed
peak (the command, the processes it forked - -j workers, the delivery's checking process -,
the Saxon child, Dask's processes) and the load average when the run ended. Every report
must equal the one-process report (byte for byte, after the run's paths).

For the table the contents check alone is also timed in this process (records per
CPU-second, the issue's measure) - before the column-at-a-time checks the issue measured
~23,000 records of 16 fields per CPU-second (31 CPU-s for 1M records); its target is
>= 1,000,000. Issue 51's figures for the bundle before this work: 1k products 21 CPU-s,
10k 158 CPU-s (352 s wall, 171 MB); target: 100k in <= 10 min wall with -j 2, <= 400 MB.
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import psutil

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))
sys.path.insert(0, str(REPO / "tests"))

from scale_bundle import RECORDS, make_bundle, write_table  # noqa: E402

PDSGEN = [sys.executable, "-m", "pdsgen", "validate", "--offline", "--format", "json"]
DASK = Path(sys.executable).with_name("dask")


@dataclass(frozen=True)
class Measured:
    wall: float
    cpu: float
    peak_mb: float
    report: bytes
    at_peak: dict[str, float]  # what each kind of process held at the summed peak, MB

    def breakdown(self) -> str:
        return ", ".join(f"{kind} {mb:.0f}" for kind, mb in self.at_peak.items())


def _kind(process: psutil.Process, root: psutil.Process) -> str:
    """What a process of the run is: the command itself, the Schematron engine, a forked worker."""
    if process.pid == root.pid:
        return "command"
    command = " ".join(process.cmdline())
    if "schematron import serve" in command:
        return "Saxon child"
    return "dask" if "dask" in command else "forked"


def _tree_pss(processes: list[psutil.Process]) -> dict[int, tuple[str, int]]:
    """Each process of the trees: its kind and proportional set size (shared pages counted once)."""
    found = {}
    for root in processes:
        try:
            family = [root, *root.children(recursive=True)]
        except psutil.NoSuchProcess:
            continue
        for process in family:
            try:
                found[process.pid] = (_kind(process, root), process.memory_full_info().pss)
            except (psutil.NoSuchProcess, psutil.AccessDenied):
                pass
    return found


def _cpu(processes: list[psutil.Process]) -> float:
    """User + system seconds of long-running processes (the Dask scheduler and workers) so far."""
    total = 0.0
    for root in processes:
        for process in [root, *root.children(recursive=True)]:
            try:
                times = process.cpu_times()
                total += times.user + times.system + times.children_user + times.children_system
            except psutil.NoSuchProcess:
                pass
    return total


def run(command: list[str], also: list[psutil.Process] = ()) -> Measured:  # type: ignore[assignment]
    """Wall, CPU (the command and its children, plus `also`'s growth) and summed peak PSS."""
    cpu_before = _cpu(list(also))
    started = time.perf_counter()
    child = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    watched = [psutil.Process(child.pid), *also]
    peak: list[Any] = [0, {}]
    done = threading.Event()

    def sample() -> None:
        while not done.is_set():
            processes = _tree_pss(watched)
            total = sum(pss for _, pss in processes.values())
            if total > peak[0]:
                peak[:] = [total, processes]
            done.wait(0.1)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    report = child.stdout.read() if child.stdout else b""
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - started
    done.set()
    sampler.join()
    error = child.stderr.read().decode(errors="replace") if child.stderr else ""
    if os.waitstatus_to_exitcode(status) not in (0, 1):
        raise SystemExit(f"{' '.join(command)} failed:\n{error}")
    cpu = usage.ru_utime + usage.ru_stime + _cpu(list(also)) - cpu_before
    at_peak: dict[str, float] = {}
    for kind, pss in sorted(peak[1].values(), key=lambda found: -found[1]):
        at_peak[kind] = at_peak.get(kind, 0) + pss / 1e6
    return Measured(wall, cpu, peak[0] / 1e6, report, at_peak)


class Cluster:
    """`dask scheduler` + 2 `dask worker` processes on 127.0.0.1, as a site would run them."""

    def __enter__(self) -> Cluster:
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        self.address = f"tcp://127.0.0.1:{port}"
        self.log = open(os.devnull, "wb")
        self.popens = [subprocess.Popen([str(DASK), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                                         "--no-dashboard"], stdout=self.log, stderr=self.log)]
        deadline = time.monotonic() + 60
        while socket.socket().connect_ex(("127.0.0.1", port)) != 0:
            if time.monotonic() > deadline:
                raise SystemExit("the dask scheduler did not start")
            time.sleep(0.2)
        for _ in range(2):
            self.popens.append(subprocess.Popen([str(DASK), "worker", self.address, "--nthreads", "1",
                                                 "--no-dashboard", "--memory-limit", "0", "--host", "127.0.0.1"],
                                                stdout=self.log, stderr=self.log))
        time.sleep(5)  # the workers join
        self.processes = [psutil.Process(p.pid) for p in self.popens]
        return self

    def __exit__(self, *_: object) -> None:
        for process in reversed(self.popens):
            process.terminate()
        for process in self.popens:
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
        self.log.close()


def _mode_commands(target: Path, modes: list[str], cluster: Cluster | None) -> dict[str, tuple[list[str], list]]:
    commands: dict[str, tuple[list[str], list]] = {}
    if "one" in modes:
        commands["one process"] = ([*PDSGEN, str(target)], [])
    if "j2" in modes:
        commands["-j 2"] = ([*PDSGEN, "-j", "2", str(target)], [])
    if "cluster" in modes and cluster is not None:
        commands["cluster (2 workers)"] = ([*PDSGEN, "--scheduler", cluster.address, str(target)], cluster.processes)
    return commands


def bench_bundles(sizes: list[int], workdir: Path, modes: list[str], bundle_name: str, keep: bool,
                  cluster: Cluster | None) -> None:
    print(f"\nBundles of copies of a Table_Character product ({RECORDS} records x 16 fields), "
          f"load {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"  {'products':>9s} {'mode':22s} {'wall s':>9s} {'CPU s':>9s} {'CPU ms/product':>15s} {'peak MB':>9s}  "
          "faults found, same report")
    per_product: dict[str, dict[int, float]] = {}
    for size in sizes:
        root = workdir / f"bundle_{size}"
        if not root.exists():
            made = time.perf_counter()
            make_bundle(root, size, bundle_name=bundle_name, fault_last=True)
            print(f"  (made {size} products in {time.perf_counter() - made:.0f} s)")
        reference = None
        for mode, (command, also) in _mode_commands(root, modes, cluster).items():
            measured = run(command, also)
            reference = reference or measured.report
            found = _planted_found(measured.report, size)
            per_product.setdefault(mode, {})[size] = measured.cpu / size
            print(f"  {size:9d} {mode:22s} {measured.wall:9.1f} {measured.cpu:9.1f} {measured.cpu / size * 1e3:15.2f} "
                  f"{measured.peak_mb:9.0f}  {'yes' if found else 'NO'}, "
                  f"{'yes' if measured.report == reference else 'NO'}  (at the peak, MB: {measured.breakdown()}; "
                  f"load {os.getloadavg()[0]:.1f})")
            if measured.report != reference:  # kept beside the first mode's, to be compared
                for name, report in (("first", reference), (mode.split()[0].strip("-"), measured.report)):
                    (workdir / f"report_{size}_{name}.json").write_bytes(report)
                print(f"  (both reports kept in {workdir}/report_{size}_*.json)")
        if not keep:
            shutil.rmtree(root)
    if len(sizes) > 1:
        for mode, costs in per_product.items():
            small, large = min(costs), max(costs)
            print(f"  growth {small} -> {large} products, {mode}: CPU per product x{costs[large] / costs[small]:.2f} "
                  "(1.00 = linear)")


def _planted_found(report: bytes, size: int) -> bool:
    last = f"p{size - 1:06d}.xml".encode()
    return (b"PDS4-053" in report and b"DLV-011" in report and report.count(last) >= 1
            and b"123.45 outside Field_Statistics" in report)


def bench_tables(sizes: list[int], workdir: Path, modes: list[str], keep: bool, cluster: Cluster | None) -> None:
    from lxml import etree

    from pdsgen.validate.pds4 import table_checks
    from pdsgen.validate.pds4.label_tree import Pds4Hits

    print(f"\nOne Table_Character of 16 fields, load {os.getloadavg()[0]:.1f}")
    print(f"  {'records':>10s} {'MB':>6s} {'what':28s} {'wall s':>8s} {'CPU s':>8s} {'peak MB':>8s} "
          f"{'records/CPU-s':>14s} {'vs 23,000':>9s}")
    for records in sizes:
        directory = workdir / f"table_{records}"
        label = directory / "table.xml"
        if not label.exists():
            write_table(directory, "table", records)
        size_mb = (directory / "table.tab").stat().st_size / 1e6
        hits = Pds4Hits(label)
        cpu, wall = time.process_time(), time.perf_counter()
        table_checks.check_tables(hits, etree.parse(str(label)))
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        assert not hits.by_rule, hits.by_rule
        print(f"  {records:10d} {size_mb:6.0f} {'contents check, in process':28s} {wall:8.2f} {cpu:8.2f} {'':>8s} "
              f"{records / cpu:14,.0f} {records / cpu / 23000:8.0f}x")
        for mode, (command, also) in _mode_commands(label, [m for m in modes if m == "one"], cluster).items():
            measured = run(command, also)
            print(f"  {records:10d} {size_mb:6.0f} {'pdsgen validate, ' + mode:28s} {measured.wall:8.2f} "
                  f"{measured.cpu:8.2f} {measured.peak_mb:8.0f} {records / measured.cpu:14,.0f} "
                  f"{records / measured.cpu / 23000:8.0f}x")
        if not keep:
            shutil.rmtree(directory)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--products", default="1000", help="bundle sizes, comma-separated (e.g. 1000,10000,100000)")
    parser.add_argument("--records", default="1000000", help="table sizes, comma-separated (e.g. 1000000,10000000)")
    parser.add_argument("--only", default="bundle,table")
    parser.add_argument("--modes", default="one,j2,cluster")
    parser.add_argument("--bundle-name", default="bundle_scale.xml")
    parser.add_argument("--workdir", help="where the bundles and tables are made (default: a temporary directory)")
    parser.add_argument("--keep", action="store_true", help="keep what was made (and reuse it next time)")
    args = parser.parse_args()
    modes = args.modes.split(",")
    workdir = Path(args.workdir) if args.workdir else Path(tempfile.mkdtemp(prefix="validate_scale_"))
    workdir.mkdir(parents=True, exist_ok=True)
    try:
        with Cluster() if "cluster" in modes else _nothing() as cluster:
            if "bundle" in args.only:
                bench_bundles([int(n) for n in args.products.split(",")], workdir, modes, args.bundle_name, args.keep,
                              cluster)
            if "table" in args.only:
                bench_tables([int(n) for n in args.records.split(",")], workdir, modes, args.keep, cluster)
    finally:
        if not args.workdir:
            shutil.rmtree(workdir, ignore_errors=True)


class _nothing:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *_: object) -> None:
        return None


if __name__ == "__main__":
    main()
