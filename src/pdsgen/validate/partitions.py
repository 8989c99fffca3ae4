"""A validation run's per-file work on a Dask cluster: the files, in the order the run
found them, cut into partitions; each partition validated by a worker (labels, schemas,
data, tables - everything `validate_file` does); the results handed back in that same
order, so that everything that looks across files - the SET rules, the delivery checks
(inventories, membership, LIDVID uniqueness), the run checks (PDS4-060) and the report -
runs in the client exactly as in a one-process run, over what the workers return. The
report is then the one-process run's, byte for byte.

The cluster is any object with `submit(function, *args, pure=False)` returning a future
with `result()` - a `distributed.Client`; the command line opens it (batch/cluster.py,
as `pdsgen batch` does) and the runner is given it. At most WINDOW partitions are out at
once: the client holds only their results, however large the tree.
"""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from typing import Any, TypeVar

from ..errors import PdsgenError

PARTITION = 64  # files per task: large enough that a task's overhead is small beside its files
WINDOW = 16  # partitions submitted ahead of the one being read

Item = TypeVar("Item")
Result = TypeVar("Result")


def partitions(items: Iterable[Item], size: int = PARTITION) -> Iterator[list[Item]]:
    """Consecutive runs of `size` items (the last may be shorter), in order."""
    iterator = iter(items)
    while batch := list(itertools.islice(iterator, size)):
        yield batch


def in_partitions(cluster: Any, work: Callable[[list[Item], Any], list[Result]], items: Iterable[Item],
                  job: Any, size: int = PARTITION, window: int = WINDOW) -> Iterator[Result]:
    """work(partition, job) for each partition of `items` on the cluster's workers, the
    results one by one in the items' order."""
    pending: deque[Any] = deque()
    for batch in partitions(items, size):
        pending.append(cluster.submit(work, batch, job, pure=False))
        if len(pending) >= window:
            yield from _result(pending.popleft())
    while pending:
        yield from _result(pending.popleft())


def _result(future: Any) -> list[Any]:
    try:
        return list(future.result())
    except Exception as exc:  # a worker that died or could not run pdsgen: one line, not a traceback
        raise PdsgenError(None, f"a Dask worker could not validate its partition ({type(exc).__name__}: {exc})") \
            from None
