"""Reading a PDS3 label file whole: is it one, its tree, and is its structure known.

Every reader of a PDS3 label in pdsgen (the validator, deliver, Extras, HRSC source
labels, migration) reads the file's head up to END with `read_label_head` and parses it
with `parse_label` (both in parser.py, with the one END rule), so they agree on what a
label is and where it ends.
"""

from __future__ import annotations

import os

from .parser import parse_label, read_on_to_end
from .tree import Issue, Label

# What a PDS3 label file starts with: its first keyword, or the SFDU label that wraps it.
PDS3_STARTS = (b"PDS_VERSION_ID", b"CCSD3")
_FIRST = 65536  # bytes read at a time


def is_pds3_head(head: bytes) -> bool:
    """True when a file's first bytes are those of a PDS3 label."""
    return head.lstrip().upper().startswith(PDS3_STARTS)


def read_pds3_label(path: str | os.PathLike[str], limit: int = 4 << 20) -> Label | None:
    """The label of a PDS3 file (attached or detached), read up to its END line; None when
    the file is no PDS3 label or cannot be read."""
    try:
        with open(path, "rb") as stream:  # one open: most labels are read in their first block
            data = stream.read(_FIRST)
            if not is_pds3_head(data[:64]):
                return None
            head = read_on_to_end(stream, data, _FIRST, _FIRST, limit)
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
