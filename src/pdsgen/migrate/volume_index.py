"""A PDS3 volume's index table as the manifest of its products.

The index is the table a label in INDEX/ describes with a FILE_SPECIFICATION_NAME column
(or PATH_NAME and FILE_NAME). Genuine volumes name it otherwise than INDEX (a `volindex`),
name the table in upper case while the disk holds lower case, and right-justify the paths;
a row is therefore matched on its path stripped of blanks and quotes, case aside. Rows are
read one at a time, so a table of any length takes little memory.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from ..bounded import checked_count, file_size
from ..label.beside import find_beside
from ..label.parser import LabelFile
from ..label.tree import Block, parse_pointer
from ..storage.containment import contained

_PATH_COLUMNS = ("FILE_SPECIFICATION_NAME", "PATH_NAME", "FILE_NAME")


@dataclass(frozen=True)
class VolumeIndex:
    label: Path
    table: Path
    row_bytes: int
    columns: dict[str, tuple[int, int]]  # column name -> (0-based start byte, bytes)

    def rows(self) -> Iterator[tuple[int, str, str | None]]:
        """(row number, product path upper case with '/' separators, PRODUCT_ID or None) per row."""
        with open(self.table, "rb") as stream:
            number = 0
            while row := stream.read(self.row_bytes):
                number += 1
                yield number, self._path(row), self._value(row, "PRODUCT_ID")

    def _value(self, row: bytes, name: str) -> str | None:
        if name not in self.columns:
            return None
        start, size = self.columns[name]
        value = row[start:start + size].decode("latin-1").strip().strip('"').strip()
        return value or None

    def _path(self, row: bytes) -> str:
        spec = self._value(row, "FILE_SPECIFICATION_NAME")
        if spec is None:
            spec = "/".join(p.strip("/") for p in (self._value(row, "PATH_NAME"), self._value(row, "FILE_NAME")) if p)
        return spec.replace("\\", "/").lstrip("/").upper()


def find_index(volume: Path, index_dir: Path) -> VolumeIndex | None:
    """The index table of the volume among the tables labels in `index_dir` describe with a path
    column: INDEX.LBL's first, then one whose label is named like an index (VOLINDEX, CUMINDEX),
    then one with a PRODUCT_ID column (a checksum table lists files, not products), by name."""
    tables = [table for label in index_dir.iterdir() if _is_label(label, volume)
              if (table := _index_table(label, volume)) is not None]
    return min(tables, key=_index_first, default=None)


def _is_label(path: Path, volume: Path) -> bool:
    """A label file of the index directory; a link leading out of the volume is not read."""
    return path.suffix.lower() == ".lbl" and path.is_file() and contained(path, volume) is not None


def _index_first(table: VolumeIndex) -> tuple[bool, bool, bool, str]:
    stem = table.label.stem.upper()
    return stem != "INDEX", "INDEX" not in stem, "PRODUCT_ID" not in table.columns, table.label.name.upper()


def _index_table(label: Path, volume: Path) -> VolumeIndex | None:
    try:
        found = LabelFile.read_pds3(label)
    except OSError:
        return None
    if found is None:
        return None
    root = found.root
    for stmt in root.statements():
        if not stmt.pointer:
            continue
        pointer = parse_pointer(stmt)
        table = next(iter(root.blocks(pointer.name)), None)
        if table is None or pointer.file_name is None or (pointer.record or 1) != 1 or pointer.byte:
            continue  # an index beginning inside its file (attached) is not read as a manifest
        columns = _columns(table)
        row_bytes = table.number("ROW_BYTES")
        if not row_bytes or not ("FILE_SPECIFICATION_NAME" in columns or "FILE_NAME" in columns):
            continue
        path = find_beside(label.parent, pointer.file_name, volume)
        if path is not None:
            record_bytes = int(row_bytes) + _prefix_bytes(table)
            if file_size(path):  # a row is read whole: it must fit in the bytes there
                checked_count(path, "ROW_BYTES", 1, record_bytes, file_size(path))
            return VolumeIndex(label, path, record_bytes, columns)
    return None


def _columns(table: Block) -> dict[str, tuple[int, int]]:
    columns = {}
    for column in table.blocks("COLUMN"):
        name, start, size = column.text("NAME"), column.number("START_BYTE"), column.number("BYTES")
        if name and start and size and name.upper() in (*_PATH_COLUMNS, "PRODUCT_ID"):
            columns[name.upper()] = (int(start) - 1, int(size))
    return columns


def _prefix_bytes(table: Block) -> int:
    """ROW_PREFIX_BYTES and ROW_SUFFIX_BYTES a row carries besides ROW_BYTES."""
    return int(table.number("ROW_PREFIX_BYTES") or 0) + int(table.number("ROW_SUFFIX_BYTES") or 0)
