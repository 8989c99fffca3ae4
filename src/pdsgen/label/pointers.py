"""PDS3 pointers (`^IMAGE = ("X.IMG", 12)`), classified into the forms the PDS3 Standards
name: which file, which record or byte an object starts at, and whether the pointer names
data or a reference file kept elsewhere (a catalog, a description).

Every reader of pointers (the validator's rules, the delivery's grouping of files into
products, migration) classifies them here, so they agree on what a label points at.
"""

from __future__ import annotations

from dataclasses import dataclass

from .tree import Block, Statement, Value

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


def label_pointers(root: Block) -> list[Pointer]:
    """The pointers of the label's top level, in order."""
    return [parse_pointer(s) for s in root.statements() if s.pointer]
