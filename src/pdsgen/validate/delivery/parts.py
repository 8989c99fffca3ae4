"""What every delivery check shares: a finding before its severity is known, the reading of a
PDS3 label through the run's cache, the walk of a delivery's files and the containment of a name
a delivery's own table gives."""

from __future__ import annotations

import os
import stat
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ...bounded import open_regular
from ...label.tree import Block, first_statement
from ...storage.containment import link_leaves

if TYPE_CHECKING:
    from ...label.read import LabelCache


@dataclass
class Found:
    """One finding of a delivery check: the rule's severity is added when it is reported."""

    rule: str
    file: Path
    message: str
    line: int | None = None
    keyword: str | None = None


def read_pds3(path: Path, labels: LabelCache | None) -> Block | None:
    """A PDS3 label's tree, reading no further than its END line; None when it is no PDS3 label."""
    from ...label.read import read_pds3_label  # start-up: loaded only when a delivery is checked

    label = read_pds3_label(path, labels)
    return label.root if label is not None else None


def first(root: Block, keyword: str) -> tuple[str | None, int | None]:
    stmt = first_statement(root, keyword)
    return (stmt.value.text, stmt.line) if stmt is not None else (None, None)


def all_files(root: Path) -> Iterator[Path]:
    """The regular files of the delivery, in order. A FIFO, socket or device is no file an
    archive holds and is never opened (reading a FIFO waits for ever), nor is a link leading
    out of the delivery (/etc/passwd named DATA/X.LBL): irregular_files names them."""
    for path in _entries(root):
        if _regular(path, root):
            yield path


def irregular_files(root: Path) -> Iterator[Path]:
    """What the delivery holds that is not a regular file inside it (a FIFO, socket, device, a
    link dangling or leading outside)."""
    for path in _entries(root):
        if not _regular(path, root):
            yield path


def _entries(root: Path) -> Iterator[Path]:
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames.sort()
        for name in sorted(filenames):
            yield Path(dirpath) / name


def _regular(path: Path, root: Path) -> bool:
    try:
        mode = path.lstat().st_mode
        if stat.S_ISLNK(mode):  # a link: only one to a regular file of the delivery (the rare case pays)
            return not link_leaves(path, root) and stat.S_ISREG(path.stat().st_mode)
        return stat.S_ISREG(mode)
    except OSError:  # gone, or a link loop
        return False


def read_head(path: Path) -> bytes:
    try:
        with open_regular(path) as stream:
            return stream.read(32)
    except OSError:
        return b""


def named_inside(root: Path, name: str) -> tuple[Path | None, str | None]:
    """(the path, None) of a file a delivery's own table names (MD5SUMS.TXT, INDEX.TAB), by the
    containment rule; (None, why) for a name no file inside the delivery can have."""
    from ...storage.containment import contained, name_problem

    problem = name_problem(name)
    if problem is not None:
        return None, problem
    path = root.joinpath(*name.split("/"))
    return (path, None) if contained(path, root) is not None else (None, "a link leads out of it")

