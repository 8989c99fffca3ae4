"""PDS4 tables against their data: Table_Character, Table_Binary, Table_Delimited and
collection inventories, checked as NASA's validator checks them.

- the definition: fields inside the record and not overlapping (PDS4-050);
- the records: their delimiter, their length, their count (PDS4-051);
- the values: each parses as its field's data_type (PDS4-052), and a numeric value lies
  within the field's Field_Statistics minimum/maximum (PDS4-053, error) and its
  Special_Constants valid range (PDS4-054, warning, as NASA warns);
- Table_Delimited: the number of fields in each record, no double quote inside a
  double-quoted value (PDS4-055);
- inventories: member status P or S, LIDVID/LID syntax, no member listed twice (PDS4-056).

Records are read one at a time from the file (memory does not grow with the table), and
each rule reports at most a few findings per table plus a count of the rest.
"""

from __future__ import annotations

import re
import struct
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np
from lxml import etree

from . import table_columns as columns
from .label_tree import P, Pds4Hits, data_path, file_areas

_SHOWN = 5  # findings per rule and table before "and N more"
_CR, _LF = b"\r", b"\n"

# ASCII data types: what a value must look like (after stripping blanks).
_REAL = r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?"
_DATE_YMD = r"\d{4}(-(0[1-9]|1[0-2])(-(0[1-9]|[12]\d|3[01]))?)?"
_DATE_DOY = r"\d{4}(-(00[1-9]|0[1-9]\d|[12]\d\d|3[0-5]\d|36[0-6]))?"
_TIME = r"([01]\d|2[0-3])(:[0-5]\d(:([0-5]\d|60)(\.\d+)?)?)?"
_ZONE = r"(Z|[+-]\d{2}:?\d{2})?"
_LID = r"urn:[A-Za-z0-9-]+:[A-Za-z0-9._-]+:[A-Za-z0-9_.:-]+"
# Standards Reference 6C.1-2: file and directory names of letters, digits, '-', '_', '.', neither
# beginning nor ending with one of those three; a file name has a period and an extension.
_DIRECTORY = r"[A-Za-z0-9](?:[A-Za-z0-9_-]*[A-Za-z0-9])?"
# (The look-ahead keeps to the name's own characters, which is the same wherever the name matches,
# so that the pattern never looks past the value when a column is checked as lines of text.)
_FILE = r"(?=[A-Za-z0-9._-]*\.[A-Za-z0-9])[A-Za-z0-9](?:[A-Za-z0-9._-]*[A-Za-z0-9])?"
SYNTAX: dict[str, str] = {
    "ASCII_Real": _REAL + r"|[+-]?(INF|Inf|inf|Infinity|NaN|nan)",
    "ASCII_Integer": r"[+-]?\d+",
    "ASCII_NonNegative_Integer": r"\+?\d+",
    "ASCII_Numeric_Base2": r"[01]+",
    "ASCII_Numeric_Base8": r"[0-7]+",
    "ASCII_Numeric_Base16": r"[0-9a-fA-F]+",
    "ASCII_Boolean": r"true|false|0|1",
    "ASCII_Date_YMD": _DATE_YMD + _ZONE,
    "ASCII_Date_DOY": _DATE_DOY + _ZONE,
    "ASCII_Date_Time_YMD": rf"{_DATE_YMD}(T({_TIME})?)?{_ZONE}",
    "ASCII_Date_Time_YMD_UTC": rf"{_DATE_YMD}(T({_TIME})?)?Z",
    "ASCII_Date_Time_DOY": rf"{_DATE_DOY}(T({_TIME})?)?{_ZONE}",
    "ASCII_Date_Time_DOY_UTC": rf"{_DATE_DOY}(T({_TIME})?)?Z",
    "ASCII_Date_Time": rf"({_DATE_YMD}|{_DATE_DOY})(T({_TIME})?)?{_ZONE}",
    "ASCII_Date_Time_UTC": rf"({_DATE_YMD}|{_DATE_DOY})(T({_TIME})?)?Z",
    "ASCII_Time": _TIME + _ZONE,
    "ASCII_MD5_Checksum": r"[0-9a-fA-F]{32}",
    "ASCII_LID": _LID,
    "ASCII_LIDVID": _LID + r"::\d+\.\d+",
    "ASCII_LIDVID_LID": _LID + r"(::\d+\.\d+)?",
    "ASCII_VID": r"\d+\.\d+",
    "ASCII_File_Name": _FILE,
    "ASCII_Directory_Path_Name": rf"/?(?:{_DIRECTORY}/)*{_DIRECTORY}/?",
    "ASCII_File_Specification_Name": rf"/?(?:{_DIRECTORY}/)*{_FILE}",
}
PATTERNS: dict[str, re.Pattern[str]] = {name: re.compile(rf"(?:{pattern})\Z") for name, pattern in SYNTAX.items()}
_NUMERIC = {"ASCII_Real", "ASCII_Integer", "ASCII_NonNegative_Integer"}
_BASES = {"ASCII_Numeric_Base2": 2, "ASCII_Numeric_Base8": 8, "ASCII_Numeric_Base16": 16}
_DELIMITERS = {"Comma": b",", "Horizontal Tab": b"\t", "Semicolon": b";", "Vertical Bar": b"|"}
_RECORD_ENDS = {"Carriage-Return Line-Feed": b"\r\n", "Line-Feed": b"\n"}
# Binary field types and their struct codes (size checked against field_length).
_BINARY = {"IEEE754MSBSingle": ">f", "IEEE754LSBSingle": "<f", "IEEE754MSBDouble": ">d", "IEEE754LSBDouble": "<d",
           "SignedByte": "b", "UnsignedByte": "B", "SignedMSB2": ">h", "SignedLSB2": "<h", "UnsignedMSB2": ">H",
           "UnsignedLSB2": "<H", "SignedMSB4": ">i", "SignedLSB4": "<i", "UnsignedMSB4": ">I",
           "UnsignedLSB4": "<I", "SignedMSB8": ">q", "SignedLSB8": "<q", "UnsignedMSB8": ">Q",
           "UnsignedLSB8": "<Q"}


