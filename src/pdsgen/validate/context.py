"""What every rule gets for one file: the parsed label, its bytes, and its data pointers.

The label is read and parsed once here; rule families only look things up. Data
files are never read here (only stat'ed), so label-only validation stays fast.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..label.parser import parse_label, read_label_head
from ..label.tree import Block, Label, Statement, Value
from .dictionary import load as load_dictionary

if TYPE_CHECKING:
    from ..label.beside import DirectoryNames

_FIRST_READ = 256 * 1024
_MAX_LABEL = 16 * 1024 * 1024

# Pointers that name documentation or format files kept elsewhere in an archive
# (CATALOG/, DOCUMENT/, LABEL/), not data objects in this product.
REFERENCE_POINTERS = frozenset(
    {
        "DATA_SET_MAP_PROJECTION",
        "DATA_SET_MAP_PROJECTION_CATALOG",
        "DESCRIPTION",
        "STRUCTURE",
        "CATALOG",
        "DATA_SET_CATALOG",
        "INSTRUMENT_CATALOG",
        "MISSION_CATALOG",
        "TARGET_CATALOG",
        "SOFTWARE_CATALOG",
        "PERSONNEL_CATALOG",
        "REFERENCE_CATALOG",
        "INSTRUMENT_HOST_CATALOG",
        "SPICE_KERNEL",
        "TEXT",
        "LABEL",
    }
)


@dataclass(slots=True)
class Pointer:
    """A data pointer, resolved: which file, which byte the object starts at (0-based)."""

    name: str  # object name without the caret, upper case
    statement: Statement
    form: str  # "record", "bytes", "file", "file+record", "file+bytes", "files", "invalid"
    file_name: str | None  # as written in the label; None for an attached object
    record: int | None  # 1-based record number as written
    byte: int | None  # 1-based byte number as written (<BYTES> forms)
    file_names: tuple[str, ...] = ()  # the "files" form: each file named

    @property
    def targets(self) -> tuple[str, ...]:
        """Every file the pointer names (none for an attached object)."""
        return (self.file_name,) if self.file_name is not None else self.file_names

    @property
    def attached(self) -> bool:
        return self.file_name is None and self.form != "files"

    @property
    def is_reference(self) -> bool:
        return self.name in REFERENCE_POINTERS or self.name.endswith("_CATALOG")


# A file name in a pointer: "quoted", bare, or 'single-quoted' (Cassini ISS and NEAR labels
# as ISIS writes them; GDAL and pvl read all three).
_NAME_KINDS = ("string", "ident", "symbol")


def parse_pointer(stmt: Statement) -> Pointer:
    """Classify a pointer value into one of the PDS3 forms (or "invalid")."""
    val = stmt.value
    name = stmt.keyword.upper()

    def loc(v: Value) -> tuple[str, int | None, int | None]:
        if v.kind != "int":
            return "invalid", None, None
        if v.unit is None:
            return "record", int(v.number), None
        if v.unit.upper() == "BYTES":
            return "bytes", None, int(v.number)
        return "invalid", None, None

    if val.kind in _NAME_KINDS and val.items is None:
        return Pointer(name, stmt, "file", val.text, None, None)
    if val.kind == "int":
        form, record, byte = loc(val)
        return Pointer(name, stmt, form, None, record, byte)
    if val.kind == "seq" and val.items and len(val.items) == 2:
        first, second = val.items
        if first.kind in _NAME_KINDS and first.items is None:
            form, record, byte = loc(second)
            if form != "invalid":
                return Pointer(name, stmt, "file+" + form, first.text, record, byte)
    if val.kind in ("seq", "set") and val.items and all(v.kind in _NAME_KINDS for v in val.items):
        # several files, each holding a part (a document in a header and a source file):
        # {"A.H", "B.C"} in the Galileo Probe archive; NASA's PDS3 label tools read a set of
        # file names as one pointer to each
        return Pointer(name, stmt, "files", None, None, None, tuple(v.text for v in val.items))
    return Pointer(name, stmt, "invalid", None, None, None)


class FileContext:
    """One label file being validated, with lazy helpers the rule families share."""

    def __init__(self, path: Path, labels_only: bool = False, dictionaries: tuple[str, ...] = (),
                 strict: bool = False) -> None:
        self.path = path
        self.labels_only = labels_only
        self.dictionaries = dictionaries
        self.strict = strict
        # What rule families compute once per file and share, by key: "_is_hrsc" (profiles),
        # "_dict_statements"/"_dict_defined" (DICT), "_img_stats" (IMG), "_map_offsets" (MAP),
        # "_jp2" (GEO). Declared here so no family sets attributes of its own on the context.
        self.cache: dict[str, Any] = {}
        self.size = path.stat().st_size
        self.head = self._read_head()
        self.label: Label = parse_label(self.head.decode("latin-1"))

    def _read_head(self) -> bytes:
        """The label bytes (and a little after): enough to find END in any real label."""
        return read_label_head(self.path, first=_FIRST_READ, step=_MAX_LABEL, limit=_MAX_LABEL)

    @property
    def dictionary(self):
        """The keyword dictionary (with any extra dictionaries the user named)."""
        return load_dictionary(self.dictionaries)

    # -- label look-ups ------------------------------------------------------------
    @property
    def root(self) -> Block:
        return self.label.root

    @cached_property
    def pointers(self) -> list[Pointer]:
        return [parse_pointer(s) for s in self.root.statements() if s.pointer]

    def data_pointers(self) -> Iterator[Pointer]:
        for ptr in self.pointers:
            if not ptr.is_reference:
                yield ptr

    @cached_property
    def attached(self) -> bool:
        """True when the file carries data after its label (an attached label)."""
        return any(p.attached and p.form != "invalid" for p in self.data_pointers())

    @cached_property
    def written_by_pdsgen(self) -> bool:
        """pdsgen states itself in SOFTWARE_NAME ("pdsgen 0.4.0") of every label it writes."""
        return (self.root.text("SOFTWARE_NAME") or "").strip().lower().startswith("pdsgen ")

    @cached_property
    def data_absent(self) -> bool:
        """True for an attached label whose file ends with the label: a label-only copy.

        Its pointers describe data that are not there, so nothing about the data can be
        checked (and nothing must be computed from the label's own bytes instead)."""
        if not self.attached or not self.label.end_found:
            return False
        starts = [self.pointer_offset(p) for p in self.data_pointers() if p.attached]
        first = min((s for s in starts if s is not None), default=None)
        if first is None or first >= self.size:
            return True
        rest = self.head[self.label.label_end:]
        return len(self.head) >= self.size and not rest.strip(b" \r\n\x00\x1a")

    @property
    def record_bytes(self) -> int | None:
        val = self.root.number("RECORD_BYTES")
        return int(val) if isinstance(val, int) else None

    def pointer_offset(self, ptr: Pointer) -> int | None:
        """0-based byte offset of the object in its file, or None if it cannot be known."""
        if ptr.byte is not None:
            return ptr.byte - 1
        if ptr.record is not None:
            rb = self.record_bytes
            if rb is None:
                return None
            return (ptr.record - 1) * rb
        if ptr.form == "file":
            return 0
        return None

    def object_for(self, ptr: Pointer) -> Block | None:
        """The OBJECT block a pointer describes (^IMAGE -> OBJECT = IMAGE), if present."""
        for block in self.root.walk():
            if block.kind == "OBJECT" and block.name.upper() == ptr.name:
                return block
        return None

    @property
    def listing(self) -> DirectoryNames:
        """Names in the label's directory (listed once for all the labels in it, for case checks)."""
        from ..label.beside import directory_listing  # a product's own label check lists nothing

        return directory_listing(self.path.parent)

    def resolve(self, file_name: str) -> tuple[Path | None, Path | None]:
        """(exact path, path differing only in case) of a file named in the label."""
        from ..label.beside import resolve_beside

        return resolve_beside(self.path.parent, self.listing, file_name)

    def target_size(self, ptr: Pointer) -> int | None:
        """Size of the file the pointer's object lives in, if it can be found."""
        if ptr.attached:
            return self.size
        if ptr.file_name is None:
            return None
        exact, other = self.resolve(ptr.file_name)
        path = exact or other
        return path.stat().st_size if path is not None else None

    def target_path(self, ptr: Pointer) -> Path | None:
        if ptr.attached:
            return self.path
        if ptr.file_name is None:
            return None
        exact, other = self.resolve(ptr.file_name)
        return exact or other
