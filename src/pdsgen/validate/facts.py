"""Facts about one file that checks across files join, made where the file is validated.

A check across files (a delivery's inventories and membership, LIDVID uniqueness, or any
run-level rule) runs once, in the run's own process, after the per-file work. Reading
every label again there makes that process the bottleneck of a parallel run: with
100,000 labels it parses them all alone while the workers wait. So such a check reads a
file through `of(reader, path)`, with a reader registered by `fact(target)`: in a run
with workers (`-j N`, a Dask cluster) each worker applies every registered reader of the
file's target to each file it validates (`made`) and returns the results beside the
file's report; the run's process `learn`s them and `of` hands them out, once each. A
file no worker read (and any file in a one-process run) is read by `of` itself, so the
checks find the same either way - nothing here knows what any check reads.

Readers run in worker processes: they take a Path and return something picklable (or None).
The run's process keeps what it learns pickled (`made` pickles in the worker), a few hundred
bytes a file instead of the objects' few kilobytes: a delivery of 100,000 products learns the
facts of every label before its check reads them (runner.py), and unpickles each only when
asked.
"""

from __future__ import annotations

import os
import pickle
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

Reader = TypeVar("Reader", bound=Callable[[Any], Any])

_READERS: dict[str, dict[str, Callable[[Any], Any]]] = {}  # target -> reader name -> reader
_LEARNT: dict[str, dict[str, bytes]] = {}  # file -> reader name -> what a worker read, pickled


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


def read(path: str, target: str) -> dict[str, Any]:
    """Every registered reader of `target` applied to the file (in a worker)."""
    return {name: reader(Path(path)) for name, reader in _READERS.get(target, {}).items()}


def packed(read: dict[str, Any]) -> dict[str, bytes]:
    """What `read` returned, each reader's result pickled (as the run's process keeps it)."""
    return {name: pickle.dumps(value, pickle.HIGHEST_PROTOCOL) for name, value in read.items()}


def made(path: str, target: str) -> dict[str, bytes]:
    """Every registered reader of `target` applied to the file, pickled (in a worker)."""
    return packed(read(path, target))


def learn(path: str, facts: dict[str, bytes]) -> None:
    """What a worker read of a file (`made`), kept for `of`."""
    if facts:  # the reader names once in this process, not a copy a file
        _LEARNT.setdefault(_key(path), {}).update((sys.intern(name), value) for name, value in facts.items())


def of(reader: Callable[[Any], Any], path: Any) -> Any:
    """reader(path): what a worker read of the file, handed out once, or read here."""
    key = _key(path)
    learnt = _LEARNT.get(key, {})
    value = learnt.pop(_name(reader), None)
    if value is None:
        return reader(path)
    if not learnt:
        del _LEARNT[key]
    return pickle.loads(value)  # pickled by this run's own workers (made), never read from a file


def drop(path: str) -> None:
    """Drop what was learnt of a file whose report has passed every check across files (a
    reader no check asked for, as in a run without a delivery, is not kept to the end)."""
    _LEARNT.pop(_key(path), None)


def forget() -> None:
    """Drop what was learnt (a run's end: the files may change before the next run)."""
    _LEARNT.clear()
