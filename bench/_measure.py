"""Run a command in a fresh process and report wall time and peak memory (RSS)."""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from dataclasses import dataclass


@dataclass(frozen=True)
class Run:
    seconds: float
    peak_mb: float


def measure(command: list[str], env: dict[str, str] | None = None) -> Run:
    """Wall time and the child's own peak RSS (from wait4), so runs don't share a high-water mark."""
    start = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    _, status, usage = os.wait4(process.pid, 0)
    elapsed = time.perf_counter() - start
    stderr = process.stderr.read().decode(errors="replace") if process.stderr else ""
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"command failed: {' '.join(command)}\n{stderr}")
    return Run(elapsed, usage.ru_maxrss / 1024.0)


def best_of(command: list[str], repeat: int, outputs: list[str], env: dict[str, str] | None = None) -> Run:
    """Fastest of `repeat` runs, each writing fresh outputs after a sync.

    Removing the previous outputs and flushing dirty pages before each run keeps
    one tool's write-back from being charged to the other.
    """
    runs = []
    for _ in range(repeat):
        for path in outputs:
            if os.path.isdir(path):
                shutil.rmtree(path)
            elif os.path.exists(path):
                os.unlink(path)
        os.sync()
        time.sleep(3.0)  # let the file system finish discarding deleted blocks
        runs.append(measure(command, env))
    return min(runs, key=lambda run: run.seconds)


def print_side_by_side(title: str, ours: Run, baseline: Run, baseline_name: str) -> None:
    print(title)
    print(f"  {'':28s} {'wall s':>9s} {'peak MB':>9s}")
    print(f"  {'pdsgen':28s} {ours.seconds:9.2f} {ours.peak_mb:9.1f}")
    print(f"  {baseline_name:28s} {baseline.seconds:9.2f} {baseline.peak_mb:9.1f}")
    print(f"  ratio pdsgen/baseline: time {ours.seconds / baseline.seconds:.2f}, "
          f"memory {ours.peak_mb / baseline.peak_mb:.2f}")
