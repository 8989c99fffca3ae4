"""What a Dask worker does with one job: check its marker, run it in a child, record it.

This function is what `client.submit` sends. It never raises: every outcome - done,
skipped because a current marker says so, failed with a one-line reason, crashed,
timed out - comes back as a small dict, so the client can report and go on.
"""

from __future__ import annotations

import contextlib
import resource
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from .. import clock
from ..storage import files, is_s3
from .resident import DEFAULT_MAX_GROWTH_MB, DEFAULT_MAX_JOBS, Recycling, run_in_child
from .resume import file_stats, is_done, may_replace, read_marker, remove_marker, write_marker


def run_job(task: dict[str, Any]) -> dict[str, Any]:
    """Run one job (see child.py) unless its marker shows it done; the outcome as a dict."""
    start = time.monotonic()
    marker_file = Path(task["marker"])
    marker = read_marker(marker_file)
    if is_done(marker, task["options"], task["inputs"]):
        assert marker is not None
        return _outcome(task, "skipped", start, outputs=list(marker["outputs"]), products=marker["products"])
    inputs = file_stats(task["inputs"])
    owner = may_replace(marker)
    write_marker(marker_file, state="started", options=task["options"], id=task["id"], owner=owner,
                 outdir=task["outdir"])
    with _directory_lock(task["lock"]):
        result = _run_child({**task, "resume": owner})
    if not result.get("ok"):
        if owner:
            write_marker(marker_file, state="failed", options=task["options"], id=task["id"], owner=True)
        else:
            remove_marker(marker_file)
        return _outcome(task, "failed", start, error=result["error"], retry=result.get("retry", False),
                        peak_mb=result.get("peak_mb"), child_pid=result.get("pid"))
    write_marker(marker_file, state="done", options=task["options"], id=task["id"], inputs=inputs,
                 outputs=file_stats(result["outputs"]), shared=result["shared"], products=result["products"],
                 version=task["version"])
    return _outcome(task, "done", start, outputs=result["outputs"] + result["shared"], products=result["products"],
                    peak_mb=result.get("peak_mb"), child_pid=result.get("pid"), work_seconds=result.get("work_seconds"))


def _outcome(task: dict[str, Any], status: str, start: float, **fields: Any) -> dict[str, Any]:
    """The job's outcome; `peak_mb` is the job's own peak RSS in its child (`child_pid`), `worker`
    where it ran (with that worker process's own peak RSS), for sizing the MEMORY a job declares."""
    elapsed = time.monotonic() - start
    return {"id": task["id"], "status": status, "seconds": round(elapsed, 3),
            "started": round(time.time() - elapsed, 3), "log": task["log"], "outputs": [], "products": [],
            "error": None, "peak_mb": None, "child_pid": None, **_where(), **fields}


def _where() -> dict[str, Any]:
    try:
        from distributed import get_worker

        address = get_worker().address
    except (ImportError, ValueError):
        address = None
    return {"worker": address, "worker_peak_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)}


@contextlib.contextmanager
def _directory_lock(name: str | None) -> Iterator[None]:
    """Hold the cluster-wide lock NAME (if any) while the job runs.

    Jobs that read, extend and rewrite a file shared by a whole directory (an
    orthoimage's JP2INFO.TXT) take turns, or one would drop the other's entry. While
    waiting, the job leaves its worker thread free for other jobs (Dask's secede).
    """
    if name is None:
        yield
        return
    from distributed import Lock, rejoin, secede

    secede()
    with Lock(name):
        rejoin()
        yield


def _run_child(task: dict[str, Any]) -> dict[str, Any]:
    """The job's body in this worker slot's resident child (resident.py), its output appended
    to the job's log after a header line. A log in a bucket (s3:// OUTDIR) is written on this
    worker's disk while the job runs (begun with what earlier attempts wrote) and uploaded
    whole when it ends."""
    if not is_s3(task["log"]):
        return _run_child_logged(task)
    with tempfile.TemporaryDirectory(prefix="pdsgen-batch-log-") as folder:
        local = Path(folder) / Path(task["log"]).name
        local.write_text(files.read_text(task["log"]) or "", encoding="utf-8")
        try:
            return _run_child_logged({**task, "log": str(local)})
        finally:
            files.write_text_whole(task["log"], local.read_text("utf-8", "replace"))


def _run_child_logged(task: dict[str, Any]) -> dict[str, Any]:
    log = Path(task["log"])
    log.parent.mkdir(parents=True, exist_ok=True)
    with open(log, "ab") as log_file:
        log_file.write(f"== pdsgen batch: {task['kind']} {task['id']} ({clock.wall_time()})\n"
                       .encode())
    recycling = Recycling(task.get("child_jobs", DEFAULT_MAX_JOBS), task.get("child_growth_mb", DEFAULT_MAX_GROWTH_MB))
    result = run_in_child(task, recycling)
    if not result.get("ok") and result.get("retry") and result["error"].startswith(("crashed", "exited")):
        result["error"] += f"; see {log}"
    return result
