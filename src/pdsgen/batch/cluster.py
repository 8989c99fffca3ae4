"""The Dask cluster a batch runs on: a local one of processes, or a running scheduler.

A worker is never given more concurrent jobs than it has memory for. Where every
worker declares the resource MEMORY (bytes; the local cluster does), jobs ask Dask
for their memory as that resource. Workers started plainly (`dask worker ADDRESS`,
dask-jobqueue or an operator's defaults) declare none; then the client places each
job on a worker itself (Sizing), within the worker's threads and its memory_limit
(a worker's MEMORY where it declares one). Before anything is submitted the workers
are checked - they run this pdsgen version and some worker has the memory each job
asks for - because a job no worker can take would wait forever without a word.
"""

from __future__ import annotations

import contextlib
import logging
import os
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..errors import PdsgenError
from .manifest import Job

RESOURCE = "MEMORY"
CONNECT_TIMEOUT = 30  # seconds to reach a scheduler and see a first worker


def local_workers(threads_per_job: int) -> int:
    """Default worker count: one per core, each job getting THREADS_PER_JOB of them."""
    return max(1, (os.cpu_count() or 1) // max(1, threads_per_job))


@contextlib.contextmanager
def open_client(scheduler: str | None, workers: int) -> Iterator[Any]:
    """A connected distributed.Client: to SCHEDULER, or to a new LocalCluster of WORKERS processes."""
    from distributed import Client, LocalCluster

    logging.getLogger("distributed").setLevel(logging.ERROR)
    if scheduler is None:
        # memory_limit=0: a worker's own memory thresholds would pause or restart it while
        # its job's child does the work; job memory is managed by the MEMORY resource.
        # The scheduler's HTTP server takes a free loopback port: left to its default it tries
        # 8787 and warns on stderr whenever another cluster on the machine holds that port.
        memory = _total_memory() // workers
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0",
                          resources={RESOURCE: memory}, memory_limit=0, host="127.0.0.1",
                          silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
            yield client
        return
    try:
        client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT}s")
    except (OSError, TimeoutError) as exc:
        raise PdsgenError(None, f"cannot reach the Dask scheduler at {scheduler} ({exc})") from None
    with client:
        try:
            client.wait_for_workers(1, timeout=CONNECT_TIMEOUT)
        except TimeoutError:
            raise PdsgenError(None, f"the Dask scheduler at {scheduler} has no workers "
                                    f"(none joined within {CONNECT_TIMEOUT} s)") from None
        yield client


@dataclass
class Sizing:
    """How jobs are fitted to workers: by the MEMORY resource Dask enforces (`by_resource`),
    or by the client placing each job on a worker with a free thread and the memory it
    asks for (`free`: address -> [threads, bytes or None for no limit])."""

    by_resource: bool
    free: dict[str, list[Any]] = field(default_factory=dict)
    declared: set[str] = field(default_factory=set)  # workers (placed) that also declare MEMORY

    @classmethod
    def of(cls, workers: Mapping[str, Mapping[str, Any]]) -> Sizing:
        declared = {a for a, w in workers.items() if (w.get("resources") or {}).get(RESOURCE)}
        if declared == set(workers):
            return cls(True)
        free = {a: [max(1, int(w.get("nthreads") or 1)), _offered(w)] for a, w in workers.items()}
        return cls(False, free, declared)

    def describe(self) -> str:
        if self.by_resource:
            return f"jobs sized by the workers' {RESOURCE} resource (each job asks for its memory)"
        limits = ", ".join(f"{a}: {t} thread(s), {'no memory limit' if m is None else _gb(m)}"
                           for a, (t, m) in sorted(self.free.items()))
        return (f"workers declare no {RESOURCE} resource: jobs placed by each worker's threads and "
                f"memory_limit ({limits})")

    def largest(self) -> float:
        """The most memory one job can have (inf where a worker sets no limit)."""
        if self.by_resource:
            return 0.0
        return max((float("inf") if m is None else m for _, m in self.free.values()), default=0.0)

    def take(self, memory: int) -> str | None:
        """A worker with a free thread and MEMORY bytes free (the one with most memory free),
        booked for the job; None while none has."""
        fits = [(float("inf") if m is None else m, a) for a, (t, m) in self.free.items()
                if t > 0 and (m is None or m >= memory)]
        if not fits:
            return None
        address = max(fits)[1]
        self.free[address][0] -= 1
        if self.free[address][1] is not None:
            self.free[address][1] -= memory
        return address

    def give_back(self, address: str, memory: int) -> None:
        self.free[address][0] += 1
        if self.free[address][1] is not None:
            self.free[address][1] += memory


def _offered(worker: Mapping[str, Any]) -> int | None:
    """The memory a worker offers to jobs: its MEMORY resource, else its memory_limit (None: none)."""
    declared = (worker.get("resources") or {}).get(RESOURCE)
    limit = declared or worker.get("memory_limit") or 0
    return int(limit) if limit else None


def check_version(client: Any, version: str) -> None:
    """PdsgenError (one line) unless every worker runs pdsgen VERSION (a `pdsgen validate
    --scheduler` run checks this too: other workers could find other things)."""
    try:
        versions = client.run(_pdsgen_version)
    except Exception as exc:  # unpickling fails on a worker without pdsgen
        raise PdsgenError(None, f"the Dask workers cannot run pdsgen ({type(exc).__name__}: {exc})") from None
    wrong = {addr: v for addr, v in versions.items() if v != version}
    if wrong:
        addr, other = next(iter(wrong.items()))
        raise PdsgenError(None, f"{len(wrong)} Dask worker(s) run pdsgen {other} (e.g. {addr}); "
                                f"this client runs {version}: install the same version everywhere")


def check_workers(client: Any, jobs: Sequence[Job], version: str) -> Sizing:
    """How jobs are sized on these workers; PdsgenError (one line) unless the workers run
    pdsgen VERSION and some worker can take every job."""
    check_version(client, version)
    workers = client.scheduler_info()["workers"]
    sizing = Sizing.of(workers)
    too_big = max(jobs, key=lambda j: j.memory)
    if sizing.by_resource:
        largest = max(w["resources"][RESOURCE] for w in workers.values())
        offer = f"{RESOURCE}={_gb(largest)}"
    else:
        largest = sizing.largest()
        offer = f"memory_limit={_gb(largest)} (or {RESOURCE})"
    if too_big.memory > largest:
        raise PdsgenError(None, f"job {too_big.id!r} needs memory {_gb(too_big.memory)} but the largest Dask "
                                f"worker offers {offer}")
    return sizing


def _pdsgen_version() -> str:
    from .. import __version__

    return __version__


def _gb(size: float) -> str:
    return f"{size / 1e9:.2f} GB"


def _total_memory() -> int:
    from distributed.system import MEMORY_LIMIT

    return int(MEMORY_LIMIT)
