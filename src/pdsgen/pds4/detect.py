"""Whether a file is a PDS4 label, decided from its prolog and root element.

Kept apart from the PDS4 checks (validate/pds4/) so that telling PDS4 labels from PDS3
ones (done for every file a validation run meets) does not load lxml and the PDS4 checks;
a run over PDS3 labels never imports them.

Decided by content, not by extension: PDS4 labels are .xml by custom but .lblx
by the standard's own recommendation for new archives, and either may be met.

XML puts no limit on what comes before the root element (the declaration, comments,
processing instructions, a document type declaration), so the prolog is read as far as
it goes, not only a first few KB: a long comment cannot hide a label's root and let a
directory run pass over it. A file that starts as XML but whose root element cannot be
found (a comment never closed, a prolog beyond `MAX_PROLOG_BYTES`) is taken for a PDS4
label too, so that its checks report it rather than nothing being said.
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path

from ..resources import user_cache_dir

# The names a PDS4 label file may have: .xml by custom, .lblx as the standard recommends.
LABEL_SUFFIXES = (".xml", ".lblx")
_HEAD_BYTES = 8192  # what tells a data file or a PDS3 label from XML, read first
_CHUNK_BYTES = 65536
MAX_PROLOG_BYTES = 64 * 1024 * 1024  # a prolog longer than this is not read on: the file is reported
_MAX_KEPT_BYTES = 1024 * 1024  # a document type declaration or root start tag longer is not read on
_PDS4_NAMESPACE = b"http://pds.nasa.gov/pds4/pds/v1"
_BOM = b"\xef\xbb\xbf"
_XML_STARTS = (b"<?xml", b"<!--", b"<!DOCTYPE")
# What may come before the root element, each matched whole: a processing instruction
# (the declaration, xml-model), a comment, a document type declaration (its internal
# subset's quoted strings and comments may hold '>' and ']'), or white space. Each
# alternative starts differently from the others, so a prolog that never ends fails in
# linear time (a comment inside the subset is matched only to its first `-->`).
_PROLOG_ITEM = re.compile(rb"""\s+|<\?.*?\?>|<!--.*?-->|<!DOCTYPE(?:[^\[>"']|"[^"]*"|'[^']*')*"""
                          rb"""(?:\[(?:[^\]"'<]|"[^"]*"|'[^']*'|<!--(?:[^-]|-(?!-))*-->|<(?!!--)[^>"']*(?:(?:"[^"]*"|'[^']*')[^>"']*)*>)*\]\s*)?>""",
                          re.S)
_ROOT_TAG = re.compile(rb"""<([^\s/>!?]+)(?:[^>"']|"[^"]*"|'[^']*')*>""", re.S)
_ROOT_START = re.compile(rb"<[^\s/>!?]")
_TAG_STOP = re.compile(rb"""[>"']""")


def is_pds4_label(path: Path) -> bool:
    """A file whose root element is a Product_* in the PDS namespace, whatever its name;
    or one that starts as XML whose root element cannot be found (reported by the checks)."""
    verdict = _root_verdict(path)
    return verdict is None or verdict


def _root_verdict(path: Path) -> bool | None:
    """True for a PDS4 root, False for anything else (not XML, another root), None for
    XML whose root element cannot be found."""
    root = _root_in_file(path)
    return _is_pds4_root(root) if isinstance(root, re.Match) else root


def root_name(path: Path) -> str | None:
    """The local name of an XML file's root element (its prefix dropped: `Product_Bundle`),
    read as `is_pds4_label` reads it - the prolog item by item in linear time, a FIFO never
    opened - or None for a file that is no XML, whose root cannot be found, or unreadable."""
    root = _root_in_file(path)
    return root[1].rsplit(b":", 1)[-1].decode("ascii", "replace") if isinstance(root, re.Match) else None


def _root_in_file(path: Path) -> re.Match[bytes] | bool | None:
    """_root_of the file at `path`; False for one that is not a regular file (a FIFO or device
    is never read here: reading one may never end) or cannot be read."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return False
        with open(path, "rb") as handle:
            return _root_of(handle, path)
    except OSError:
        return False


def _root_of(handle, path: Path) -> re.Match[bytes] | bool | None:  # noqa: ANN001 - a binary file object
    """The root element's start tag (a match of _ROOT_TAG); False for a file that is no XML;
    None for XML whose root cannot be found (or not found within the bounds). The prolog is
    read item by item, in chunks, keeping only what is not yet consumed; a comment or
    processing instruction is skipped to its end without being kept whole."""
    data = handle.read(_HEAD_BYTES)
    if data.removeprefix(_BOM).lstrip()[:1] not in (b"", b"<"):
        return False  # binary data, PDS3 text: not XML, decided from the first bytes (most files a walk meets)
    data = (data + handle.read(_CHUNK_BYTES - _HEAD_BYTES)).removeprefix(_BOM)
    start = data.lstrip()
    if not start.startswith(b"<"):
        return False
    unfound = None if start.startswith(_XML_STARTS) or path.suffix.lower() in LABEL_SUFFIXES else False
    read = len(data)
    while True:
        position = 0
        while (item := _PROLOG_ITEM.match(data, position)) is not None:
            position = item.end()
        rest = data[position:]
        if _ROOT_START.match(rest):
            tag = _root_start_tag(rest, handle, read)
            root = _ROOT_TAG.match(tag) if tag is not None else None
            return root if root is not None else unfound
        mark = b"-->" if rest.startswith(b"<!--") else b"?>" if rest.startswith(b"<?") else None
        if mark is not None:  # a comment or instruction running past this chunk: find its end
            found = rest.find(mark, len(mark) + 1)
            while found < 0:
                more = handle.read(_CHUNK_BYTES)
                read += len(more)
                if not more or read > MAX_PROLOG_BYTES:
                    return unfound
                rest = rest[-len(mark):] + more
                found = rest.find(mark)
            data = rest[found + len(mark):]
            continue
        more = handle.read(_CHUNK_BYTES)
        read += len(more)
        if not more or read > MAX_PROLOG_BYTES or len(rest) > _MAX_KEPT_BYTES:
            return unfound
        data = rest + more


def _root_start_tag(data: bytes, handle, read: int) -> bytes | None:  # noqa: ANN001 - a binary file
    """The root element's whole start tag (DATA begins with it), read on in chunks. Its end is
    looked for from where the previous look stopped (a quoted value may hold '>'), so a start
    tag of 80,000 namespace declarations is scanned once, not again from its start for every
    chunk read. None when it does not end within the bounds."""
    kept, position, quote = bytearray(data), 1, b""
    while True:
        while position < len(kept):
            if quote:
                end = kept.find(quote, position)
                position, quote = (len(kept), quote) if end < 0 else (end + 1, b"")
                continue
            stop = _TAG_STOP.search(kept, position)
            if stop is None:
                position = len(kept)
            elif stop[0] == b">":
                return bytes(kept[:stop.end()])
            else:
                position, quote = stop.end(), stop[0]
        more = handle.read(_CHUNK_BYTES)
        read += len(more)
        if not more or read > MAX_PROLOG_BYTES or len(kept) > _MAX_KEPT_BYTES:
            return None
        kept += more


def _is_pds4_root(root: re.Match[bytes]) -> bool:
    """A Product_* element (any prefix) whose start tag declares the PDS namespace."""
    local = root[1].rsplit(b":", 1)[-1]
    return local.startswith(b"Product_") and _PDS4_NAMESPACE in root[0]


def default_schema_cache() -> Path:
    """Where downloaded PDS4 schemas are kept: ~/.cache/pdsgen/pds4-schemas (or under
    $XDG_CACHE_HOME). Here, not in `catalog`, so the CLI can name it without lxml."""
    return user_cache_dir("pds4-schemas")
