"""Reading a PDS3 label from a file: where its text ends (the one END rule) and its tree.

Every reader of a PDS3 label in pdsgen (the validator, deliver, Extras, HRSC source
labels, migration) reads the file's head up to END with `read_label_head` and parses it
with `parse_label` (parser.py), so they agree on what a label is and where it ends.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from .parser import parse_label
from .tree import Issue, Label

# END (any case: ODL keywords are) alone on its line, maybe with ';' and a comment after it,
# or followed directly by binary data with no line end (ISIS and several pipelines write it
# so). What the parser takes for END, as a pattern on bytes: the reading of a label's head
# stops where it matches.
END_LINE = re.compile(rb"(?im)^[ \t]*END[ \t]*;?[ \t]*(?:/\*.*)?(?:\r?$|(?=[^\x20-\x7e\r\n]))")

# What a PDS3 label file starts with: its first keyword, or the SFDU label that wraps it.
PDS3_STARTS = (b"PDS_VERSION_ID", b"CCSD3")


def has_end(data: bytes) -> bool:
    """True when `data` holds a label's END line."""
    return END_LINE.search(data) is not None


def end_of_label(data: bytes) -> int | None:
    """The offset just past END and what follows it on its line (before the line end), or None."""
    found = END_LINE.search(data)
    return found.end() if found is not None else None


def label_length(data: bytes) -> int | None:
    """The length of the label `data` starts with: up to and including END's line end, or None."""
    end = end_of_label(data)
    if end is None:
        return None
    if data.startswith(b"\r\n", end):
        return end + 2
    return end + 1 if data.startswith((b"\n", b"\r"), end) else end


def is_pds3_head(head: bytes) -> bool:
    """True when a file's first bytes are those of a PDS3 label."""
    return head.lstrip().upper().startswith(PDS3_STARTS)


def read_label_head(path: str | os.PathLike[str], first: int = 65536, step: int = 65536,
                    limit: int = 4 << 20) -> bytes:
    """The file's first bytes up to its label's END line (and the rest of the last block
    read): `first` bytes, then `step` more at a time until END or `limit` bytes. The data
    after an attached label is read no further. OSError when the file cannot be read."""
    with open(path, "rb") as stream:
        data = stream.read(first)
        if len(data) < first or has_end(data):  # the whole file, or its label, read
            return data
        blocks = [data]
        size = len(data)
        while size < limit:
            block = stream.read(min(step, limit - size))
            if not block:
                break
            blocks.append(block)
            size += len(block)
            if has_end(blocks[-2] + block):  # END may straddle two blocks
                break
    return b"".join(blocks)


def read_pds3_label(path: str | os.PathLike[str], limit: int = 4 << 20) -> Label | None:
    """The label of a PDS3 file (attached or detached), read up to its END line; None when
    the file is no PDS3 label or cannot be read."""
    try:
        with open(path, "rb") as stream:
            if not is_pds3_head(stream.read(64)):
                return None
        head = read_label_head(Path(path), limit=limit)
    except OSError:
        return None
    return parse_label(head.decode("latin-1"))


# The reader's rule ids for OBJECT/GROUP blocks that do not close (or close another block).
_STRUCTURE_RULES = ("SYNTAX-005",)


def structure_problem(label: Label) -> Issue | None:
    """The first problem that leaves the label's structure unknown (an OBJECT or GROUP that
    does not close, or closes another), or None. A reader of a label's values refuses such
    a label rather than guess which block a keyword is in; a statement the reader could not
    take (a symbol spanning lines, as some ISIS labels have) is only left out."""
    return next((issue for issue in label.issues if issue.rule in _STRUCTURE_RULES), None)
