"""Reading a PDS3 label file whole, once: its head up to END, the parsed tree and what readers ask of it.

Every reader of a PDS3 label file in pdsgen (the validator's FileContext, deliver's grouping
of files into products, the review page, Extras, the HRSC writer's source labels, migration)
opens it here, so they agree on how much of a file may be label (one limit, LABEL_LIMIT),
on what a label starts with (one head test, `is_pds3_head`) and on the questions they ask
of it: the first value of a keyword anywhere (`first`), the IMAGE object (`image`), the map
projection object (`projection`) and the pointers (`pointers`).

`LabelCache` keeps the labels of one run (a `pdsgen deliver`), so a label that the scan,
the validation and the review page all read is read and parsed once.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path

from .parser import label_length, parse_label, read_on_to_end
from .pointers import Pointer, label_pointers
from .tree import Block, Issue, Label, Statement

FIRST_READ = 256 * 1024  # most labels (and small attached products) are read in one block
LABEL_LIMIT = 16 * 1024 * 1024  # no real label is larger; the head of a file is read no further

# What a PDS3 label file starts with: its first keyword (ODL_VERSION_ID in some PDS version 2
# labels), or the SFDU label that wraps it; blanks before it are allowed, case is not asked.
_PDS3_START = re.compile(rb"\s*(?:PDS_VERSION_ID|ODL_VERSION_ID|CCSD3)", re.IGNORECASE)

# The objects that hold a PDS3 map projection, in the order they are looked for.
PROJECTION_OBJECTS = ("IMAGE_MAP_PROJECTION", "IMAGE_MAP_PROJECTION_CATALOG")


def is_pds3_head(head: bytes) -> bool:
    """True when a file's first bytes are those of a PDS3 label."""
    return _PDS3_START.match(head) is not None


@dataclass(eq=False)
class LabelFile:
    """One PDS3 label file (attached or detached) as read: the bytes up to its END line (and
    the rest of the last block read), the parsed label and the file's size."""

    path: Path
    size: int
    head: bytes
    label: Label
    # The file is its label alone (all of it read, nothing but blanks after END): an attached
    # label whose data are absent. Known when read, so a kept copy may drop the bytes after END.
    label_only: bool = False

    @classmethod
    def read(cls, path: str | os.PathLike[str]) -> LabelFile:
        """The file's label, whatever its first bytes (the validator reports a file that is no
        PDS3 label itself; `is_pds3` says whether it looks like one). OSError when unreadable."""
        found = cls._read(Path(path), pds3_only=False)
        assert found is not None
        return found

    @classmethod
    def read_pds3(cls, path: str | os.PathLike[str]) -> LabelFile | None:
        """The file's label, or None when its first bytes are no PDS3 label's (then nothing
        more of the file is read). OSError when unreadable."""
        return cls._read(Path(path), pds3_only=True)

    @classmethod
    def _read(cls, path: Path, pds3_only: bool) -> LabelFile | None:
        with open(path, "rb") as stream:
            size = os.fstat(stream.fileno()).st_size
            first = stream.read(FIRST_READ)
            if pds3_only and not is_pds3_head(first):
                return None
            head = read_on_to_end(stream, first, FIRST_READ, LABEL_LIMIT, LABEL_LIMIT)
        label = parse_label(head.decode("latin-1"))
        rest = head[label.label_end:]
        return cls(path, size, head, label, len(head) >= size and not rest.strip(b" \r\n\x00\x1a"))

    @property
    def is_pds3(self) -> bool:
        return is_pds3_head(self.head)

    @property
    def root(self) -> Block:
        return self.label.root

    @property
    def end_found(self) -> bool:
        return self.label.end_found

    def first_statement(self, key: str) -> Statement | None:
        return first_statement(self.root, key)

    def first(self, key: str) -> str | None:
        """`key`'s value as written (a string unquoted), at the top or in the first block that
        has it as a single value; None when no block has."""
        return first_text(self.root, key)

    def image(self) -> Block | None:
        return image_object(self.root)

    def projection(self) -> Block | None:
        return projection_object(self.root)

    @cached_property
    def pointers(self) -> list[Pointer]:
        """The pointers of the label's top level, classified (label/pointers.py)."""
        return label_pointers(self.root)

    def at(self, path: Path) -> LabelFile:
        """The same label as read through another name of the file (a hard link)."""
        return self if path == self.path else replace(self, path=path)

    def kept(self) -> LabelFile:
        """This label without the bytes after its END line (what a cache holds: an attached
        label's data are not kept in memory)."""
        end = label_length(self.head)
        return self if end is None or end >= len(self.head) else replace(self, head=self.head[:end])


