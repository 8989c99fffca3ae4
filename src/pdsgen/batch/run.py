"""Run a checked manifest on a Dask cluster, or print what a run would do.

The client submits each job once the jobs it is `after` have finished (Extras after
their DTM take that DTM's product as input), takes results with `as_completed` and
releases each as it arrives, retries crashes and timeouts up to the job's
`retries`, and marks the jobs that wait for a failed one as blocked. The outcome
of every job goes into one JSON summary beside the jobs' logs.
"""

from __future__ import annotations

import json
import logging
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

import click

from .. import __version__
from ..storage import files
from .cluster import RESOURCE, Sizing, check_workers, open_client
from .manifest import OUTPUT_OPTIONS, Job, Manifest, command
from .progress import Progress
from .resident import DEFAULT_MAX_GROWTH_MB, DEFAULT_MAX_JOBS
from .resume import (
    STATE_DIR,
    file_stats,
    is_done,
    marker_path,
    options_hash,
    read_marker,
    remove_interrupted_leftovers,
)

# Kinds whose jobs update a file shared by their whole output directory (an ortho
# writes its entry into JP2INFO.TXT): such jobs in one directory take turns. Extras
# (README.TXT) are ordered by `after` instead, checked in the manifest, because
# README.TXT lists products in the order they were made.
SHARED_FILE_KINDS = ("ortho",)
log = logging.getLogger("pdsgen.batch")


@dataclass
class Settings:
    scheduler: str | None = None
    workers: int = 1
    log_dir: Path | None = None
    child_jobs: int = DEFAULT_MAX_JOBS  # jobs a resident child runs before it is replaced
    child_growth_mb: float = DEFAULT_MAX_GROWTH_MB  # RSS growth after which it is replaced


@dataclass
class Summary:
    path: Path
    data: dict[str, Any] = field(default_factory=dict)

    @property
    def failed(self) -> list[dict[str, Any]]:
        return [j for j in self.data["jobs"] if j["status"] in ("failed", "blocked")]

    @property
    def exit_code(self) -> int:
        return 1 if self.failed else 0


def log_dir(manifest: Manifest, settings: Settings) -> Path:
    return settings.log_dir or manifest.outdir / STATE_DIR / "logs"


def make_task(job: Job, manifest: Manifest, settings: Settings, products: Mapping[str, list[str]]) -> dict[str, Any]:
    """What the worker needs to run JOB (JSON only): parameters, inputs, hash, marker and log paths."""
    params: dict[str, Any] = {k: list(v) if isinstance(v, tuple) else v for k, v in job.params.items()}
    if job.inputs_from_after:
        params[job.argument] = [p for needed in job.after for p in products.get(needed, [])]
    inputs = [str(v) for name in input_names(job.kind) for v in _as_list(params.get(name))]
    digest = options_hash(job.kind, params, __version__)
    output = params.get("outdir") or (str(Path(params["output"]).parent) if params.get("output") else None)
    return {
        "id": job.id, "kind": job.kind, "params": params, "inputs": inputs, "options": digest, "outdir": output,
        "lock": f"pdsgen-batch:{output}" if job.kind in SHARED_FILE_KINDS else None,
        "threads": job.threads, "timeout": job.timeout, "version": __version__,
        "child_jobs": settings.child_jobs, "child_growth_mb": settings.child_growth_mb,
        "marker": str(marker_path(manifest.outdir, job.id)),
        "log": str(log_dir(manifest, settings) / f"{job.id}.log"),
    }


def input_names(kind: str) -> list[str]:
    """Parameters of KIND that name files the job reads (its click.Path parameters, less outputs)."""
    return [p.name for p in command(kind).params
            if isinstance(p.type, click.Path) and p.name and p.name not in OUTPUT_OPTIONS]


def _as_list(value: Any) -> list[Any]:
    if value is None:
        return []
    return list(value) if isinstance(value, list | tuple) else [value]


