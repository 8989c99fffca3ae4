"""Whether a file is a PDS4 label, decided from its first bytes.

Kept apart from the PDS4 checks (validate/pds4/) so that telling PDS4 labels from PDS3
ones (done for every file a validation run meets) does not load lxml and the PDS4 checks;
a run over PDS3 labels never imports them.

Decided by content, not by extension: PDS4 labels are .xml by custom but .lblx
by the standard's own recommendation for new archives, and either may be met.
"""

from __future__ import annotations

from pathlib import Path

from ..formats.sniff import file_head
from ..resources import user_cache_dir

# The names a PDS4 label file may have: .xml by custom, .lblx as the standard recommends.
LABEL_SUFFIXES = (".xml", ".lblx")
_HEAD_BYTES = 8192
_PDS4_NAMESPACE = b"http://pds.nasa.gov/pds4/pds/v1"
_BOM = b"\xef\xbb\xbf"


def is_pds4_label(path: Path) -> bool:
    """A file that starts as XML and names a PDS4 Product_* root in the PDS namespace
    within its first few KB, whatever its name."""
    head = file_head(path, _HEAD_BYTES) or b""
    if not head.removeprefix(_BOM).lstrip().startswith(b"<"):
        return False  # binary data, PDS3 text: not XML, decided from the first byte
    return _PDS4_NAMESPACE in head and b"<Product_" in head


def default_schema_cache() -> Path:
    """Where downloaded PDS4 schemas are kept: ~/.cache/pdsgen/pds4-schemas (or under
    $XDG_CACHE_HOME). Here, not in `catalog`, so the CLI can name it without lxml."""
    return user_cache_dir("pds4-schemas")