def first_statement(root: Block, key: str) -> Statement | None:
    """The first statement of `key` with a single value, at the top or in the first block that has one."""
    for block in root.walk():
        stmt = block.get(key)
        if stmt is not None and stmt.value.items is None:
            return stmt
    return None


def first_text(root: Block, key: str) -> str | None:
    stmt = first_statement(root, key)
    return stmt.value.text if stmt is not None else None


def image_object(root: Block) -> Block | None:
    """The label's IMAGE object (at the top, or the uncompressed file's of a JP2 label)."""
    for block in root.walk():
        if block is not root and block.name.upper() == "IMAGE" and block.kind == "OBJECT":
            return block
    return None


def projection_object(root: Block) -> Block | None:
    """The label's map projection object (IMAGE_MAP_PROJECTION, else ..._CATALOG), at any depth."""
    for name in PROJECTION_OBJECTS:
        found = next(root.find(name), None)
        if found is not None:
            return found
    return None


def read_pds3_label(path: str | os.PathLike[str], labels: LabelCache | None = None) -> LabelFile | None:
    """The label of a PDS3 label file, read up to its END line (the data after an attached
    label are never read); None when the file does not start as a PDS3 label or cannot be
    read. `labels`: the run's cache, when there is one."""
    try:
        return labels.open_pds3(path) if labels is not None else LabelFile.read_pds3(path)
    except OSError:
        return None


class LabelCache:
    """The labels read in one run, each parsed once: keyed by the file itself (device, inode,
    size, modification time), so a label seen again under another name of the same file (the
    delivery's hard link of a product) or read again by another step is not read again, and a
    file changed in between is read anew. A label is kept without the bytes after its END
    line. `parses` counts the files read and parsed, by path."""

    def __init__(self) -> None:
        self._labels: dict[tuple[int, int, int, int], LabelFile | None] = {}
        self.parses: dict[Path, int] = {}

    def open(self, path: str | os.PathLike[str]) -> LabelFile:
        """The file's label, whatever its first bytes (as `LabelFile.read`); OSError when unreadable."""
        path = Path(path)
        key = _file_key(path)
        found = self._labels.get(key)
        if found is None:
            found = self._keep(key, path, LabelFile.read(path))
        return found.at(path)

    def open_pds3(self, path: str | os.PathLike[str]) -> LabelFile | None:
        """The file's label, or None when it does not start as one (as `LabelFile.read_pds3`)."""
        path = Path(path)
        key = _file_key(path)
        if key in self._labels:
            found = self._labels[key]
            return found.at(path) if found is not None and found.is_pds3 else None
        fresh = LabelFile.read_pds3(path)
        if fresh is None:
            self._labels[key] = None
            return None
        return self._keep(key, path, fresh)

    def _keep(self, key: tuple[int, int, int, int], path: Path, fresh: LabelFile) -> LabelFile:
        self.parses[path] = self.parses.get(path, 0) + 1
        self._labels[key] = fresh.kept()
        return fresh


def _file_key(path: Path) -> tuple[int, int, int, int]:
    info = path.stat()
    return info.st_dev, info.st_ino, info.st_size, info.st_mtime_ns


# The reader's rule ids for OBJECT/GROUP blocks that do not close (or close another block).
_STRUCTURE_RULES = ("SYNTAX-005",)


def structure_problem(label: Label) -> Issue | None:
    """The first problem that leaves the label's structure unknown (an OBJECT or GROUP that
    does not close, or closes another), or None. A reader of a label's values refuses such
    a label rather than guess which block a keyword is in; a statement the reader could not
    take (a symbol spanning lines, as some ISIS labels have) is only left out."""
    return next((issue for issue in label.issues if issue.rule in _STRUCTURE_RULES), None)
