"""DLV-001 to DLV-005: a PDS3 volume's index table, read through the columns INDEX.LBL declares
(never the writer's layout), against its label, every product label and VOLDESC.CAT."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ...archive import layout
from ...bounded import open_regular
from ...label.beside import outside_tree
from ...label.tree import Block
from .model import DeliveryModel
from .parts import Found, first, named_inside

# An index row is ROW_BYTES long: a "line" read past this is cut (and reported, its CR LF missing),
# so a table of no line ends is never held whole
_LONGEST_ROW = 1 << 20
_FORMAT = re.compile(r"([AFIE])(\d+)(?:\.(\d+))?", re.IGNORECASE)


@dataclass
class _Column:
    name: str
    data_type: str
    start: int
    size: int
    format: str | None
    line: int


def _index_columns(label: Block, found: list[Found], path: Path) -> tuple[Block | None, list[_Column]]:
    table = next((b for b in label.walk() if b.kind == "OBJECT" and b.name.upper().endswith("TABLE")), None)
    if table is None:
        found.append(Found("DLV-001", path, "no INDEX_TABLE object"))
        return None, []
    columns: list[_Column] = []
    for block in table.blocks("COLUMN"):
        start, size = block.number("START_BYTE"), block.number("BYTES")
        if not isinstance(start, int) or not isinstance(size, int):
            found.append(Found("DLV-001", path, "a COLUMN without integer START_BYTE and BYTES", block.line))
            continue
        columns.append(_Column((block.text("NAME") or "").upper(), (block.text("DATA_TYPE") or "").upper(),
                               start, size, block.text("FORMAT"), block.line))
    return table, columns


def _table_file(label: Block, label_path: Path) -> Path | None:
    """The file the label's table pointer (^INDEX_TABLE = "INDEX.TAB") names, beside the label."""
    for stmt in label.statements():
        if stmt.pointer and stmt.keyword.upper().endswith("TABLE"):
            for value in stmt.value.scalars():
                if value.kind in ("string", "ident"):  # one outside the label's directory is not read
                    return label_path.parent / value.text if not outside_tree(label_path.parent, value.text) else None
    return None


def _field(row: bytes, column: _Column, number: int, path: Path, found: list[Found]) -> str | None:
    """One field's text as the column states it, or None after a DLV-001 finding."""
    begin, end = column.start - 1, column.start - 1 + column.size
    text = row[begin:end].decode("ascii", errors="replace")
    where = f"row {number}, column {column.name}"
    if column.data_type == "CHARACTER":
        if row[begin - 1:begin] != b'"' or row[end:end + 1] != b'"':
            found.append(Found("DLV-001", path, f"{where}: the value is not between the double quotes "
                                                 f"START_BYTE {column.start} and BYTES {column.size} place",
                                number))
            return None
        return text.strip()
    value = text.strip()
    try:
        float(value) if column.data_type == "ASCII_REAL" else int(value)
    except ValueError:
        found.append(Found("DLV-001", path, f"{where}: {text!r} is not {column.data_type}", number))
        return None
    match = _FORMAT.fullmatch(column.format or "")
    if match and match.group(3) is not None and match.group(1).upper() == "F":
        decimals = len(value.split(".", 1)[1]) if "." in value else 0
        if decimals != int(match.group(3)):
            found.append(Found("DLV-001", path, f"{where}: {value} has {decimals} decimals, FORMAT "
                                                 f"{column.format} states {match.group(3)}", number))
    return value


def _same(row_value: str, label_value: str | None, data_type: str, column_format: str | None) -> bool:
    """Whether a row holds its label's value. A keyword the label does not have cannot be compared
    (archives' indexes carry derived columns); it passes."""
    if label_value is None:
        return True
    if data_type == "CHARACTER":
        return row_value.strip().upper() == label_value.strip().upper()
    match = _FORMAT.fullmatch(column_format or "")
    decimals = int(match.group(3)) if match and match.group(3) else 0
    return _number_equal(row_value, label_value, decimals)


def _number_equal(a: str, b: str, decimals: int) -> bool:
    try:
        return abs(float(a) - float(b)) <= 0.5 * 10.0 ** -decimals + 1e-12 * max(1.0, abs(float(b)))
    except ValueError:
        return False


