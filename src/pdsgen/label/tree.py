"""The PDS3 label tree: what the label reader (parser.py) builds and every reader of a label uses.

One `Label` per file: a root `Block` holding `Statement`s and nested OBJECT/GROUP
`Block`s, each with its 1-based line number, so a finding can point a person at the
exact line to fix, and where the label's text ends.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field


@dataclass(slots=True)
class Value:
    """One parsed value: its kind, the text as written, the Python value and its unit.

    kind is one of: int, real, based, string (double-quoted), symbol (single-quoted),
    ident (unquoted word), date, seq, set, or bad (a malformed number or date that the
    reader has already reported). `items` holds the members of seq/set.
    """

    kind: str
    raw: str
    py: object
    line: int
    unit: str | None = None
    items: list[Value] | None = None

    def scalars(self) -> Iterator[Value]:
        """Every scalar member, flattening nested sequences and sets."""
        if self.items is None:
            return iter((self,))  # most values: no generator to start
        return self._members()

    def _members(self) -> Iterator[Value]:
        for item in self.items or ():
            yield from item.scalars()

    @property
    def is_number(self) -> bool:
        return self.kind in ("int", "real", "based")

    @property
    def number(self) -> int | float:
        """The value of an int, real or based value (checks test `is_number` first)."""
        if self.is_number and isinstance(self.py, (int, float)):
            return self.py
        raise ValueError(f"{self.raw} is not a number")

    @property
    def text(self) -> str:
        """The value as a string (quotes removed), for comparisons of names."""
        return self.py if isinstance(self.py, str) else self.raw


@dataclass(slots=True)
class Statement:
    """`KEYWORD = value` (or `^KEYWORD = value` when pointer is true)."""

    keyword: str
    value: Value
    line: int
    pointer: bool = False

    @property
    def key(self) -> str:
        """Upper-case keyword, with the pointer caret, as used for look-ups."""
        return ("^" if self.pointer else "") + self.keyword.upper()


@dataclass(slots=True)
class Block:
    """An OBJECT or GROUP (or the label root) with its statements and children."""

    kind: str  # ROOT, OBJECT or GROUP
    name: str
    line: int
    end_line: int | None = None
    items: list[Statement | Block] = field(default_factory=list)
    # Look-up tables built on first use: rules read the tree only once the label is read, and
    # every rule family walks it again (a label's blocks are walked ~400 times per file).
    _index: dict[str, Statement] | None = field(default=None, repr=False, compare=False)
    _statements: list[Statement] | None = field(default=None, repr=False, compare=False)
    _children: list[Block] | None = field(default=None, repr=False, compare=False)
    _tree: list[Block] | None = field(default=None, repr=False, compare=False)

    def statements(self) -> Iterator[Statement]:
        if self._statements is None:
            self._statements = [item for item in self.items if isinstance(item, Statement)]
        return iter(self._statements)

    def blocks(self, name: str | None = None) -> Iterator[Block]:
        """Direct child blocks, optionally only those whose name is `name`."""
        if self._children is None:
            self._children = [item for item in self.items if isinstance(item, Block)]
        if name is None:
            return iter(self._children)
        return (child for child in self._children if child.name.upper() == name)

    def walk(self) -> Iterator[Block]:
        """This block and every block nested in it, depth first."""
        if self._tree is None:
            tree = [self]
            for child in self.blocks():
                tree.extend(child.walk())
            self._tree = tree
        return iter(self._tree)

    def find(self, name: str) -> Iterator[Block]:
        """Every block at any depth named `name` (upper case)."""
        for block in self.walk():
            if block is not self and block.name.upper() == name:
                yield block

    def get(self, key: str) -> Statement | None:
        """The first statement with this upper-case key (`^IMAGE` for pointers).

        Indexed on first use: rules look keywords up only once the label is read."""
        if self._index is None:
            index: dict[str, Statement] = {}
            for stmt in self.statements():
                index.setdefault(stmt.key, stmt)
            self._index = index
        return self._index.get(key)

    def value(self, key: str) -> Value | None:
        stmt = self.get(key)
        return stmt.value if stmt is not None else None

    def number(self, key: str) -> float | None:
        """The numeric value of a scalar keyword, or None if absent or not a number."""
        val = self.value(key)
        if val is None or not val.is_number:
            return None
        return val.number

    def text(self, key: str) -> str | None:
        val = self.value(key)
        if val is None or val.items is not None:
            return None
        return val.text


@dataclass(slots=True)
class Issue:
    """A problem found while reading the label text, before any rule runs."""

    rule: str
    line: int | None
    message: str
    keyword: str | None = None
    severity: str | None = None  # when not the rule's own (a milder form of the problem)


@dataclass(slots=True)
class Line:
    """One physical line of label text: byte offsets and how it ended."""

    number: int
    start: int
    end: int  # offset of the first byte of the line terminator (or end of text)
    ending: str  # "CRLF", "LF", "CR" or "" (no terminator, end of file)


@dataclass(slots=True)
class Label:
    """A parsed label: the tree, where its text ends, and what the reader noticed."""

    root: Block
    text: str  # label text decoded as Latin-1 (one character per byte)
    label_end: int  # byte offset just past the END statement's line terminator
    end_found: bool
    lines: list[Line]
    issues: list[Issue]
    first_keyword: str | None = None
    first_line: int | None = None
    sfdu: str | None = None


# -- pointers (`^IMAGE = ("X.IMG", 12)`), classified into the forms the PDS3 Standards name: which
# file, which record or byte an object starts at, data or a reference file kept elsewhere. Every
# reader of pointers (the validator's rules, deliver's grouping of files, migration) asks here. --

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


# Objects that name a file by FILE_NAME rather than by a pointer (a HiRISE orthoimage's JP2 is
# its label's COMPRESSED_FILE; PDS3 Standards, chapter 5).
FILE_OBJECTS = ("COMPRESSED_FILE", "UNCOMPRESSED_FILE")


def every_named_file(root: Block) -> Iterator[tuple[str, str, int]]:
    """(keyword, file name, line) of every file a label names, at any depth: data, reference
    and include (^STRUCTURE) pointers, and COMPRESSED_FILE/UNCOMPRESSED_FILE names - all the
    names the containment rule (label/beside.py) is applied to."""
    for block in root.walk():
        for stmt in block.statements():
            if stmt.pointer:
                for name in parse_pointer(stmt).targets:
                    yield "^" + stmt.keyword.upper(), name, stmt.line
            elif block.kind == "OBJECT" and block.name.upper() in FILE_OBJECTS and stmt.key == "FILE_NAME":
                yield "FILE_NAME", stmt.value.text, stmt.line


# -- what readers ask of a label tree (parser.LabelFile asks these of its root) ----------------

# The objects that hold a PDS3 map projection, in the order they are looked for.
PROJECTION_OBJECTS = ("IMAGE_MAP_PROJECTION", "IMAGE_MAP_PROJECTION_CATALOG")


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
