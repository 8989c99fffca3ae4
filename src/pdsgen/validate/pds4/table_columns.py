"""The records of a fixed-width table a block at a time, and each field's values screened
a column at a time: which values may break a rule.

Checking a table value by value in Python runs at some 20,000 records a second; a table
of ten million records then takes minutes. Here a block of whole records is one numpy
array (records x bytes), a field is a slice of its columns, and each rule is asked of the
whole column at once: printable ASCII (numpy), the data_type's syntax and a
validation_format's decimals (one regular-expression pass over the column in C), ranges
and special constants (numpy comparisons over the values as float64). What a screen
flags is then checked value by value by the exact checks of table_checks.py, which word
the finding - so a value is reported exactly when, and exactly as, the value-at-a-time
checks report it; a screen only has to flag every value that could be reported (it may
flag more, never fewer).

Memory is one block (BLOCK_BYTES of records, at least one record) and its columns,
whatever the table's size.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from typing import BinaryIO

import numpy as np

from ...bounded import file_size

BLOCK_BYTES = 4 << 20
_SPACE, _NEWLINE = 0x20, 0x0A

# PDS4 binary data types as numpy dtypes (struct's sizes and byte orders)
NUMPY_TYPES = {"IEEE754MSBSingle": ">f4", "IEEE754LSBSingle": "<f4", "IEEE754MSBDouble": ">f8",
               "IEEE754LSBDouble": "<f8", "SignedByte": "i1", "UnsignedByte": "u1", "SignedMSB2": ">i2",
               "SignedLSB2": "<i2", "UnsignedMSB2": ">u2", "UnsignedLSB2": "<u2", "SignedMSB4": ">i4",
               "SignedLSB4": "<i4", "UnsignedMSB4": ">u4", "UnsignedLSB4": "<u4", "SignedMSB8": ">i8",
               "SignedLSB8": "<i8", "UnsignedMSB8": ">u8", "UnsignedLSB8": "<u8"}


def record_blocks(handle: BinaryIO, record_length: int, records: int) -> Iterator[tuple[int, np.ndarray]]:
    """(number of the block's first record, its whole records as a records x record_length
    uint8 array) for up to `records` records read from the handle's position; the blocks
    stop early where the file ends (a record it cuts short is not given). No read asks for
    more than the file holds (its size as bounded.file_size gives every count checked against
    a file), whatever record_length the label claims."""
    per_block = max(1, BLOCK_BYTES // record_length)
    left = max(0, file_size(handle.name) - handle.tell())  # a record_length of 10^15 reads the file
    first = 1
    while first <= records:
        want = min(per_block, records - first + 1)
        data = handle.read(min(want * record_length, left))
        left -= len(data)
        whole = len(data) // record_length
        block = np.frombuffer(data, np.uint8, whole * record_length).reshape(whole, record_length)
        if whole:
            yield first, block
        if whole < want:
            return
        first += whole


def ends_wrong(block: np.ndarray, ending: bytes) -> np.ndarray:
    """Records (rows) that do not end with the record delimiter."""
    if block.shape[1] < len(ending):
        return np.ones(len(block), bool)
    tail = block[:, block.shape[1] - len(ending):]
    return ~(tail == np.frombuffer(ending, np.uint8)).all(axis=1)


def line_check(value_pattern: str) -> re.Pattern[bytes]:
    """A pass over a column written one value a line (blank-padded): it matches every line
    whose value, blanks stripped, is empty or matches `value_pattern` (an ASCII regular
    expression), and stops at the first line that does not."""
    return re.compile(rb"(?: *(?:" + value_pattern.encode("ascii") + rb")? *\n)*+")


def decimals_pattern(precision: int) -> str:
    """A number written with exactly `precision` decimals (none, or a bare point, for 0)."""
    point = r"\.?" if precision == 0 else r"\." + r"\d" * precision
    return rf"[+-]?\d*{point}(?:[eE][+-]?\d+)?"


def text_suspects(column: np.ndarray, checks: list[re.Pattern[bytes]],
                  cleared: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(values the checks may find fault with, blank values) of a column of text (bytes x
    records, see by_position): every value that is not printable ASCII, and every line a
    check stops at. The checks pass over the values not `cleared` already (see Numbers)."""
    width, count = column.shape
    suspect: np.ndarray = np.asarray(((column < _SPACE) | (column > 0x7E)).any(axis=0))
    blank: np.ndarray = np.asarray((column == _SPACE).all(axis=0))
    rows = np.flatnonzero(~(suspect | blank) if cleared is None else ~(suspect | blank | cleared))
    if checks and len(rows):
        lines = np.empty((len(rows), width + 1), np.uint8)
        lines[:, :width] = column[:, rows].T
        lines[:, width] = _NEWLINE
        blob = lines.tobytes()
        stopped = np.zeros(len(rows), bool)
        for check in checks:
            _mark_stops(check, blob, width + 1, stopped)
        suspect[rows[stopped]] = True
    return suspect, blank