def check_index(model: DeliveryModel, found: list[Found]) -> None:
    root = model.root
    label_path = root / layout.INDEX_DIR / layout.INDEX_LABEL
    table_path = root / layout.INDEX_DIR / layout.INDEX_TABLE
    # one string per product (not a Path): memory stays small for 10,000 products
    products = {name.upper(): name for name in (p.relative_to(root).as_posix() for p in model.pds3_labels)}
    if not label_path.is_file():  # a PDS4 bundle alone has no index; a PDS3 volume (VOLDESC.CAT) must
        if products and (root / layout.VOLDESC).is_file():
            found.append(Found("DLV-002", root / layout.VOLDESC,
                                f"a PDS3 volume without {layout.INDEX_DIR}/{layout.INDEX_LABEL}"))
        return
    label = model.label_tree(label_path)
    if label is None:
        found.append(Found("DLV-001", label_path, "not a PDS3 label"))
        return
    table, columns = _index_columns(label, found, label_path)
    if table is None:
        return
    table_path = _table_file(label, label_path) or table_path
    row_bytes, rows = table.number("ROW_BYTES"), table.number("ROWS")
    volume_ids = {label.text("VOLUME_ID")} | {_text_value(model, root / layout.VOLDESC, "VOLUME_ID")}
    declared = {name.upper() for name in _set_of(label, "DATA_SET_ID")}
    seen: dict[str, int] = {}
    count = 0
    try:
        with open_regular(table_path) as stream:  # row by row: memory does not grow
            for count, line in enumerate(iter(lambda: stream.readline(_LONGEST_ROW), b""), 1):
                if not line.endswith(b"\r\n"):
                    found.append(Found("DLV-001", table_path, f"row {count} does not end with CR LF", count))
                    continue
                raw = line[:-2]
                if row_bytes is not None and len(line) != row_bytes:
                    found.append(Found("DLV-001", table_path, f"row {count} has {len(line)} bytes with its "
                                                               f"CR LF, ROW_BYTES = {row_bytes}", count))
                    continue
                values = {c.name: _field(raw, c, count, table_path, found) for c in columns}
                _check_row(model, table_path, count, values, columns, seen, volume_ids, found)
                _check_row_data_set(table_path, count, values.get("DATA_SET_ID"), declared, found)
    except OSError as exc:
        found.append(Found("DLV-001", table_path, f"cannot read the index table: {exc.strerror or exc}"))
        return
    if rows is not None and rows != count:
        found.append(Found("DLV-001", table_path, f"ROWS = {rows} in {layout.INDEX_LABEL}, but the table has "
                                                   f"{count} rows"))
    for key, name in products.items():
        if key not in seen:
            found.append(Found("DLV-002", root / name, f"this data product is not in {layout.INDEX_DIR}/"
                                                 f"{layout.INDEX_TABLE}"))
    _check_data_sets(model, label, found)


def _check_row(model: DeliveryModel, table_path: Path, number: int, values: dict[str, str | None],
               columns: list[_Column], seen: dict[str, int], volume_ids: set[str | None], found: list[Found]) -> None:
    spec = values.get("FILE_SPECIFICATION_NAME")
    if spec is None:
        return
    volume_id = values.get("VOLUME_ID")
    if volume_id is not None and len({v for v in volume_ids if v} | {volume_id}) > 1:
        found.append(Found("DLV-005", table_path, f"row {number}: VOLUME_ID {volume_id} differs from the volume's "
                                                   f"({', '.join(sorted(v for v in volume_ids if v))})", number))
    key = spec.upper()
    named, problem = named_inside(model.root, spec)
    if named is None:
        found.append(Found("DLV-003", table_path, f"row {number} names {spec!r}, which is not a file inside the "
                                                   f"delivery ({problem})", number))
        return
    if not named.is_file():
        found.append(Found("DLV-003", table_path, f"row {number} names {spec}, which does not exist", number))
        return
    if key in seen:
        found.append(Found("DLV-002", table_path, f"row {number} indexes {spec} again (first in row "
                                                   f"{seen[key]})", number))
        return
    seen[key] = number
    compared = [column.name for column in columns if column.name not in ("VOLUME_ID", "FILE_SPECIFICATION_NAME")]
    product = model.row_values(named, compared)  # DLV-004: the row against its label (its one reading)
    if product is None:
        found.append(Found("DLV-003", table_path, f"row {number} names {spec}, which is not a PDS3 label", number))
        return
    for column in columns:
        if column.name in ("VOLUME_ID", "FILE_SPECIFICATION_NAME"):
            continue
        row_value = values.get(column.name)
        if row_value is None:
            continue
        label_value, line = product[column.name]
        if not _same(row_value, label_value, column.data_type, column.format):
            found.append(Found("DLV-004", table_path, f"row {number} ({spec}): {column.name} = {row_value}, "
                                                       f"but its label has {label_value or 'none'}"
                                                       + (f" (line {line})" if line else ""), number, column.name))


def _check_row_data_set(table_path: Path, number: int, data_set: str | None, declared: set[str],
                        found: list[Found]) -> None:
    """DLV-005: a row's DATA_SET_ID (its label's, DLV-004) is one INDEX.LBL declares (and so, by
    _check_data_sets, VOLDESC.CAT)."""
    if data_set and declared and data_set.strip().upper() not in declared:
        found.append(Found("DLV-005", table_path, f"row {number}: DATA_SET_ID {data_set.strip()} is not declared in "
                                                   f"{layout.INDEX_LABEL} ({', '.join(sorted(declared))}) nor "
                                                   f"{layout.VOLDESC}", number, "DATA_SET_ID"))


def _check_data_sets(model: DeliveryModel, index_label: Block, found: list[Found]) -> None:
    """DATA_SET_ID of INDEX.LBL and VOLDESC.CAT name the same data sets."""
    index_sets = _set_of(index_label, "DATA_SET_ID")
    root = model.root
    voldesc = model.label_tree(root / layout.VOLDESC)
    if voldesc is None:
        return
    volume = next(voldesc.find("VOLUME"), voldesc)
    volume_sets = _set_of(volume, "DATA_SET_ID")
    if index_sets != volume_sets:
        found.append(Found("DLV-005", root / layout.VOLDESC, f"DATA_SET_ID {', '.join(sorted(volume_sets))} "
                            f"differs from {layout.INDEX_LABEL}'s {', '.join(sorted(index_sets))}"))


def _set_of(block: Block, keyword: str) -> set[str]:
    value = block.value(keyword)
    return {v.text for v in value.scalars()} if value is not None else set()


def _text_value(model: DeliveryModel, path: Path, keyword: str) -> str | None:
    label = model.label_tree(path)
    if label is None:
        return None
    return first(label, keyword)[0]
