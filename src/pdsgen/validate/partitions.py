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

A worker's directory is not the client's, and a worker is shared (other tasks run in its
process), so it never changes directory: a name relative to the client's directory is read
at its absolute form there, and every name in what comes back is the name as given again
(ClientPaths).
"""

from __future__ import annotations

import dataclasses
import itertools
import os
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from pathlib import PurePath
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


class ClientPaths:
    """A run's names relative to the client's directory `cwd`, on a worker: `absolute` gives
    the name to read, `as_given` turns what was read back to the names the client gave."""

    def __init__(self, cwd: str) -> None:
        self.prefix = os.path.join(cwd, "")

    def absolute(self, item: tuple[str, str | None]) -> tuple[str, str | None]:
        """A file and the directory given that holds it (None: the file was named), read from `cwd`."""
        path, given = item
        return os.path.join(self.prefix, path), os.path.join(self.prefix, given) if given is not None else None

    def as_given(self, item: tuple[str, str | None], value: Result) -> Result:
        """`value` (a report, a summary, facts: strings and paths in lists, tuples, dicts and
        dataclasses) made from the absolute form of `item`, with every name made from it
        relative again - as a run in the client's directory names it."""
        if os.path.isabs(item[0]):
            return value
        return _renamed(value, lambda text: text.replace(self.prefix, ""))


def _renamed(value: Any, rename: Callable[[str], str]) -> Any:
    if isinstance(value, str):
        return rename(value)
    if isinstance(value, PurePath):
        return type(value)(rename(str(value)))
    if isinstance(value, dict):
        return {_renamed(key, rename): _renamed(item, rename) for key, item in value.items()}
    if isinstance(value, (list, set, frozenset)):
        return type(value)(_renamed(item, rename) for item in value)
    if isinstance(value, tuple):
        items = [_renamed(item, rename) for item in value]
        return type(value)(*items) if hasattr(value, "_fields") else tuple(items)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return dataclasses.replace(value, **{field.name: _renamed(getattr(value, field.name), rename)
                                             for field in dataclasses.fields(value) if field.init})
    return value