def by_position(block: np.ndarray) -> np.ndarray:
    """A block of records (records x bytes) as bytes x records: each byte position of the
    record one contiguous row, so that a field's checks run over whole rows of the array."""
    return np.ascontiguousarray(block.T)


def _mark_stops(check: re.Pattern[bytes], blob: bytes, stride: int, suspect: np.ndarray) -> None:
    position = 0
    while True:
        match = check.match(blob, position)
        stop = match.end() if match else position
        if stop >= len(blob):
            return
        line = stop // stride
        suspect[line] = True
        position = (line + 1) * stride


class Numbers:
    """Values of a column of text numbers written plainly - blanks, an optional sign, digits
    with at most one point, blanks (the form nearly every ASCII_Real and ASCII_Integer
    column has) - recognised and read by numpy arithmetic, a byte position at a time: a
    value of that form matches ASCII_Real (and, without a point, ASCII_Integer), its
    decimals are the digits after its point, and with at most 15 digits its value is its
    digits divided by a power of ten, a division IEEE 754 rounds exactly as float() rounds
    the text. Values of any other form (exponents, INF, a second point ...) are left to the
    regular expressions."""

    def __init__(self, column: np.ndarray, signs: bytes, point: bool) -> None:
        count = column.shape[1]
        bad = np.zeros(count, bool)
        started, ended, seen_dot, negative = (np.zeros(count, bool) for _ in range(4))
        digits, decimals = np.zeros(count, np.int64), np.zeros(count, np.int64)
        mantissa = np.zeros(count, np.int64)
        for byte in column:
            space = byte == _SPACE
            digit = (byte >= 0x30) & (byte <= 0x39)
            sign = (byte == signs[0]) | (byte == signs[-1])
            dot = (byte == 0x2E) if point else np.zeros(count, bool)
            bad |= ~(space | digit | sign | dot) | (sign & started) | (dot & (seen_dot | ended)) | (digit & ended)
            negative |= byte == 0x2D
            ended |= space & started
            started |= ~space
            seen_dot |= dot
            digits += digit
            decimals += digit & seen_dot
            np.copyto(mantissa, mantissa * 10 + (byte.astype(np.int64) - 0x30), where=digit & (digits <= 15))
        self.plain = ~bad & (digits >= 1) & (digits <= 15)
        self.decimals = decimals
        self.values = np.where(negative, -1.0, 1.0) * (mantissa / 10.0 ** np.minimum(decimals, 22))


def number_columns(column: np.ndarray, data_type: str) -> Numbers | None:
    """The plainly written numbers of a column of this data_type (None: a type they are not)."""
    if data_type == "ASCII_Real":
        return Numbers(column, b"+-", True)
    if data_type == "ASCII_Integer":
        return Numbers(column, b"+-", False)
    if data_type == "ASCII_NonNegative_Integer":
        return Numbers(column, b"+", False)
    return None


def text_values(column: np.ndarray, parse: Callable[[bytes], float] | None) -> np.ndarray | None:
    """A column of numbers (bytes x records) as float64, read by numpy, or by `parse` once per
    distinct value (None: one could not be read, so the caller checks them all exactly)."""
    texts = np.ascontiguousarray(column.T).view(f"S{column.shape[0]}").ravel()
    if parse is None:
        try:
            return texts.astype(np.float64)
        except ValueError:
            return None
    distinct, where = np.unique(texts, return_inverse=True)
    try:
        numbers = np.array([parse(text) for text in distinct.tolist()], np.float64)
    except (ValueError, OverflowError):
        return None
    return numbers[where.ravel()]


def binary_values(column: np.ndarray, data_type: str) -> np.ndarray:
    """A column of a binary field (bytes x records) as float64 (as struct unpacks then float())."""
    return np.ascontiguousarray(column.T).view(NUMPY_TYPES[data_type]).ravel().astype(np.float64)
def out_of_range(values: np.ndarray, ranges: tuple[tuple[float | None, float | None], ...],
                 constants: np.ndarray) -> np.ndarray:
    """Values outside any of the ranges and equal to no special constant (NaN is neither in
    nor out of a range)."""
    outside = np.zeros(len(values), bool)
    for low, high in ranges:
        if low is not None:
            outside |= values < low
        if high is not None:
            outside |= values > high
    if constants.size and outside.any():
        outside &= ~np.isin(values, constants)
    return outside
