"""The resident process batch jobs run in: `python -m pdsgen.batch.child`.

Each Dask worker slot keeps one such child (see resident.py). It imports pdsgen and
the libraries its jobs use once, then runs job after job: a task arrives as one JSON
line on stdin, the job's stdout and stderr (file descriptors 1 and 2, so GDAL's and
OpenJPEG's own messages too) go to the job's log while it runs, and one JSON line
comes back on the reply pipe: what the job wrote (or its one-line reason for
failing), the job's peak memory and the child's memory after it. A job that crashes
- a segfault or abort inside GDAL or OpenJPEG - ends only this process: the worker
sees the pipe close, reads the exit status and starts a new child for the next job.
The child ends when its stdin closes (the worker retired it, or died). Nothing imports
this module: it is only run, so `-m` finds it unloaded.
"""

from __future__ import annotations

import importlib
import json
import os
import resource
import sys
import time
import traceback
import warnings
from typing import Any, TextIO

# What every kind of job imports, loaded once when the child starts instead of per job.
PRELOAD = ("numpy", "rasterio", "glymur", "pdsgen.batch.calls", "pdsgen.products.dtm", "pdsgen.products.ortho",
           "pdsgen.extras", "pdsgen.validate", "pdsgen.products.options")


def run(task: dict[str, Any]) -> dict[str, Any]:
    """Make the job's library call; the result is JSON: outputs, or a one-line error."""
    import glymur

    from ..errors import PdsgenError
    from .calls import RUNNERS, ProblemsFound

    glymur.set_option("lib.num_threads", task["threads"])  # OpenJPEG's pool, for decoding and encoding
    params = task["params"]
    try:
        written = RUNNERS[task["kind"]](params, bool(params.get("overwrite")) or task["resume"], task["threads"])
    except (PdsgenError, ProblemsFound) as exc:
        return {"ok": False, "error": str(exc), "retry": False}
    except Exception as exc:  # a bug or an environment failure: keep the traceback in the log
        traceback.print_exc()
        return {"ok": False, "error": f"{type(exc).__name__}: {exc}".splitlines()[0], "retry": True}
    return {"ok": True, **written}


def memory_mb() -> tuple[float | None, float | None]:
    """(peak RSS since the last reset_peak, current RSS) of this process in MB, from /proc;
    (None, None) where /proc is not there."""
    values: dict[str, float] = {}
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith(("VmHWM:", "VmRSS:")):
                    name, kb = line.split()[:2]
                    values[name] = int(kb) / 1024
    except OSError:
        return None, None
    return values.get("VmHWM:"), values.get("VmRSS:")


def reset_peak() -> bool:
    """Start the peak-RSS mark afresh at the current size (Linux clear_refs 5), so a job's
    peak is its own, not that of an earlier job in this process. False where unsupported."""
    try:
        with open("/proc/self/clear_refs", "w", encoding="ascii") as refs:
            refs.write("5")
    except OSError:
        return False
    return True


def _job_peak(resettable: bool) -> float:
    peak, _ = memory_mb()
    if resettable and peak is not None:
        return round(peak, 1)
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)  # the life's peak, an upper bound


def _run_logged(task: dict[str, Any]) -> dict[str, Any]:
    """Run TASK with file descriptors 1 and 2 on the job's log, restored afterwards."""
    saved = os.dup(1), os.dup(2)
    with open(task["log"], "ab") as log:
        os.dup2(log.fileno(), 1)
        os.dup2(log.fileno(), 2)
        try:
            return run(task)
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])


def serve(requests: TextIO, replies: TextIO) -> int:
    """Preload, say ready, then one job per request line until REQUESTS closes."""
    for name in PRELOAD:
        importlib.import_module(name)
    _, rss = memory_mb()
    _reply(replies, {"ready": True, "pid": os.getpid(), "rss_mb": rss})
    for line in requests:
        task = json.loads(line)
        # Changing the warning filters (here re-adding a rule that changes nothing, so the
        # list does not grow) makes Python forget which warnings it has shown: each job's
        # log gets its warnings as a fresh process would print them, not only the first job's.
        warnings.filterwarnings("default", category=UserWarning, append=True)
        resettable = reset_peak()
        began = time.perf_counter()
        result = _run_logged(task)
        work = round(time.perf_counter() - began, 4)
        _, rss = memory_mb()
        _reply(replies, {**result, "work_seconds": work, "peak_mb": _job_peak(resettable), "rss_mb": rss})
    return 0


def _reply(replies: TextIO, data: dict[str, Any]) -> None:
    replies.write(json.dumps(data) + "\n")
    replies.flush()


def main() -> int:
    """Replies go on the pipe the worker gave as stdout; fd 1 itself then points at stderr,
    so nothing a library prints outside a job can be taken for a reply."""
    from ..storage.objects import boto3_kept_from_rasterio

    replies = os.fdopen(os.dup(1), "w", encoding="utf-8")
    os.dup2(2, 1)
    requests = os.fdopen(0, "r", encoding="utf-8", closefd=False)
    with boto3_kept_from_rasterio():  # as the command does: rasterio would import boto3 for every job process
        return serve(requests, replies)


if __name__ == "__main__":
    sys.exit(main())
