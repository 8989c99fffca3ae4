"""Whether a file is a PDS4 label, decided from its first bytes.

Kept apart from `validate` so that telling PDS4 labels from PDS3 ones (done for
every file a validation run meets) does not load lxml and the PDS4 checks; a run
over PDS3 labels never imports them.
"""

from __future__ import annotations

from pathlib import Path

from ..formats.sniff import file_head

_HEAD_BYTES = 8192
_PDS4_NAMESPACE = b"http://pds.nasa.gov/pds4/pds/v1"


def is_pds4_label(path: Path) -> bool:
    """An .xml file whose root element is a PDS4 Product_* (read from its first few KB)."""
    if path.suffix.lower() != ".xml":
        return False
    head = file_head(path, _HEAD_BYTES) or b""
    return _PDS4_NAMESPACE in head and b"<Product_" in head
