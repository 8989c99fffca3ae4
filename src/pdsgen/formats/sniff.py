"""A file's first bytes, for telling what kind of file it is before reading it whole.

Validation asks this of every file it meets (a PDS3 label? an iMars PVL? a PDS4
label? binary data given by mistake?); an unreadable file is not an error here
but "not that kind", and the rule that reads the file reports why it cannot.
"""

from __future__ import annotations

import os

from ..bounded import open_regular


def file_head(path: str | os.PathLike[str], size: int) -> bytes | None:
    """Up to `size` bytes from the start of `path`, or None when it cannot be read or is no
    regular file (a FIFO is not waited on: what a tree holds is never trusted to be a file)."""
    try:
        with open_regular(path) as handle:
            return handle.read(size)
    except OSError:
        return None
