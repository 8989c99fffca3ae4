"""Run a command in a fresh process and report wall time and peak memory (RSS).

Linux keeps a process's peak-RSS mark across fork and exec, so a child forked
from a large benchmark process would report at least the parent's size. Each
command is therefore started from a small launcher process (a bare Python that
imports nothing else), whose own few MB are the floor of what is reported.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass

_LAUNCHER = """
import json, os, sys, time
start = time.perf_counter()
pid = os.fork()
if pid == 0:
    os.execvp(sys.argv[2], sys.argv[2:])
_, status, usage = os.wait4(pid, 0)
with open(sys.argv[1], "w") as handle:
    json.dump({"seconds": time.perf_counter() - start, "peak_kb": usage.ru_maxrss,
               "cpu": usage.ru_utime + usage.ru_stime,
               "exit": os.waitstatus_to_exitcode(status)}, handle)
"""


@dataclass(frozen=True)
class Run:
    seconds: float
    peak_mb: float
    cpu_seconds: float = 0.0  # user + system time of the command and its threads


def measure(command: list[str], env: dict[str, str] | None = None) -> Run:
    """Wall time and peak RSS of `command`, measured by a small launcher process."""
    with tempfile.NamedTemporaryFile(suffix=".json") as report:
        process = subprocess.run([sys.executable, "-S", "-c", _LAUNCHER, report.name, *command],
                                 stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
        result = json.loads(open(report.name).read() or "{}")
    if process.returncode != 0 or result.get("exit") != 0:
        raise SystemExit(f"command failed: {' '.join(command)}\n{process.stderr.decode(errors='replace')}")
    return Run(result["seconds"], result["peak_kb"] / 1024.0, result["cpu"])


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
