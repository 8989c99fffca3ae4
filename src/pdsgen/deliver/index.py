"""The PDS3 volume index: INDEX/INDEX.TAB and its detached label INDEX/INDEX.LBL.

As the PDS3 Standards Reference prescribes for index tables: fixed-width ASCII rows
ending in CR LF, fields separated by commas, character values in double quotes (the
quotes outside START_BYTE/BYTES), numbers right-aligned; one row per data product,
values as its label writes them (reals keep every decimal: the column's FORMAT takes
the most decimals any row has, so no value is rounded).

Rows are written in two passes over a scratch file (values, then the padded rows once
every width is known), so memory does not grow with the number of products.
"""

from __future__ import annotations

import json
import tempfile
from collections.abc import Iterable
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from pathlib import Path

from ..archive import layout
from ..encode import table_field
from ..label.values import format_string


@dataclass
class Column:
    name: str
    data_type: str
    description: str
    width: int = 1
    decimals: int = 0
    whole: int = 1  # reals: characters before the decimal point (sign included)
    missing: bool = False

    @property
    def quoted(self) -> bool:
        return self.data_type == "CHARACTER"

    @property
    def format(self) -> str:
        if self.data_type == "ASCII_REAL":
            return f"F{self.width}.{self.decimals}"
        if self.data_type == "ASCII_INTEGER":
            return f"I{self.width}"
        return f"A{self.width}"


def _plain(raw: str) -> tuple[str, int] | None:
    """A number as plain decimal text (no exponent) and its count of decimals; None if not a number."""
    try:
        value = Decimal(raw)
    except InvalidOperation:
        return None
    if not value.is_finite():
        return None
    text = format(value, "f")
    return text, len(text.split(".", 1)[1]) if "." in text else 0


def _as_read(value: str) -> str:
    """A label's value as a PVL reader reads it: white space holding a line break (a quoted
    string continued on the next line) is one space. Whatever else it holds goes to the
    table-field encoder, which refuses what a row cannot carry (a lone CR, NUL, ESC ...)."""
    return " ".join(value.split()) if ("\n" in value or "\r" in value or "\t" in value) else value


class IndexWriter:
    """Collects one row per product, then writes INDEX.TAB and INDEX.LBL."""

    def __init__(self, volume_id: str) -> None:
        self.volume_id = volume_id
        self.columns = [Column(name, kind, text) for name, kind, text in layout.INDEX_COLUMNS]
        self.scratch = tempfile.TemporaryFile("w+", encoding="utf-8")
        self.rows = 0
        self.data_set_ids: dict[str, None] = {}

    def add(self, file_specification: str, values: dict[str, str | None]) -> None:
        """One product's row: `values` holds its label's values by keyword (None: absent)."""
        row: list[str] = []
        for column in self.columns:
            if column.name == "VOLUME_ID":
                text: str | None = self.volume_id
            elif column.name == "FILE_SPECIFICATION_NAME":
                text = file_specification
            else:
                text = values.get(column.name)
            row.append(self._cell(column, text, file_specification))
        data_set = values.get("DATA_SET_ID")
        if data_set:
            self.data_set_ids[data_set] = None
        self.scratch.write(json.dumps(row) + "\n")
        self.rows += 1

    def _cell(self, column: Column, text: str | None, source: str) -> str:
        if column.quoted:
            cell = table_field(_as_read(text or layout.NOT_APPLICABLE), column.name, source)
            column.width = max(column.width, len(cell))
            return cell
        plain = _plain(text) if text is not None else None
        if plain is None or (column.data_type == "ASCII_INTEGER" and plain[1]):
            column.missing = True
            plain = (layout.MISSING_NUMBER, 0)
        column.decimals = max(column.decimals, plain[1])
        column.whole = max(column.whole, len(plain[0].split(".", 1)[0]))
        column.width = max(column.width, len(plain[0]))
        return plain[0]

    def _finish_widths(self) -> None:
        """Reals are written with the column's decimals, so the width is the widest whole part,
        the point and every decimal."""
        for column in self.columns:
            if column.data_type == "ASCII_REAL":
                column.width = column.whole + (1 + column.decimals if column.decimals else 0)

    def write(self, directory: Path) -> tuple[Path, Path]:
        """INDEX.TAB and INDEX.LBL into `directory`."""
        self._finish_widths()
        table = directory / layout.INDEX_TABLE
        self.scratch.seek(0)
        with open(table, "w", encoding="ascii", newline="") as out:
            for line in self.scratch:
                out.write(self._format_row(json.loads(line)))
        self.scratch.close()
        label = directory / layout.INDEX_LABEL
        label.write_bytes(self._label_text().encode("ascii"))
        return table, label

    def _format_row(self, cells: Iterable[str]) -> str:
        fields = []
        for column, cell in zip(self.columns, cells, strict=True):
            if column.quoted:
                fields.append('"' + cell.ljust(column.width) + '"')
            elif column.data_type == "ASCII_REAL":
                fields.append(format(Decimal(cell), f">{column.width}.{column.decimals}f"))
            else:
                fields.append(cell.rjust(column.width))
        return ",".join(fields) + "\r\n"

    @property
    def row_bytes(self) -> int:
        return sum(c.width + (2 if c.quoted else 0) for c in self.columns) + len(self.columns) - 1 + 2

    def _label_text(self) -> str:
        data_sets = list(self.data_set_ids) or [layout.NOT_APPLICABLE]
        quoted = [format_string(d, "DATA_SET_ID", layout.INDEX_LABEL) for d in data_sets]
        data_set = quoted[0] if len(quoted) == 1 else "(" + ",\r\n                        ".join(quoted) + ")"
        lines = [
            "PDS_VERSION_ID        = PDS3",
            "RECORD_TYPE           = FIXED_LENGTH",
            f"RECORD_BYTES          = {self.row_bytes}",
            f"FILE_RECORDS          = {self.rows}",
            f"^INDEX_TABLE          = {format_string(layout.INDEX_TABLE)}",
            f"VOLUME_ID             = {format_string(self.volume_id, 'VOLUME_ID', layout.INDEX_LABEL)}",
            f"DATA_SET_ID           = {data_set}",
            "",
            "OBJECT                = INDEX_TABLE",
            "  INTERCHANGE_FORMAT  = ASCII",
            f"  ROWS                = {self.rows}",
            f"  ROW_BYTES           = {self.row_bytes}",
            f"  COLUMNS             = {len(self.columns)}",
            "  INDEX_TYPE          = SINGLE",
            '  DESCRIPTION         = "One row per data product of the volume, with',
            '                        values taken from the product\'s label."',
        ]
        start = 1
        for number, column in enumerate(self.columns, 1):
            first = start + (1 if column.quoted else 0)
            lines += [
                "",
                "  OBJECT              = COLUMN",
                f"    COLUMN_NUMBER     = {number}",
                f"    NAME              = {column.name}",
                f"    DATA_TYPE         = {column.data_type}",
                f"    START_BYTE        = {first}",
                f"    BYTES             = {column.width}",
                f"    FORMAT            = {format_string(column.format)}",
            ]
            if column.missing:
                lines.append(f"    MISSING_CONSTANT  = {layout.MISSING_NUMBER}")
            lines += [f"    DESCRIPTION       = {format_string(column.description)}",
                      "  END_OBJECT          = COLUMN"]
            start += column.width + (2 if column.quoted else 0) + 1
        lines += ["", "END_OBJECT            = INDEX_TABLE", "", "END"]
        return "\r\n".join(lines) + "\r\n"