def plan(manifest: Manifest, settings: Settings, out: TextIO) -> None:
    """Print, without running anything, which jobs are done, to do, or wait for others.

    On a cluster the client may not see the workers' files, so the inputs it cannot
    see are listed: not an error here, but worth a look before a long run.
    """
    products: dict[str, list[str]] = {}
    state: dict[str, str] = {}
    unseen: list[str] = []
    for job in _in_order(manifest.jobs):
        task = make_task(job, manifest, settings, products)
        marker = read_marker(Path(task["marker"]))
        waiting = [a for a in job.after if state[a] != "done"]
        if not waiting and is_done(marker, task["options"], task["inputs"]):
            state[job.id] = "done"
            products[job.id] = marker["products"] if marker else []
        else:
            state[job.id] = "blocked" if waiting else "to do"
        reason = f"  (after {', '.join(waiting)})" if waiting else ""
        out.write(f"{state[job.id]:<8}{job.kind:<9}{job.id}{reason}\n")
        if not job.inputs_from_after or not waiting:
            unseen += [i for i, st in file_stats(task["inputs"]).items() if st is None and i not in unseen]
    counts = {s: list(state.values()).count(s) for s in ("to do", "done", "blocked")}
    out.write(f"{len(state)} jobs: {counts['to do']} to do, {counts['done']} done, "
              f"{counts['blocked']} blocked until the jobs they are after are made\n")
    for name in unseen:
        out.write(f"not visible from here (must exist on the workers): {name}\n")


def _in_order(jobs: list[Job]) -> list[Job]:
    """Jobs ordered so each comes after the jobs it needs (the manifest has no cycles)."""
    ordered: list[Job] = []
    placed: set[str] = set()
    remaining = list(jobs)
    while remaining:
        for job in remaining:
            if all(a in placed for a in job.after):
                ordered.append(job)
                placed.add(job.id)
                remaining.remove(job)
                break
    return ordered


def run(manifest: Manifest, settings: Settings, progress_stream: TextIO | None = None,
        bar: bool | None = None) -> Summary:
    """Run every job of MANIFEST on the cluster; the summary (also written as summary.json)."""
    started = time.time()
    progress = Progress(len(manifest.jobs), progress_stream, bar)
    with open_client(settings.scheduler, settings.workers) as client:
        sizing = check_workers(client, manifest.jobs, __version__)
        log.info("%s", sizing.describe())
        removed = remove_interrupted_leftovers(marker_path(manifest.outdir, j.id) for j in manifest.jobs)
        if removed:
            progress.note(f"removed {len(removed)} temporary file(s) left by an interrupted run")
        outcomes = _Submitter(client, manifest, settings, progress, sizing).run_all()
        if settings.scheduler is not None:  # a local cluster's workers end with the run, and their children
            _close_idle_children(client)
    progress.close()
    return _write_summary(manifest, settings, outcomes, started)


def _close_idle_children(client: Any) -> None:
    from .resident import close_idle_children

    try:
        client.run(close_idle_children)
    except Exception as exc:  # a worker gone meanwhile: its children ended with it
        log.info("idle job processes not closed on every worker (%s)", exc)


