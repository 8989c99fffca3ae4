"""Resident children: one pre-imported job process per worker slot, reused job after job.

Starting Python and importing numpy, rasterio, glymur and pdsgen costs about 0.4 s,
more than a small product's whole work. So a worker keeps, per slot (a thread that
runs jobs), a child process that has imported all of that once (child.py) and hands
it job after job. Crash isolation stays: a job still runs in its own process, not in
the worker, so a segfault, an abort or the kernel's OOM killer ends only the child;
the job fails with that reason (and may be retried) and the next job gets a new
child. A child is also replaced after `max_jobs` jobs, or once its memory has grown
by `max_growth_mb` over its size when it was ready, so a slow leak in a library
cannot pile up over a long release. A job past its timeout has its child killed.
"""

from __future__ import annotations

import ctypes
import json
import os
import select
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, BinaryIO

PR_SET_PDEATHSIG = 1  # linux/prctl.h
DEFAULT_MAX_JOBS = 100
DEFAULT_MAX_GROWTH_MB = 512.0
START_TIMEOUT = 300.0  # seconds for a new child to import its libraries (a loaded machine, a cold disk)
# Variables that size the thread pools of the native libraries a job uses; set
# from the job's thread count before those libraries load (see thread_environment).
THREAD_VARIABLES = ("GDAL_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def thread_environment(threads: int) -> dict[str, str]:
    """Environment for a child limited to THREADS threads: GDAL, OpenMP and BLAS pools."""
    return {name: str(threads) for name in THREAD_VARIABLES}


@dataclass(frozen=True)
class Recycling:
    """When a resident child is replaced: after MAX_JOBS jobs (1: a fresh process per job)
    or once its RSS has grown by MAX_GROWTH_MB over its size when ready."""

    max_jobs: int = DEFAULT_MAX_JOBS
    max_growth_mb: float = DEFAULT_MAX_GROWTH_MB


class ChildGone(Exception):
    """The child ended before replying: crashed, killed, or exited."""

    def __init__(self, reason: str, peak_mb: float | None) -> None:
        super().__init__(reason)
        self.reason, self.peak_mb = reason, peak_mb


class JobTimedOut(ChildGone):
    pass


# Children are started from this one long-lived thread: PR_SET_PDEATHSIG fires when the
# *thread* that forked a child ends, and Dask's task threads come and go (secede/rejoin).
_SPAWNER = ThreadPoolExecutor(max_workers=1, thread_name_prefix="pdsgen-child-spawner")


class Child:
    """One resident child process and its two pipes (requests in, replies out)."""

    def __init__(self, threads: int) -> None:
        self.threads = threads
        env = {**os.environ, **thread_environment(threads), "PYTHONUNBUFFERED": "1"}
        self.proc: subprocess.Popen[bytes] = _SPAWNER.submit(
            subprocess.Popen, [sys.executable, "-m", "pdsgen.batch.child"], stdin=subprocess.PIPE,
            stdout=subprocess.PIPE, stderr=None, env=env, preexec_fn=_die_with_parent).result()
        self.jobs = 0
        ready = self._reply(START_TIMEOUT, "starting")
        self.ready_rss_mb: float | None = ready.get("rss_mb")
        self.rss_mb = self.ready_rss_mb

    @property
    def pid(self) -> int:
        return self.proc.pid

    def run(self, task: dict[str, Any], timeout: float | None) -> dict[str, Any]:
        """The reply to TASK (its result, peak_mb, rss_mb); ChildGone if the child ended first,
        JobTimedOut (after killing it) if TIMEOUT seconds passed."""
        assert self.proc.stdin is not None
        self.jobs += 1
        try:
            self.proc.stdin.write(json.dumps(task).encode("utf-8") + b"\n")
            self.proc.stdin.flush()
        except BrokenPipeError:
            raise self._gone() from None
        reply = self._reply(timeout, "running")
        self.rss_mb = reply.pop("rss_mb", None)
        return reply

    def worn(self, recycling: Recycling) -> bool:
        """Whether this child has run its share of jobs or grown too much to run another."""
        grown = (self.rss_mb or 0.0) - (self.ready_rss_mb or 0.0)
        return self.jobs >= recycling.max_jobs or grown > recycling.max_growth_mb

    def close(self) -> None:
        """Let the child end by itself (its stdin closes), killed if it does not."""
        try:
            if self.proc.stdin is not None:
                self.proc.stdin.close()
            self.proc.wait(timeout=10)
        except (OSError, subprocess.TimeoutExpired):
            self.proc.kill()
            self.proc.wait()

    def _reply(self, timeout: float | None, doing: str) -> dict[str, Any]:
        stdout: BinaryIO | None = self.proc.stdout  # type: ignore[assignment]
        assert stdout is not None
        deadline = None if not timeout else time.monotonic() + timeout
        while True:
            left = None if deadline is None else deadline - time.monotonic()
            if left is not None and left <= 0:
                self.proc.kill()
                peak = self._wait()
                raise JobTimedOut(f"timed out after {timeout:g} s", peak)
            readable, _, _ = select.select([stdout], [], [], left)
            if readable:
                line = stdout.readline()
                if not line:
                    raise self._gone()
                try:
                    return dict(json.loads(line))
                except ValueError:
                    self.proc.kill()
                    self._wait()
                    raise ChildGone(f"the job process wrote a broken reply while {doing}", None) from None

    def _gone(self) -> ChildGone:
        peak = self._wait()
        code = self.proc.returncode
        if code is not None and code < 0:
            return ChildGone(f"crashed (killed by {signal.Signals(-code).name})", peak)
        return ChildGone(f"exited with status {code} without a result", peak)

    def _wait(self) -> float | None:
        """Reap the child; its peak RSS over its life in MB (None if already reaped)."""
        if self.proc.returncode is not None:
            return None
        try:
            _, status, usage = os.wait4(self.proc.pid, 0)
        except ChildProcessError:
            return None
        self.proc.returncode = os.waitstatus_to_exitcode(status)
        return round(usage.ru_maxrss / 1024, 1)


class Pool:
    """Idle resident children of this worker process, by thread count; a job takes one
    (or starts one), runs, and gives it back unless it is worn out or gone."""

    def __init__(self) -> None:
        self._idle: dict[int, list[Child]] = {}
        self._lock = threading.Lock()
        self.started = 0

    def take(self, threads: int) -> Child:
        with self._lock:
            idle = self._idle.get(threads, [])
            while idle:
                child = idle.pop()
                if child.proc.poll() is None:
                    return child
        child = Child(threads)  # may raise ChildGone if it cannot even start
        with self._lock:
            self.started += 1
        return child

    def give_back(self, child: Child, recycling: Recycling) -> None:
        if child.worn(recycling):
            child.close()
            return
        with self._lock:
            self._idle.setdefault(child.threads, []).append(child)

    def close(self) -> None:
        with self._lock:
            children = [c for idle in self._idle.values() for c in idle]
            self._idle.clear()
        for child in children:
            child.close()


POOL = Pool()  # this worker process's children


def close_idle_children() -> None:
    """End this worker's idle children: run on every worker of an existing cluster when a
    batch is over, so workers that outlive it do not keep pdsgen's processes alive."""
    POOL.close()


def run_in_child(task: dict[str, Any], recycling: Recycling) -> dict[str, Any]:
    """TASK run in a resident child: its result with peak_mb, or ok False with the reason
    (crashed, timed out, exited) and retry True."""
    try:
        child = POOL.take(task["threads"])
    except ChildGone as exc:
        return {"ok": False, "error": f"the job process could not start: {exc.reason}", "retry": True,
                "peak_mb": exc.peak_mb}
    try:
        reply = child.run(task, task["timeout"])
    except ChildGone as exc:
        return {"ok": False, "error": exc.reason, "retry": True, "peak_mb": exc.peak_mb, "pid": child.pid}
    POOL.give_back(child, recycling)
    return {**reply, "pid": child.pid}


def _die_with_parent() -> None:
    """In the child, before exec: end with the worker, never run on as an orphan.

    A batch killed part way must not leave jobs finishing behind the next run's back.
    """
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
