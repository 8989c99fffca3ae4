"""The walk of a PDS3 label's include pointers (where their files are: beside.find_reference).

Include pointers (^STRUCTURE, ^CATALOG and their `_STRUCTURE` / `_CATALOG` forms) bring the
named file's statements into the label, and an included file may include others. `IncludeWalk`
follows them with each file read once (through the one label reader, LabelFile, with its
bound), so files including each other four times over, 20 deep, are 20 reads, not 4^19, and a
file that leads back to one being included is a loop reported once, not followed for ever.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from .beside import find_reference, is_include, pointer_kind, volume_root
from .parser import LabelFile
from .tree import Label, Statement, parse_pointer

MAX_INCLUDE_DEPTH = 20


def reference_names(label: Label) -> Iterator[tuple[Statement, str, str]]:
    """(statement, kind, file name) of each reference pointer of a kind (beside.pointer_kind)
    naming a file, at any depth."""
    for block in label.root.walk():
        for stmt in block.statements():
            if not stmt.pointer:
                continue
            kind = pointer_kind(stmt.keyword)
            if kind is not None:
                for name in parse_pointer(stmt).targets:
                    yield stmt, kind, name


@dataclass
class IncludeWalk:
    """The include pointers of labels in one trusted tree, each file read once (memoised for
    every label validated in this tree by this walk)."""

    tree: Path
    _includes: dict[Path, list[tuple[str, int, Path | None]]] = field(default_factory=dict)
    _volumes: dict[Path, Path] = field(default_factory=dict)  # a directory's volume root, found once

    def includes(self, path: Path, label: Label | None = None) -> list[tuple[str, int, Path | None]]:
        """(^KEYWORD, line, resolved file or None) of each include pointer of the file at `path`
        (`label`: the file as parsed already)."""
        key = path.resolve()
        known = self._includes.get(key)
        if known is not None:
            return known
        if label is None:
            try:
                label = LabelFile.read(path).label
            except OSError:
                label = None
        found: list[tuple[str, int, Path | None]] = []
        for stmt, kind, name in (reference_names(label) if label is not None else ()):
            if is_include(stmt.keyword):
                target = find_reference(path.parent, name, kind, self.tree, self._volume(path.parent))
                found.append(("^" + stmt.keyword.upper(), stmt.line, target.resolve() if target is not None else None))
        self._includes[key] = found
        return found

    def _volume(self, directory: Path) -> Path:
        root = self._volumes.get(directory)
        if root is None:
            root = self._volumes[directory] = volume_root(directory, self.tree)[0]
        return root

    def loops(self, path: Path, label: Label) -> Iterator[tuple[str, int, list[Path]]]:
        """(^KEYWORD and line of the label's include pointer, chain) of each include loop reached from the
        label at `path`: the files from the label to the one that includes a file already in
        the chain. Each file's includes are followed once."""
        start = path.resolve()
        done: set[Path] = set()

        def walk(node: Path, chain: list[Path]) -> Iterator[list[Path]]:
            if len(chain) > MAX_INCLUDE_DEPTH:
                return
            for _, _, target in self.includes(node):
                if target is None:
                    continue
                if target in chain:
                    yield chain + [target]
                elif target not in done:
                    yield from walk(target, chain + [target])
            done.add(node)

        for keyword, line, target in self.includes(path, label):
            if target is None:
                continue
            if target == start:
                yield keyword, line, [start, start]
            elif target not in done:
                yield from ((keyword, line, chain) for chain in walk(target, [start, target]))
