"""What every rule gets for one file: the parsed label, its bytes, and its data pointers.

The label is read and parsed once here; rule families only look things up. Data
files are never read here (only stat'ed), so label-only validation stays fast.
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..label.parser import LabelFile, parse_label
from ..label.tree import Block, Label
from .dictionary import load as load_dictionary

if TYPE_CHECKING:
    from ..label.beside import DirectoryNames
    from ..label.tree import Pointer

# The label is read and parsed by the label reader (label/parser.py), never by code of validate/.
__all__ = ["FileContext", "parse_label"]


class FileContext:
    """One label file being validated, with lazy helpers the rule families share."""

    def __init__(self, path: Path, labels_only: bool = False, dictionaries: tuple[str, ...] = (),
                 strict: bool = False, file: LabelFile | None = None, tree: Path | None = None) -> None:
        """`file`: the label as read already (a run's LabelCache); else the file is read here.
        `tree`: the directory tree the files the label names must stay inside (label/beside.py's
        trusted_tree: the directory the user gave, or --root); the label's directory by default."""
        self.path = path
        self.tree = tree if tree is not None else path.parent
        self.labels_only = labels_only
        self.dictionaries = dictionaries
        self.strict = strict
        # What rule families compute once per file and share, by key: "_is_hrsc" (profiles),
        # "_dict_statements"/"_dict_defined" (DICT), "_img_stats" (IMG), "_map_offsets" (MAP),
        # "_jp2" (GEO), "_outside" (outside), "_reference_pointers"/"_include_walk" (PTR). Declared
        # here so no family sets attributes of its own on the context.
        self.cache: dict[str, Any] = {}
        self.file = file if file is not None else LabelFile.read(path)
        self.size = self.file.size
        self.head = self.file.head  # the label bytes (and, unless kept by a cache, a little after)
        self.label: Label = self.file.label

    @property
    def dictionary(self):
        """The keyword dictionary (with any extra dictionaries the user named)."""
        return load_dictionary(self.dictionaries)

    @property
    def dictionary_is_authority(self) -> bool:
        """The user named the dictionaries to check against (the PSDD as released, a mission's
        local dictionary): their constraints are then the rules the label must keep, and what
        breaks them is an error (DICT family; see docs/pds3-parity.md). Against the built-in
        dictionary alone they stay warnings where genuine archives break them."""
        return bool(self.dictionaries)

    # -- label look-ups ------------------------------------------------------------
    @property
    def root(self) -> Block:
        return self.label.root

    @property
    def pointers(self) -> list[Pointer]:
        return self.file.pointers

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
        return self.file.label_only

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

        return resolve_beside(self.path.parent, self.listing, file_name, self.tree)

    def outside(self, file_name: str) -> Path | None:
        """The file named in the label when it lies outside the trusted tree (refused); asked
        once per name (PTR-009 and the rules that skip what it reports ask the same)."""
        from ..label.beside import outside_tree

        known: dict[str, Path | None] = self.cache.setdefault("_outside", {})
        if file_name not in known:
            known[file_name] = outside_tree(self.path.parent, file_name, self.tree)
        return known[file_name]

    def outside_names(self) -> list[tuple[str, str, int]]:
        """(keyword, name, line) of each file the label names that lies outside the trusted tree."""
        from ..label.tree import every_named_file

        return [(keyword, name, line) for keyword, name, line in every_named_file(self.root)
                if self.outside(name) is not None]

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
