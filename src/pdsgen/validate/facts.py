"""Facts about one file that checks across files join, made where the file is validated.

A check across files (a delivery's inventories and membership, LIDVID uniqueness, or any
run-level rule) runs once, in one process: the run's own, or for a delivery on workers one
forked to check it before the files are validated (runner.py). Reading every label again
there makes that process the bottleneck of a parallel run: with 100,000 labels it parses
them all alone while the workers wait. So such a check reads a file through
`of(reader, path)`, with a reader registered by `fact(target)`: in a run with workers
(`-j N`, a Dask cluster) each worker applies the registered readers of the file's target to
each file it is given (`made`) and returns the results; the checking process `learn`s them
and `of` hands them out, once each (`asked` tells which readers a check used, so that the
workers need not apply them again). A file no worker read (and any file in a one-process
run) is read by `of` itself, so the checks find the same either way - nothing here knows
what any check reads.

Readers run in worker processes: they take a Path and return something picklable (or None).
What a process learns is kept pickled (`made` pickles in the worker) in a temporary file of
its own, with one number a file in memory to find it: a delivery of 100,000 products learns
the facts of every label before its check reads them (runner.py), and its labels' objects
(a couple of kilobytes each) exist only while the check holds them.
"""

from __future__ import annotations

import os
import pickle
import tempfile
from collections.abc import Callable, Collection
from pathlib import Path
from typing import Any, TypeVar

Reader = TypeVar("Reader", bound=Callable[[Any], Any])

_READERS: dict[str, dict[str, Callable[[Any], Any]]] = {}  # target -> reader name -> reader
_AT: dict[str, int] = {}  # file -> where what was learnt of it is in the store: offset << 32 | length
_STORE: dict[int, Any] = {}  # process id -> the temporary file what is learnt is kept in (a fork opens its own)
_ASKED: set[str] = set()  # the readers `of` was asked for since the last `forget`


def _name(reader: Callable[[Any], Any]) -> str:
    return f"{reader.__module__}.{reader.__qualname__}"


def _key(path: Any) -> str:
    return os.path.abspath(os.fspath(path))


def fact(target: str) -> Callable[[Reader], Reader]:
    """Register a reader of one file of `target` (a rule target: "pds4", "label", "imars")
    whose result a check across files takes through `of`."""

    def register(reader: Reader) -> Reader:
        _READERS.setdefault(target, {})[_name(reader)] = reader
        return reader

    return register


def read(path: str, target: str, skip: Collection[str] = ()) -> dict[str, Any]:
    """Every registered reader of `target` applied to the file (in a worker), but those named in
    `skip` (readers whose checks have already run: `asked`)."""
    return {name: reader(Path(path)) for name, reader in _READERS.get(target, {}).items() if name not in skip}


def packed(read: dict[str, Any]) -> dict[str, bytes]:
    """What `read` returned, each reader's result pickled (as the run's process keeps it)."""
    return {name: pickle.dumps(value, pickle.HIGHEST_PROTOCOL) for name, value in read.items()}


def made(path: str, target: str) -> dict[str, bytes]:
    """Every registered reader of `target` applied to the file, pickled (in a worker)."""
    return packed(read(path, target))


def learn(path: str, facts: dict[str, bytes]) -> None:
    """What a worker read of a file (`made`), kept for `of`."""
    if facts:
        key = _key(path)
        _keep(key, {**_taken(key), **facts})


def of(reader: Callable[[Any], Any], path: Any) -> Any:
    """reader(path): what a worker read of the file, handed out once, or read here."""
    key, name = _key(path), _name(reader)
    _ASKED.add(name)
    learnt = _taken(key)
    value = learnt.pop(name, None)
    if learnt:
        _keep(key, learnt)
    if value is None:
        return reader(path)
    return pickle.loads(value)  # pickled by this run's own workers (made), never read from an input


def _keep(key: str, learnt: dict[str, bytes]) -> None:
    store = _STORE.get(os.getpid())
    if store is None:
        store = _STORE[os.getpid()] = tempfile.TemporaryFile()
    data = pickle.dumps(learnt, pickle.HIGHEST_PROTOCOL)
    offset = store.seek(0, os.SEEK_END)
    store.write(data)
    _AT[key] = offset << 32 | len(data)


def _taken(key: str) -> dict[str, bytes]:
    """What was learnt of a file, no longer kept ({} when nothing was)."""
    where = _AT.pop(key, None)
    store = _STORE.get(os.getpid())
    if where is None or store is None:
        return {}
    store.seek(where >> 32)
    return pickle.loads(store.read(where & 0xFFFFFFFF))  # written by _keep in this process


def drop(path: str) -> None:
    """Drop what was learnt of a file whose report has passed every check across files (a
    reader no check asked for, as in a run without a delivery, is not kept to the end)."""
    _AT.pop(_key(path), None)


def asked() -> frozenset[str]:
    """The readers asked for since the last `forget` (those a check across files has used)."""
    return frozenset(_ASKED)


def forget() -> None:
    """Drop what was learnt (a run's end: the files may change before the next run)."""
    _AT.clear()
    _ASKED.clear()
    store = _STORE.pop(os.getpid(), None)
    if store is not None:
        store.close()
