"""A label tree as plain Python values, in the shape pvl gives a PDS3 label.

Code that reads a label as a mapping of keywords (the Extras' product description, the
HRSC writer's source labels, the label georeferencing they share) takes this mapping of
the one reader's tree, so it needs no second reader and agrees with the validator on
what the label says. The values are what pvl would return, so that code reads the same
numbers and texts it read before: int, float, str (a quoted text's blanks and line ends
collapsed to single spaces, a word broken with '-' at a line end joined), None for NULL,
bool for TRUE/FALSE, inf/nan, datetime/date/time (UTC), a list for a sequence, a
frozenset for a set, and `MappedQuantity(value, units)` for a value with a unit.

`BlockView` is the other shape: a block read lazily as a mapping (upper-case keywords and
OBJECT/GROUP names), its values decoded by a decoder the caller chooses with the quantity
class it reads (as pvl's decoder model lets a caller choose): `numbers_as_quantities`
(every number a quantity, a float; the review page's label facts and kind decision) or
`units_as_quantities` (a number with a unit a quantity, other numbers as written; the
georeferencing of a migrated product).
"""

from __future__ import annotations

import datetime as dt
import math
import re
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any, NamedTuple

from .tree import Block, Label, Statement, Value


class MappedQuantity(NamedTuple):
    """A value with its unit (`2575.0 <KM>`), with pvl's field names."""

    value: Any
    units: str


@dataclass(frozen=True)
class LabelQuantity:
    """A number with its unit (None when the label gives none), read through a BlockView."""

    value: float | int
    units: str | None


Decoder = Callable[[Value], Any]


class BlockView(Mapping[str, Any]):
    """A block of the label tree as a read-only mapping: its keywords (pointers are looked up
    by `^NAME` but are not among the keys) and OBJECT/GROUP names, upper case, to values as
    `decode` makes them and to nested views. A keyword is found before an object of its name."""

    def __init__(self, block: Block, decode: Decoder) -> None:
        self._block = block
        self._decode = decode

    def _keys(self) -> dict[str, None]:
        keys = [s.keyword.upper() for s in self._block.statements() if not s.pointer]
        return dict.fromkeys(keys + [b.name.upper() for b in self._block.blocks()])

    def __getitem__(self, key: str) -> Any:
        value = self._block.value(key)
        if value is not None:
            return self._decode(value)
        child = next(self._block.blocks(key), None)
        if child is None:
            raise KeyError(key)
        return BlockView(child, self._decode)

    def __iter__(self) -> Iterator[str]:
        return iter(self._keys())

    def __len__(self) -> int:
        return len(self._keys())


def numbers_as_quantities(quantity: Callable[[float, str | None], Any] = LabelQuantity) -> Decoder:
    """Every number a `quantity(float, unit or None)`, a sequence a list, anything else its text."""

    def decode(value: Value) -> Any:
        if value.items is not None:
            return [decode(item) for item in value.items]
        if value.is_number:
            return quantity(float(value.number), value.unit)
        return value.text

    return decode


def units_as_quantities(quantity: Callable[[float | int, str], Any] = LabelQuantity) -> Decoder:
    """A number with a unit a `quantity(number, unit)`, other numbers as written (int or float),
    anything else (a sequence too) its text."""

    def decode(value: Value) -> Any:
        if value.is_number:
            return quantity(value.number, value.unit) if value.unit else value.number
        return value.text

    return decode


_DATE_TIME = re.compile(
    r"(?P<year>\d{4})-(?:(?P<doy>\d{3})|(?P<month>\d{1,2})-(?P<day>\d{1,2}))"
    r"(?:T(?P<time>.*))?"
)
_TIME = re.compile(r"(?P<h>\d{1,2}):(?P<m>\d{1,2})(?::(?P<s>\d{1,2})(?:\.(?P<f>\d*))?)?Z?")
_WORDS: dict[str, Any] = {"NULL": None, "TRUE": True, "FALSE": False, "INF": math.inf, "+INF": math.inf,
                          "-INF": -math.inf, "NAN": math.nan}
_BROKEN_WORD = re.compile(r"-(?:\r\n|\n|\r)\s*")


def label_mapping(label: Label) -> dict[str, Any]:
    """The whole label as a mapping (see as_mapping), with the SFDU label that wraps it first."""
    found: dict[str, Any] = {label.sfdu: "SFDU_LABEL"} if label.sfdu else {}
    for key, value in as_mapping(label.root).items():
        found.setdefault(key, value)
    return found