class _Submitter:
    """Submits each job once the jobs it is after are done, and collects the outcomes."""

    def __init__(self, client: Any, manifest: Manifest, settings: Settings, progress: Progress,
                 sizing: Sizing) -> None:
        from distributed import as_completed

        self.client, self.manifest, self.settings, self.progress = client, manifest, settings, progress
        self.sizing = sizing
        self.queue: list[Job] = []  # ready jobs waiting for a worker with room (placed sizing)
        self.placed: dict[str, str] = {}  # future key -> the worker booked for it
        self.futures = as_completed()
        self.submitted: dict[str, Job] = {}  # future key -> job
        self.attempts: dict[str, int] = {}
        self.outcomes: dict[str, dict[str, Any]] = {}
        self.products: dict[str, list[str]] = {}

    def run_all(self) -> dict[str, dict[str, Any]]:
        self._release_ready()
        for future in self.futures:
            job = self.submitted.pop(future.key)
            if future.key in self.placed:
                self.sizing.give_back(self.placed.pop(future.key), job.memory)
            outcome = {**_outcome_of(future), "id": job.id}
            future.release()
            if outcome["status"] == "failed" and outcome.pop("retry", False) and self.attempts[job.id] <= job.retries:
                self.progress.running -= 1
                self._submit(job)
                continue
            outcome.pop("retry", None)
            self._finish(job, {**outcome, "attempts": self.attempts[job.id]})
            self._dispatch()
        return self.outcomes

    def _submit(self, job: Job) -> None:
        self.attempts[job.id] = self.attempts.get(job.id, 0) + 1
        self.queue.append(job)
        self._dispatch()

    def _dispatch(self) -> None:
        """Send the queued jobs that have room: all of them where Dask sizes jobs by the MEMORY
        resource, else those a worker has a free thread and the memory for (Sizing.take)."""
        for job in list(self.queue):
            where = None if self.sizing.by_resource else self.sizing.take(job.memory)
            if where is None and not self.sizing.by_resource:
                continue
            self.queue.remove(job)
            self._send(job, where)

    def _send(self, job: Job, where: str | None) -> None:
        from .worker import run_job

        task = make_task(job, self.manifest, self.settings, self.products)
        key = f"{job.kind}-{job.id}-{task['options'][:12]}-{self.attempts[job.id]}"
        self.submitted[key] = job
        options: dict[str, Any] = {}
        if where is None or where in self.sizing.declared:
            options["resources"] = {RESOURCE: job.memory}
        if where is not None:  # pinned while that worker lives; elsewhere if it leaves
            options.update(workers=[where], allow_other_workers=True)
            self.placed[key] = where
        self.futures.add(self.client.submit(run_job, task, key=key, pure=False, **options))
        self.progress.started()

    def _finish(self, job: Job, outcome: dict[str, Any], was_running: bool = True) -> None:
        self.outcomes[job.id] = outcome
        self.products[job.id] = outcome["products"]
        self.progress.finished(outcome, job.kind, was_running)
        self._release_ready()

    def _release_ready(self) -> None:
        """Submit the jobs whose `after` jobs are all done; mark blocked those after a failed one."""
        for job in self.manifest.jobs:
            if job.id in self.outcomes or job.id in self.attempts:
                continue
            states = [self.outcomes.get(a, {}).get("status") for a in job.after]
            failed = [a for a, state in zip(job.after, states, strict=True) if state in ("failed", "blocked")]
            if failed:
                self._finish(job, {"id": job.id, "status": "blocked", "seconds": 0.0, "outputs": [], "products": [],
                                   "log": None, "attempts": 0,
                                   "error": f"not run: it is after {', '.join(failed)}, which did not succeed"},
                             was_running=False)
                return  # _finish released what this unblocked
            if all(state in ("done", "skipped") for state in states):
                self._submit(job)


def _outcome_of(future: Any) -> dict[str, Any]:
    """The worker's outcome dict; a failure of the cluster itself (a lost worker) as a failed job."""
    try:
        return dict(future.result())
    except Exception as exc:  # KilledWorker, CommClosedError ...: the job did not run to its end
        return {"id": None, "status": "failed", "seconds": 0.0, "outputs": [], "products": [], "log": None,
                "retry": True, "error": f"the Dask worker running it was lost ({type(exc).__name__}: {exc})"}


def _write_summary(manifest: Manifest, settings: Settings, outcomes: Mapping[str, dict[str, Any]],
                   started: float) -> Summary:
    jobs = []
    for job in manifest.jobs:
        outcome = outcomes[job.id]
        jobs.append({"id": job.id, "kind": job.kind, "status": outcome["status"],
                     "started": outcome.get("started"), "seconds": outcome["seconds"],
                     "work_seconds": outcome.get("work_seconds"),
                     "attempts": outcome.get("attempts", 0),
                     "outputs": outcome["outputs"], "error": outcome["error"], "log": outcome["log"],
                     "peak_mb": outcome.get("peak_mb"), "child_pid": outcome.get("child_pid"),
                     "worker": outcome.get("worker"),
                     "worker_peak_mb": outcome.get("worker_peak_mb")})
    counts = {s: sum(j["status"] == s for j in jobs) for s in ("done", "skipped", "failed", "blocked")}
    data = {"manifest": str(manifest.path.resolve()), "outdir": str(manifest.outdir),
            "pdsgen": __version__, "scheduler": settings.scheduler or f"local, {settings.workers} worker(s)",
            "seconds": round(time.time() - started, 3), "counts": counts, "jobs": jobs}
    path = log_dir(manifest, settings) / "summary.json"
    files.write_text_whole(path, json.dumps(data, indent=1) + "\n")  # beside the logs, in a bucket too
    return Summary(path, data)