@dataclass(frozen=True)
class Field:
    """One field as it lies in the record (groups expanded): 0-based start, length."""

    name: str
    start: int
    length: int
    data_type: str
    element: etree._Element
    special: frozenset[str]
    valid_range: tuple[float | None, float | None]
    stated_range: tuple[float | None, float | None]
    formats: tuple[tuple[str, str, int], ...] = ()  # (element name, conversion, precision) to hold to


class _Limited:
    """Findings of one table, at most _SHOWN per rule, the rest counted."""

    def __init__(self, report: Pds4Hits, table: etree._Element, name: str) -> None:
        self.report, self.table, self.name = report, table, name
        self.counts: dict[str, int] = {}

    def add(self, rule: str, message: str, element: etree._Element | None = None, keyword: str | None = None) -> None:
        self.counts[rule] = self.counts.get(rule, 0) + 1
        if self.counts[rule] <= _SHOWN:
            line = (element if element is not None else self.table).sourceline
            self.report.add(rule, f"{self.name}: {message}", line, keyword)

    def close(self) -> None:
        for rule, count in self.counts.items():
            if count > _SHOWN:
                self.report.add(rule, f"{self.name}: and {count - _SHOWN} more like these", self.table.sourceline)


def check_tables(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """Every table of every file area (inventories included) against its file."""
    for area in _areas(tree):
        path = data_path(report, area, report_missing=False)
        for table in area:
            if not isinstance(table.tag, str):
                continue
            kind = table.tag[len(P):] if table.tag.startswith(P) else ""
            check = _TABLES.get(kind)
            if check is None:
                continue
            limited = _Limited(report, table, f"{kind} {_text(table, 'name') or _text(table, 'local_identifier') or ''}"
                               .strip())
            check(limited, table, path)
            limited.close()


def _areas(tree: etree._ElementTree) -> Iterator[etree._Element]:
    """The label's file areas, and those of its Information_Package_Components (an AIP's or
    SIP's checksum and transfer manifests)."""
    yield from file_areas(tree)
    for component in tree.getroot().iterchildren(f"{P}Information_Package_Component"):
        for area in component:
            if isinstance(area.tag, str) and area.tag.startswith(f"{P}File_Area"):
                yield area


def _text(element: etree._Element, name: str) -> str | None:
    found = element.find(f"{P}{name}")
    return found.text.strip() if found is not None and found.text else None


def _int(element: etree._Element, name: str) -> int | None:
    value = _text(element, name)
    try:
        return int(value) if value is not None else None
    except ValueError:
        return None


def _start(out: _Limited, table: etree._Element, path: Path) -> int | None:
    """Where the table starts in PATH: its offset, when the file holds that byte; else None, and
    PDS4-051 says so. The one place a table's offset reaches a seek (10^20 could not be sought,
    a negative one was an OSError: every table check 'could not run')."""
    offset = _int(table, "offset") or 0
    size = path.stat().st_size
    if 0 <= offset <= size:
        return offset
    out.add("PDS4-051", f"offset {offset} lies outside {path.name} ({size} bytes)", table, "offset")
    return None


def _float(element: etree._Element | None, name: str) -> float | None:
    if element is None:
        return None
    value = _text(element, name)
    try:
        return float(value) if value is not None else None
    except ValueError:
        return None


# --- definitions ---------------------------------------------------------------------------


def _fields(record: etree._Element, base: int, field_tag: str, group_tag: str) -> Iterator[Field]:
    """Fields of a record or group in order, groups expanded over their repetitions;
    locations are 1-based in the label, relative to the enclosing group."""
    for child in record:
        if child.tag == f"{P}{field_tag}":
            location = _int(child, "field_location")
            length = _int(child, "field_length")
            if location is None:
                continue
            yield _field(child, base + location - 1, length or 0)
        elif child.tag == f"{P}{group_tag}":
            repetitions = _int(child, "repetitions") or 1
            location = (_int(child, "group_location") or 1) - 1
            length = _int(child, "group_length") or 0
            size = length // repetitions if repetitions else 0
            for repetition in range(min(repetitions, 10_000)):
                yield from _fields(child, base + location + repetition * size, field_tag, group_tag)


def _field(element: etree._Element, start: int, length: int) -> Field:
    special = element.find(f"{P}Special_Constants")
    constants: set[str] = set()
    if special is not None:
        for constant in special:
            if isinstance(constant.tag, str) and constant.text and not constant.tag.endswith(
                    ("valid_minimum", "valid_maximum")):
                constants.add(constant.text.strip())
    statistics = element.find(f"{P}Field_Statistics")
    formats = []
    for name in ("validation_format", "field_format"):
        match = _FORMAT.match(_text(element, name) or "")
        if match and match["precision"] is not None and match["conversion"] in "fFeE":
            formats.append((name, match["conversion"].lower(), int(match["precision"])))
    return Field(_text(element, "name") or "?", start, length, _text(element, "data_type") or "",
                 element, frozenset(constants), (_float(special, "valid_minimum"), _float(special, "valid_maximum")),
                 (_float(statistics, "minimum"), _float(statistics, "maximum")), tuple(formats))


# A C-style format as PDS4 writes field_format and validation_format (%6.2f, %8.3e, %-10s).
_FORMAT = re.compile(r"%[-+ 0#]*(?P<width>\d+)?(?:\.(?P<precision>\d+))?(?P<conversion>[a-zA-Z])\Z")
_DECIMALS = re.compile(r"[+-]?\d*(?:\.(?P<decimals>\d*))?(?:[eE][+-]?\d+)?\Z")


def _check_layout(out: _Limited, fields: list[Field], record_length: int) -> None:
    """Fields inside the record and not overlapping one another."""
    previous: Field | None = None
    for field in sorted(fields, key=lambda f: f.start):
        if field.start + field.length > record_length:
            out.add("PDS4-050", f"field {field.name} (bytes {field.start + 1}-{field.start + field.length}) "
                                f"extends past the record length {record_length}", field.element, "field_location")
        if previous is not None and field.start < previous.start + previous.length:
            out.add("PDS4-050", f"field {field.name} at byte {field.start + 1} overlaps field {previous.name} "
                                f"(bytes {previous.start + 1}-{previous.start + previous.length})",
                    field.element, "field_location")
        previous = field


# --- values --------------------------------------------------------------------------------


def _check_value(out: _Limited, field: Field, raw: bytes, record: int) -> None:
    """One value against its data_type, Field_Statistics and valid range."""
    try:
        text = raw.decode("utf-8").strip()
    except UnicodeDecodeError:
        out.add("PDS4-052", f"record {record}, field {field.name}: not UTF-8 text", field.element, "data_type")
        return
    if not text or text in field.special:
        return
    pattern = PATTERNS.get(field.data_type)
    if pattern is not None and not pattern.match(text):
        out.add("PDS4-052", f"record {record}, field {field.name}: {text!r} is not a valid {field.data_type}",
                field.element, "data_type")
        return
    if field.data_type in _NUMERIC or field.data_type in _BASES:
        _check_range(out, field, _number(text, field.data_type), record)
    for name, _conversion, precision in field.formats:
        match = _DECIMALS.match(text)
        decimals = len(match["decimals"] or "") if match else None
        if decimals is not None and decimals != precision:
            rule = "PDS4-058" if name == "validation_format" else "PDS4-059"
            out.add(rule, f"record {record}, field {field.name}: {text!r} has {decimals} decimals, its "
                          f"{name} {_text(field.element, name)} {precision}", field.element, name)
            break


def _number(text: str, data_type: str) -> float:
    base = _BASES.get(data_type)
    return float(int(text, base)) if base else float(text)


def _check_range(out: _Limited, field: Field, value: float, record: int) -> None:
    if any(_same(value, constant) for constant in field.special):
        return
    low, high = field.stated_range
    if (low is not None and value < low) or (high is not None and value > high):
        out.add("PDS4-053", f"record {record}, field {field.name}: {value:g} outside Field_Statistics "
                            f"[{low}, {high}]", field.element, "Field_Statistics")
    low, high = field.valid_range
    if (low is not None and value < low) or (high is not None and value > high):
        out.add("PDS4-054", f"record {record}, field {field.name}: {value:g} outside the valid range "
                            f"[{low}, {high}] and not a special constant", field.element, "Special_Constants")


def _same(value: float, constant: str) -> bool:
    try:
        return float(int(constant, 16)) == value if constant.lower().startswith("0x") else float(constant) == value
    except ValueError:
        return False


# --- screens: which values of a block to check exactly (see table_columns.py) ----------------


@dataclass(frozen=True)
class _Screen:
    """How one field's values are screened a column at a time; `exact` checks a flagged one."""

    field: Field
    index: int  # the field's place in its record (findings come in record, then field, order)
    start: int
    stop: int  # the field's bytes, cut at the record's end as a record slice cuts them
    checks: tuple[re.Pattern[bytes], ...]  # syntax and decimals, over the text
    numeric: str | None  # "text" (parsed), "base" (parsed per distinct value), "binary"
    constants: np.ndarray  # the special constants' values
    exact: Callable[[_Limited, Field, bytes, int], None]  # a flagged value, checked and worded

    def suspects(self, positions: np.ndarray) -> np.ndarray:
        """The records (of a block, as columns.by_position gives it) whose value may be reported."""
        column = positions[self.start:self.stop]
        ranges = (self.field.stated_range, self.field.valid_range)
        if self.numeric == "binary":
            return columns.out_of_range(columns.binary_values(column, self.field.data_type), ranges, self.constants)
        numbers = columns.number_columns(column, self.field.data_type)
        cleared = None
        if numbers is not None:  # plainly written numbers: syntax and decimals known without a pass
            cleared = numbers.plain.copy()
            for _, _, precision in self.field.formats:
                cleared &= numbers.decimals == precision
        suspect, blank = columns.text_suspects(column, list(self.checks), cleared)
        if numbers is not None and cleared is not None:
            suspect |= numbers.plain & ~cleared
        if self.numeric is not None:
            suspect |= self._out_of_range(column, suspect | blank, numbers)
        return suspect

    def _out_of_range(self, column: np.ndarray, skip: np.ndarray, numbers: columns.Numbers | None) -> np.ndarray:
        """Values outside the field's ranges; where one cannot be read, every value of the column
        (each is then checked exactly)."""
        values = np.full(column.shape[1], np.nan)
        rest = ~skip
        if numbers is not None:
            read = rest & numbers.plain
            values[read] = numbers.values[read]
            rest &= ~numbers.plain
        if rest.any():
            parse = None if self.numeric == "text" else partial(_parsed, data_type=self.field.data_type)
            others = columns.text_values(column[:, rest], parse)
            if others is None:
                return ~skip
            values[rest] = others
        return columns.out_of_range(values, (self.field.stated_range, self.field.valid_range), self.constants)


def _parsed(text: bytes, data_type: str) -> float:
    return _number(text.decode("ascii").strip(), data_type)


def _screen(field: Field, index: int, record_length: int, binary: bool) -> _Screen | None:
    """The field's screen (None: none of its values can be reported, as for a field that
    lies wholly past the record's end)."""
    start, stop = field.start, min(field.start + field.length, record_length)
    if stop <= start:
        return None
    ranged = any(bound is not None for bound in (*field.stated_range, *field.valid_range))
    constants = np.array([c for c in map(_constant, field.special) if c is not None and c == c], np.float64)
    code = _BINARY.get(field.data_type) if binary else None
    if code is not None:
        if struct.calcsize(code) != stop - start or not ranged:
            return None
        return _Screen(field, index, start, stop, (), "binary", constants, _check_binary_value)
    if binary and not (field.data_type in PATTERNS or field.data_type.startswith("ASCII")):
        return None
    checks = [columns.line_check(SYNTAX[field.data_type])] if field.data_type in SYNTAX else []
    checks += [columns.line_check(columns.decimals_pattern(precision)) for _, _, precision in field.formats]
    numeric = None
    if ranged and field.data_type in _NUMERIC:
        numeric = "text"
    elif ranged and field.data_type in _BASES:
        numeric = "base"
    return _Screen(field, index, start, stop, tuple(checks), numeric, constants, _check_value)


def _constant(constant: str) -> float | None:
    """A special constant's value as _same compares it (None: not a number)."""
    try:
        return float(int(constant, 16)) if constant.lower().startswith("0x") else float(constant)
    except ValueError:
        return None


def _check_values(out: _Limited, screens: list[_Screen], block: np.ndarray, first: int) -> None:
    """The block's flagged values checked exactly, in record order and, within a record, field order."""
    rows, places = [], []
    positions = columns.by_position(block)
    for screen in screens:
        flagged = np.flatnonzero(screen.suspects(positions))
        rows.append(flagged)
        places.append(np.full(len(flagged), screen.index))
    if not rows:
        return
    row_of, place_of = np.concatenate(rows), np.concatenate(places)
    by_place = {screen.index: screen for screen in screens}
    for position in np.lexsort((place_of, row_of)).tolist():
        row, screen = int(row_of[position]), by_place[int(place_of[position])]
        screen.exact(out, screen.field, block[row, screen.start:screen.stop].tobytes(), first + row)


# --- Table_Character -----------------------------------------------------------------------


def _table_character(out: _Limited, table: etree._Element, path: Path | None) -> None:
    record = table.find(f"{P}Record_Character")
    if record is None:
        return
    record_length = _int(record, "record_length") or 0
    fields = list(_fields(record, 0, "Field_Character", "Group_Field_Character"))
    _check_layout(out, fields, record_length)
    if path is None or record_length <= 0:
        return
    ending = _RECORD_ENDS.get(_text(table, "record_delimiter") or "Carriage-Return Line-Feed", b"\r\n")
    records = _int(table, "records") or 0
    offset = _start(out, table, path)
    if offset is None:
        return
    screens = [s for s in (_screen(f, i, record_length, False) for i, f in enumerate(fields)) if s is not None]
    done = 0
    with open(path, "rb") as handle:
        handle.seek(offset)
        for first, block in columns.record_blocks(handle, record_length, records):
            done += len(block)
            wrong = np.flatnonzero(columns.ends_wrong(block, ending)).tolist()
            misplaced = first == 1 and wrong[:1] == [0] and bool(np.isin(block[0, :-1], (_CR[0], _LF[0])).any())
            for row in wrong[:1] if misplaced else wrong:
                out.add("PDS4-051", f"record {first + row} does not end with the record delimiter "
                                    f"{_text(table, 'record_delimiter')} at byte {record_length} (record_length or "
                                    f"the delimiter is wrong)", record, "record_length")
            if misplaced:
                return  # the records are not where the label says: their values mean nothing
            _check_values(out, screens, block, first)
    if done < records:
        out.add("PDS4-051", f"the file ends in record {done + 1} of {records} (records of "
                            f"{record_length} bytes from offset {offset})", table, "records")


# --- Table_Binary --------------------------------------------------------------------------


def _table_binary(out: _Limited, table: etree._Element, path: Path | None) -> None:
    record = table.find(f"{P}Record_Binary")
    if record is None:
        return
    record_length = _int(record, "record_length") or 0
    fields = list(_fields(record, 0, "Field_Binary", "Group_Field_Binary"))
    _check_layout(out, fields, record_length)
    for field in fields:
        _check_bits(out, field)
        code = _BINARY.get(field.data_type)
        if code is not None and struct.calcsize(code) != field.length:
            out.add("PDS4-050", f"field {field.name}: {field.data_type} takes {struct.calcsize(code)} bytes, "
                                f"field_length is {field.length}", field.element, "field_length")
    if path is None or record_length <= 0:
        return
    records = _int(table, "records") or 0
    offset = _start(out, table, path)
    if offset is None:
        return
    size = path.stat().st_size
    if offset + records * record_length > size:
        out.add("PDS4-051", f"{records} records of {record_length} bytes from offset {offset} need "
                            f"{offset + records * record_length} bytes; {path.name} has {size}", table, "records")
        return
    screens = [s for s in (_screen(f, i, record_length, True) for i, f in enumerate(fields)) if s is not None]
    with open(path, "rb") as handle:
        handle.seek(offset)
        for first, block in columns.record_blocks(handle, record_length, records):
            _check_values(out, screens, block, first)


def _check_binary_value(out: _Limited, field: Field, raw: bytes, record: int) -> None:
    """One value of a binary field: a number against its ranges, ASCII text as in a character table."""
    code = _BINARY.get(field.data_type)
    if code is not None and struct.calcsize(code) == len(raw):
        value = struct.unpack(code, raw)[0]
        if value == value:  # NaN is neither in nor out of a range
            _check_range(out, field, float(value), record)
    elif field.data_type in PATTERNS or field.data_type.startswith("ASCII"):
        _check_value(out, field, raw, record)


def _check_bits(out: _Limited, field: Field) -> None:
    """Bit fields of a packed field: inside its bits, start <= stop, not overlapping."""
    packed = field.element.find(f"{P}Packed_Data_Fields")
    if packed is None:
        return
    bits = field.length * 8
    spans = []
    for bit in packed.iter(f"{P}Field_Bit"):
        start, stop = _int(bit, "start_bit_location"), _int(bit, "stop_bit_location")
        name = _text(bit, "name") or "?"
        if start is None or stop is None:
            continue
        if not 1 <= start <= stop <= bits:
            out.add("PDS4-050", f"bit field {name} (bits {start}-{stop}) is not within the {bits} bits of "
                                f"field {field.name}", bit, "stop_bit_location")
        spans.append((start, stop, name, bit))
    spans.sort(key=lambda span: span[0])
    for (_, stop, before, _), (start, _, name, bit) in zip(spans, spans[1:], strict=False):
        if start <= stop:
            out.add("PDS4-050", f"bit field {name} starts at bit {start}, inside bit field {before} "
                                f"(which stops at {stop})", bit, "start_bit_location")


def check_object_layout(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """The objects of one file (headers, tables, arrays...) must not overlap: each starts
    at or after the end of the one before it (label only)."""
    for area in file_areas(tree):
        spans = []
        for element in area:
            if not isinstance(element.tag, str) or element.find(f"{P}offset") is None:
                continue
            start = _int(element, "offset")
            length = _extent(element)
            if start is not None and length:
                spans.append((start, start + length, element))
        spans.sort(key=lambda span: span[0])
        for (_, end, before), (start, _, element) in zip(spans, spans[1:], strict=False):
            if start < end:
                report.add("PDS4-057", f"{element.tag[len(P):]} at offset {start} starts inside "
                                       f"{before.tag[len(P):]} (bytes {_int(before, 'offset')}-{end - 1})",
                           element.find(f"{P}offset").sourceline, "offset")


_SAMPLE_BYTES = {name: struct.calcsize(code) for name, code in _BINARY.items()}
_SAMPLE_BYTES.update({"ComplexMSB8": 8, "ComplexLSB8": 8, "ComplexMSB16": 16, "ComplexLSB16": 16})


def _extent(element: etree._Element) -> int | None:
    """Bytes an object takes in its file, when the label says (object_length, or records
    of a fixed length, or an array's elements)."""
    stated = _int(element, "object_length")
    if stated is not None:
        return stated
    for record_tag in ("Record_Character", "Record_Binary"):
        record = element.find(f"{P}{record_tag}")
        if record is not None:
            return (_int(element, "records") or 0) * (_int(record, "record_length") or 0)
    if element.tag.startswith(f"{P}Array"):
        size = _SAMPLE_BYTES.get(element.findtext(f"{P}Element_Array/{P}data_type") or "")
        axes = [_int(axis, "elements") or 0 for axis in element.findall(f"{P}Axis_Array")]
        if size and axes:
            count = 1
            for n in axes:
                count *= n
            return count * size
    return None


# --- Table_Delimited and inventories -------------------------------------------------------


def _delimited_records(handle, limit: int) -> Iterator[bytes]:  # noqa: ANN001 - a binary file
    """The first `limit` records of a delimited table, each with its delimiter (the last may
    lack it); the file is left just after them."""
    for _ in range(limit):
        line = handle.readline()
        if not line:
            return
        yield line


def _records_after(handle, object_length: int | None) -> int:  # noqa: ANN001 - a binary file
    """Non-empty lines left after the stated records (a table alone in its file, with no
    object_length, ends at the end of the file)."""
    if object_length is not None:
        return 0
    return sum(1 for line in handle if line.strip())


def _split(record: bytes, delimiter: bytes) -> list[bytes]:
    """Values of a delimited record (a double-quoted field without its quotes)."""
    return [_unquoted(field) for field in _as_written(record, delimiter)]


def _as_written(record: bytes, delimiter: bytes) -> list[bytes]:
    """Fields of a delimited record, as written (quotes kept); a double-quoted field may hold
    the delimiter."""
    if b'"' not in record:  # nothing quoted: every delimiter separates (the common case, at C speed)
        return record.split(delimiter)
    fields, current, quoted = [], bytearray(), False
    for byte in record:
        char = bytes([byte])
        if char == b'"':
            quoted = not quoted
        elif char == delimiter and not quoted:
            fields.append(bytes(current))
            current = bytearray()
            continue
        current += char
    fields.append(bytes(current))
    return fields


def _unquoted(field: bytes) -> bytes:
    """A field's value: a double-quoted field without its quotes."""
    return field.strip().strip(b'"') if field.strip().startswith(b'"') else field


def _quote_inside_quotes(field: bytes) -> bool:
    """PDS DSV 1 (Standards Reference 4C) has no escape for a double quote: a double-quoted
    value must not hold one (RFC 4180's doubled "" included)."""
    text = field.strip()
    return len(text) >= 2 and text.startswith(b'"') and text.endswith(b'"') and b'"' in text[1:-1]


def _table_delimited(out: _Limited, table: etree._Element, path: Path | None,
                     row_check: Callable[[int, list[bytes]], None] | None = None) -> None:
    record = table.find(f"{P}Record_Delimited")
    if record is None or path is None:
        return
    fields = [_field(f, 0, _int(f, "maximum_field_length") or 0) for f in _delimited_fields(record)]
    declared = _int(record, "fields")
    delimiter = _DELIMITERS.get(_text(table, "field_delimiter") or "", b",")
    ending = _RECORD_ENDS.get(_text(table, "record_delimiter") or "Carriage-Return Line-Feed", b"\r\n")
    records = _int(table, "records") or 0
    count = 0
    offset = _start(out, table, path)
    if offset is None:
        return
    with open(path, "rb") as handle:
        handle.seek(offset)
        for count, data in enumerate(_delimited_records(handle, records), start=1):
            if not data.endswith(ending) or (ending == _LF and data.endswith(b"\r\n")):
                out.add("PDS4-051", f"record {count} does not end with the record delimiter "
                                    f"{_text(table, 'record_delimiter')}", table, "record_delimiter")
            written = _as_written(data[:-len(ending)] if data.endswith(ending) else data.rstrip(b"\r\n"), delimiter)
            values = [_unquoted(value) for value in written]
            expected = len(fields) if fields or declared is None else declared  # groups expanded
            if len(values) != expected:
                out.add("PDS4-055", f"record {count} has {len(values)} fields, the label defines {expected}",
                        record, "fields")
                continue
            for number, value in enumerate(written, start=1):
                if _quote_inside_quotes(value):
                    name = fields[number - 1].name if number <= len(fields) else str(number)
                    out.add("PDS4-055", f"record {count}, field {name}: a double-quoted value holds a double "
                                        "quote, which PDS DSV 1 does not allow", record, "field_delimiter")
            for field, value in zip(fields, values, strict=False):
                if field.length and len(value) > field.length:
                    out.add("PDS4-052", f"record {count}, field {field.name}: {len(value)} characters, "
                                        f"more than maximum_field_length {field.length}", field.element,
                            "maximum_field_length")
                _check_value(out, field, value, count)
            if row_check is not None:
                row_check(count, values)
        # more records than stated: an error NASA's validator makes for inventories only
        extra = _records_after(handle, _int(table, "object_length")) if row_check is not None else 0
    if count < records:
        out.add("PDS4-051", f"the label states {records} records, {path.name} holds {count}", table, "records")
    elif extra:
        out.add("PDS4-051", f"the label states {records} records, {path.name} holds {records + extra}",
                table, "records")


def _delimited_fields(record: etree._Element) -> Iterator[etree._Element]:
    for child in record:
        if child.tag == f"{P}Field_Delimited":
            yield child
        elif child.tag == f"{P}Group_Field_Delimited":
            for _ in range(_int(child, "repetitions") or 1):
                yield from _delimited_fields(child)


_MEMBER = re.compile(rf"(?:{_LID})(::\d+\.\d+)?\Z")


def _inventory(out: _Limited, table: etree._Element, path: Path | None) -> None:
    """An inventory: a delimited table of (member status, LIDVID or LID) rows."""
    seen: dict[str, int] = {}

    def row(number: int, values: list[bytes]) -> None:
        if len(values) < 2:
            return
        status = values[0].decode("utf-8", "replace").strip()
        member = values[1].decode("utf-8", "replace").strip()
        if status not in ("P", "S"):
            out.add("PDS4-056", f"record {number}: member status {status!r} is neither P nor S", table,
                    "member_status")
        if not _MEMBER.match(member):
            out.add("PDS4-056", f"record {number}: {member!r} is not a LIDVID or LID", table, "lidvid_reference")
        elif member in seen:
            out.add("PDS4-056", f"record {number}: {member} is listed again (first in record {seen[member]})",
                    table, "lidvid_reference")
        else:
            seen[member] = number

    _table_delimited(out, table, path, row)


_TABLES: dict[str, Callable[[_Limited, etree._Element, Path | None], None]] = {
    "Table_Character": _table_character,
    "Table_Binary": _table_binary,
    "Table_Delimited": _table_delimited,
    "Inventory": _inventory,
    "Checksum_Manifest": _table_delimited,  # PDS4 defines both manifests as tables of these kinds
    "Transfer_Manifest": _table_character,
}


def check_members(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """A bundle lists each collection once: no two Bundle_Member_Entry give the same LIDVID
    or the same LID, as NASA's validator requires (label only)."""
    seen: dict[str, int] = {}
    for entry in tree.getroot().iterchildren(f"{P}Bundle_Member_Entry"):
        reference = entry.find(f"{P}lidvid_reference")
        if reference is None:
            reference = entry.find(f"{P}lid_reference")
        if reference is None or not reference.text:
            continue
        member = reference.text.strip()
        if member in seen:
            report.add("PDS4-056", f"Bundle_Member_Entry {member} is listed again (first at line {seen[member]})",
                       reference.sourceline, reference.tag[len(P):])
        else:
            seen[member] = reference.sourceline or 0