def as_mapping(block: Block) -> dict[str, Any]:
    """The block's keywords (pointers with their caret) and OBJECT/GROUP names, as written,
    to their values and nested mappings; of a repeated keyword, the first."""
    found: dict[str, Any] = {}
    for item in block.items:
        if isinstance(item, Statement):
            found.setdefault(("^" if item.pointer else "") + item.keyword, python_value(item.value))
        else:
            found.setdefault(item.name, as_mapping(item))
    return found


def python_value(value: Value) -> Any:
    """One value as pvl returns it (see the module's docstring)."""
    if value.items is None:
        return _scalar(value, with_unit=True)
    if value.kind == "set":
        return frozenset(python_value(item) for item in value.items)
    if value.unit:  # `(1, 2) <M>`: the unit belongs to the sequence
        return MappedQuantity([_scalar(item, with_unit=item.unit != value.unit) if item.items is None
                         else python_value(item) for item in value.items], value.unit)
    return [python_value(item) for item in value.items]


def _scalar(value: Value, with_unit: bool) -> Any:
    plain = _plain(value)
    return MappedQuantity(plain, value.unit) if with_unit and value.unit else plain


def _plain(value: Value) -> Any:
    kind = value.kind
    if kind in ("int", "real", "based"):
        return value.py
    if kind == "string":
        return " ".join(_BROKEN_WORD.sub("", value.text).split())
    if kind == "ident":
        upper = value.text.upper()
        return _WORDS[upper] if upper in _WORDS else value.text
    if kind in ("date", "bad"):  # pvl reads a date with one-digit fields too (10:28:2)
        return _date_time(value.text)
    return value.text  # symbol, or a malformed number or date, as written


def _date_time(text: str) -> dt.datetime | dt.date | dt.time | str:
    """A PDS3 date/time (CCYY-MM-DDThh:mm:ss.fff, CCYY-DDDThh..., or a time alone) in UTC."""
    date_part = _DATE_TIME.fullmatch(text)
    try:
        if date_part is None:
            time_part = _TIME.fullmatch(text)
            return _clock(time_part) if time_part is not None else text
        day, time_part = _calendar(date_part)
        if date_part["time"] is None:
            return day
        if time_part is None:
            return text
        return dt.datetime.combine(day, _clock(time_part))
    except ValueError:
        return text


def utc_datetime(text: str | None) -> dt.datetime | None:
    """A PDS time, PDS3's or PDS4's (CCYY-MM-DD or CCYY-DDD, optionally Thh:mm[:ss[.fff]], optionally
    Z; quoted or not) as a naive UTC datetime to the second, a date alone at midnight; None for
    anything else (UNK, N/A, nil, a time alone, a malformed or impossible date). The times the
    validator compares (creation in the future, stop before start, PDS3 against PDS4) are read
    here, on the grammar the label mapping reads dates with. The clock is added as a duration,
    so a leap second (23:59:60) or 24:00 reads as the instant it names."""
    date_part = _DATE_TIME.fullmatch((text or "").strip().strip('"'))
    if date_part is None:
        return None
    try:
        day, time_part = _calendar(date_part)
    except ValueError:
        return None
    if date_part["time"] is not None and time_part is None:
        return None
    hours, minutes, seconds = (int(time_part[k] or 0) for k in ("h", "m", "s")) if time_part else (0, 0, 0)
    return dt.datetime.combine(day, dt.time()) + dt.timedelta(hours=hours, minutes=minutes, seconds=seconds)


def _calendar(date_part: re.Match[str]) -> tuple[dt.date, re.Match[str] | None]:
    """The day a matched date names (ValueError for an impossible one) and its clock, read by
    _TIME (None when it has none, or one _TIME does not read)."""
    year = int(date_part["year"])
    if date_part["doy"]:
        day = dt.date(year, 1, 1) + dt.timedelta(days=int(date_part["doy"]) - 1)
    else:
        day = dt.date(year, int(date_part["month"]), int(date_part["day"]))
    clock = date_part["time"]
    return day, _TIME.fullmatch(clock) if clock is not None else None


def _clock(m: re.Match[str]) -> dt.time:
    fraction = (m["f"] or "")[:6].ljust(6, "0")
    return dt.time(int(m["h"]), int(m["m"]), int(m["s"] or 0), int(fraction), tzinfo=dt.timezone.utc)
