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
    stop early where the file ends (a record it cuts short is not given)."""
    per_block = max(1, BLOCK_BYTES // record_length)
    first = 1
    while first <= records:
        want = min(per_block, records - first + 1)
        data = handle.read(want * record_length)
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


def text_suspects(column: np.ndarray, checks: list[re.Pattern[bytes]]) -> tuple[np.ndarray, np.ndarray]:
    """(values the checks may find fault with, blank values) of a records x width column of
    text: every value that is not printable ASCII, and every line a check stops at."""
    count, width = column.shape
    suspect = ~((column >= _SPACE) & (column <= 0x7E)).all(axis=1)
    blank = (column == _SPACE).all(axis=1)
    if checks and count:
        lines = np.empty((count, width + 1), np.uint8)
        lines[:, :width] = column
        lines[:, width] = _NEWLINE
        lines[suspect, :width] = _SPACE  # such a value is checked exactly anyway
        blob = lines.tobytes()
        for check in checks:
            _mark_stops(check, blob, width + 1, suspect)
    return suspect, blank


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


def text_values(column: np.ndarray, skip: np.ndarray, parse: Callable[[bytes], float] | None) -> np.ndarray | None:
    """The column's values as float64 (NaN where `skip`), read by numpy, or by `parse` once per
    distinct value (None: numpy could not read one, so the caller checks them all exactly)."""
    texts = np.ascontiguousarray(column).view(f"S{column.shape[1]}").ravel()
    texts = np.where(skip, b"nan", texts)
    if parse is None:
        try:
            return texts.astype(np.float64)
        except ValueError:
            return None
    distinct, where = np.unique(texts, return_inverse=True)
    try:
        numbers = np.array([np.nan if text == b"nan" else parse(text) for text in distinct.tolist()], np.float64)
    except (ValueError, OverflowError):
        return None
    return numbers[where.ravel()]


def binary_values(column: np.ndarray, data_type: str) -> np.ndarray:
    """A records x size column of a binary field as float64 (as struct unpacks then float())."""
    return np.ascontiguousarray(column).view(NUMPY_TYPES[data_type]).ravel().astype(np.float64)


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
