"""Reading a PDS3 label file whole, once: its head up to END, the parsed tree and what readers ask of it.

Every reader of a PDS3 label file in pdsgen (the validator's FileContext, deliver's grouping
of files into products, the review page, Extras, the HRSC writer's source labels, migration)
opens it as a `LabelFile` (defined in parser.py, beside the END rule, so that a product
writer's check of its own label loads no more modules), so they agree on how much of a
file may be label (one limit, LABEL_LIMIT), on what a label starts with (one head test,
`is_pds3_head`) and on the questions they ask of it: the first value of a keyword anywhere
(`first`), the IMAGE object (`image`), the map projection object (`projection`) and the
pointers (`pointers`).

`LabelCache` keeps the labels of one run (a `pdsgen deliver`), so a label that the scan,
the validation and the review page all read is read and parsed once.
"""

from __future__ import annotations

import os
from pathlib import Path

from .parser import FIRST_READ, LABEL_LIMIT, LabelFile, is_pds3_head
from .tree import PROJECTION_OBJECTS, Issue, Label, first_statement, first_text, image_object, projection_object

# The label file object and the questions asked of a tree live beside the parser and the tree
# (parser.py, tree.py: all that a product writer's check of its own label loads); named here
# too, the home of reading a label file whole.
__all__ = ["FIRST_READ", "LABEL_LIMIT", "PROJECTION_OBJECTS", "LabelCache", "LabelFile", "first_statement",
           "first_text", "image_object", "is_pds3_head", "projection_object", "read_pds3_label",
           "structure_problem"]


def read_pds3_label(path: str | os.PathLike[str], labels: LabelCache | None = None) -> LabelFile | None:
    """The label of a PDS3 label file, read up to its END line (the data after an attached
    label are never read); None when the file does not start as a PDS3 label or cannot be
    read. `labels`: the run's cache, when there is one."""
    try:
        return labels.open_pds3(path) if labels is not None else LabelFile.read_pds3(path)
    except OSError:
        return None


# What a run's cache may hold, in bytes of label text kept. A parsed tree takes about eleven
# times its text in memory (measured on the genuine labels in tests/data: 110 KiB for 10 KiB),
# so 96 MiB of text is about 1 GiB of trees: some 10,000 typical labels parsed once, and a
# larger delivery no more memory than that - its later labels are read again by each step.
CACHE_TEXT_BYTES = 96 << 20


class LabelCache:
    """The labels read in one run, each parsed once: keyed by the file itself (device, inode,
    size, modification time), so a label seen again under another name of the same file (the
    delivery's hard link of a product) or read again by another step is not read again, and a
    file changed in between is read anew. A label is kept without the bytes after its END
    line, and only while the labels kept hold at most `text_bytes` of text: memory stays
    bounded whatever the number of labels (past the bound a label is read by each step that
    asks). `parses` counts the files read and parsed, by path."""

    def __init__(self, text_bytes: int = CACHE_TEXT_BYTES) -> None:
        self._labels: dict[tuple[int, int, int, int], LabelFile | None] = {}
        self._room = text_bytes
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
        kept = fresh.kept()
        if len(kept.head) <= self._room:
            self._room -= len(kept.head)
            self._labels[key] = kept
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
