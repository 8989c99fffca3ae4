"""What a Dask worker does with one job: check its marker, run it in a child, record it.

This function is what `client.submit` sends. It never raises: every outcome - done,
skipped because a current marker says so, failed with a one-line reason, crashed,
timed out - comes back as a small dict, so the client can report and go on.
"""

from __future__ import annotations

import contextlib
import ctypes
import json
import os
import resource
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from .child import thread_environment
from .resume import file_stats, is_done, may_replace, read_marker, remove_marker, write_marker

PR_SET_PDEATHSIG = 1  # linux/prctl.h


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
                        peak_mb=result["peak_mb"])
    write_marker(marker_file, state="done", options=task["options"], id=task["id"], inputs=inputs,
                 outputs=file_stats(result["outputs"]), shared=result["shared"], products=result["products"],
                 version=task["version"])
    return _outcome(task, "done", start, outputs=result["outputs"] + result["shared"], products=result["products"],
                    peak_mb=result["peak_mb"])


def _outcome(task: dict[str, Any], status: str, start: float, **fields: Any) -> dict[str, Any]:
    """The job's outcome; `peak_mb` is its child's peak RSS, `worker` where it ran (with that
    worker process's own peak RSS), for sizing the MEMORY a job declares."""
    return {"id": task["id"], "status": status, "seconds": round(time.monotonic() - start, 3),
            "log": task["log"], "outputs": [], "products": [], "error": None, "peak_mb": None,
            **_where(), **fields}


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
    """The job's body in `python -m pdsgen.batch.child`, its output appended to the job's log."""
    log = Path(task["log"])
    log.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="pdsgen-job-") as tmp, open(log, "ab") as log_file:
        task_file, result_file = Path(tmp) / "task.json", Path(tmp) / "result.json"
        task_file.write_text(json.dumps(task), encoding="utf-8")
        log_file.write(f"== pdsgen batch: {task['kind']} {task['id']} ({time.strftime('%Y-%m-%d %H:%M:%S')})\n"
                       .encode())
        log_file.flush()
        env = {**os.environ, **thread_environment(task["threads"]), "PYTHONUNBUFFERED": "1"}
        proc = subprocess.Popen([sys.executable, "-m", "pdsgen.batch.child", str(task_file), str(result_file)],
                                stdin=subprocess.DEVNULL, stdout=log_file, stderr=subprocess.STDOUT, env=env,
                                preexec_fn=_die_with_parent)
        timed_out = threading.Event()

        def stop() -> None:
            timed_out.set()
            proc.kill()

        timer = threading.Timer(task["timeout"] or 0, stop)
        if task["timeout"]:
            timer.start()
        _, status, usage = os.wait4(proc.pid, 0)  # the child's own peak memory comes with its status
        timer.cancel()
        proc.returncode = code = os.waitstatus_to_exitcode(status)
        peak = {"peak_mb": round(usage.ru_maxrss / 1024, 1)}
        if timed_out.is_set():
            return {"ok": False, "error": f"timed out after {task['timeout']:g} s", "retry": True, **peak}
        if code < 0:
            name = signal.Signals(-code).name
            return {"ok": False, "error": f"crashed (killed by {name}); see {log}", "retry": True, **peak}
        try:
            return {**json.loads(result_file.read_text(encoding="utf-8")), **peak}
        except (OSError, ValueError):
            return {"ok": False, "error": f"exited with status {code} without a result; see {log}",
                    "retry": True, **peak}


def _die_with_parent() -> None:
    """In the child, before exec: end with the worker, never run on as an orphan.

    A batch killed part way must not leave jobs finishing behind the next run's back.
    """
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
