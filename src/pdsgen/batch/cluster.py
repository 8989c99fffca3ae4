"""The Dask cluster a batch runs on: a local one of processes, or a running scheduler.

Jobs declare the memory they need as the worker resource MEMORY (bytes), so a
worker is never given more concurrent jobs than it has memory for. Before anything
is submitted the workers are checked - they run this pdsgen version and some worker
has the memory each job asks for - because a job no worker can take would wait
forever without a word.
"""

from __future__ import annotations

import contextlib
import logging
import os
from collections.abc import Iterator, Sequence
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
        memory = _total_memory() // workers
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
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


def check_workers(client: Any, jobs: Sequence[Job], version: str) -> None:
    """PdsgenError (one line) unless the workers run pdsgen VERSION and can take every job."""
    try:
        versions = client.run(_pdsgen_version)
    except Exception as exc:  # unpickling fails on a worker without pdsgen
        raise PdsgenError(None, f"the Dask workers cannot run pdsgen ({type(exc).__name__}: {exc})") from None
    wrong = {addr: v for addr, v in versions.items() if v != version}
    if wrong:
        addr, other = next(iter(wrong.items()))
        raise PdsgenError(None, f"{len(wrong)} Dask worker(s) run pdsgen {other} (e.g. {addr}); "
                                f"this client runs {version}: install the same version everywhere")
    workers = client.scheduler_info()["workers"]
    largest = max((w.get("resources", {}).get(RESOURCE, 0) for w in workers.values()), default=0)
    if not largest:
        raise PdsgenError(None, f"no Dask worker declares its memory for jobs: start workers with "
                                f"--resources {RESOURCE}=BYTES (e.g. {RESOURCE}=8e9)")
    too_big = max(jobs, key=lambda j: j.memory)
    if too_big.memory > largest:
        raise PdsgenError(None, f"job {too_big.id!r} needs memory {_gb(too_big.memory)} but the largest Dask "
                                f"worker offers {RESOURCE}={_gb(largest)}")


def _pdsgen_version() -> str:
    from .. import __version__

    return __version__


def _gb(size: float) -> str:
    return f"{size / 1e9:.2f} GB"


def _total_memory() -> int:
    from distributed.system import MEMORY_LIMIT

    return int(MEMORY_LIMIT)
