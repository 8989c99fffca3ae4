"""A delivery's INDEX.TAB rows, read as its INDEX.LBL describes them (the columns' names,
START_BYTE and BYTES), for showing each product's row; the validator's DLV rules are the
ones that judge the table."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..bounded import text_lines
from ..errors import InputError
from ..label.read import LabelCache, read_pds3_label


@dataclass
class IndexTable:
    columns: list[tuple[str, int, int]]  # (NAME, START_BYTE (1-based), BYTES)
    by_file: dict[str, str]  # FILE_SPECIFICATION_NAME (upper case) -> the row
    by_id: dict[str, str]  # PRODUCT_ID (upper case) -> the row

    @classmethod
    def read(cls, label_path: Path, labels: LabelCache | None = None) -> IndexTable | None:
        """The table, or None when there is none or it cannot be read as labelled."""
        label = read_pds3_label(label_path, labels) if label_path.is_file() else None
        if label is None:
            return None
        root = label.root
        table = next((b for b in root.walk() if b.kind == "OBJECT" and b.name.upper().endswith("TABLE")), None)
        if table is None:
            return None
        columns: list[tuple[str, int, int]] = []
        for block in table.blocks("COLUMN"):
            start, size = block.number("START_BYTE"), block.number("BYTES")
            if isinstance(start, int) and isinstance(size, int):
                columns.append(((block.text("NAME") or "").upper(), start, size))
        pointer = next((s for s in root.statements() if s.pointer and s.keyword.upper().endswith("TABLE")), None)
        name = pointer.value.text if pointer is not None and pointer.value.items is None else "INDEX.TAB"
        from ..label.beside import outside_tree

        if outside_tree(label_path.parent, name) is not None:  # the containment rule: never read
            return None
        result = cls(columns, {}, {})
        try:  # a line at a time, a regular file only (a FIFO named INDEX.TAB is never waited on)
            for line in text_lines(label_path.parent / name, "index table"):
                result._add(line)
        except (InputError, OSError):
            return None
        return result

    def _add(self, line: str) -> None:
        values = {name: line[start - 1:start - 1 + size].strip().strip('"').strip()
                  for name, start, size in self.columns}
        if values.get("FILE_SPECIFICATION_NAME"):
            self.by_file[values["FILE_SPECIFICATION_NAME"].upper()] = line
        if values.get("PRODUCT_ID"):
            self.by_id[values["PRODUCT_ID"].upper()] = line

    @property
    def header(self) -> str:
        """The column names, each at its START_BYTE, to stand above a row as the table holds it;
        a column the label starts past every row is left out (START_BYTE is the label's word:
        10^12 was an OverflowError, 10^9 a gigabyte of spaces)."""
        width = max((len(row) for rows in (self.by_file, self.by_id) for row in rows.values()), default=0)
        text = ""
        for name, start, _ in self.columns:
            if start > width:
                continue
            text = text.ljust(start - 1) + name + " "
        return text.rstrip()

    def row_for(self, label: str, product_id: str) -> str | None:
        """The product's row as the table holds it (without its CR LF)."""
        return self.by_file.get(label.upper()) or self.by_id.get(product_id.upper())
