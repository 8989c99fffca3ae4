"""Encode Python values as PDS3 (ODL) value text.

Every label pdsgen writes goes through `format_value`, so quoting, units, based
integers and number formatting are decided in exactly one place. The choice of
quoted string versus bare identifier is made by the caller through the type:
`str` is always quoted, `Symbol` never is.
"""

from __future__ import annotations

import datetime as _dt
import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..encode import EncodeError, check_pvl_string, shown
from .grammar import IDENTIFIER_PATTERN

_SYMBOL_RE = re.compile(f"^{IDENTIFIER_PATTERN}$")
_UNIT_RE = re.compile(r"^[A-Za-z0-9_/*.^()\- ]+$")


class Symbol(str):
    """An unquoted identifier or enumerated value, e.g. ``PC_REAL``."""

    def __new__(cls, text: str) -> Symbol:
        if not _SYMBOL_RE.fullmatch(text):
            raise EncodeError(None, None, f"{shown(text)!r} is not a PDS identifier; pass it as a quoted string", text)
        return super().__new__(cls, text)


@dataclass(frozen=True)
class Quantity:
    """A number with its unit, written ``3396.19 <KM>``."""

    value: float | int
    unit: str

    def __post_init__(self) -> None:
        if not _UNIT_RE.fullmatch(self.unit):
            raise EncodeError(None, None, f"{shown(self.unit)!r} is not a valid PDS unit", self.unit)


@dataclass(frozen=True)
class Fixed:
    """A real written with a fixed number of decimals, e.g. ``-4049.48`` (release formats)."""

    value: float
    decimals: int


@dataclass(frozen=True)
class Based:
    """A based integer such as ``16#FF7FFFFB#`` or ``2#0000001111111111#``.

    `digits` zero-pads the written form, so a bit mask keeps its full width.
    """

    value: int
    base: int
    digits: int = 0

    def __post_init__(self) -> None:
        if self.base not in (2, 8, 16):
            raise ValueError("based integers are written in base 2, 8 or 16")
        if self.value < 0:
            raise ValueError("based integers are unsigned bit patterns")


def float32_bits(value: float) -> int:
    """The IEEE single-precision bit pattern of `value` (for MISSING_CONSTANT)."""
    return int(np.array(value, dtype=">f4").view(">u4"))


def shortest_float32(value: float) -> float:
    """The shortest decimal that reads back as the same float32.

    Statistics of float32 data are float32 values; writing them through a double
    (0.10000000149011612) would be float noise, while "0.1" reads back exactly.
    """
    return float(np.format_float_positional(np.float32(value), unique=True, trim="0"))


def format_real(value: float) -> str:
    """Write a real number without float noise, always with a decimal point.

    A value within 1e-6 of a shorter decimal is written as that decimal, but
    never by more than 1e-13 relative: projection offsets of millions of pixels
    times MAP_SCALE must still reproduce the geotransform to 1e-6 pixel.
    Otherwise the shortest text that round-trips the double.
    """
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"cannot write {value!r} in a PDS label")
    if value == 0.0:
        return "0.0"
    tolerance = min(1e-6, 1e-13 * abs(value))
    for decimals in range(0, 17):
        rounded = round(value, decimals)
        if abs(value - rounded) <= tolerance:
            value = rounded
            break
    text = repr(value)
    if "e" in text:
        mantissa, exponent = text.split("e")
        if "." not in mantissa:
            mantissa += ".0"
        return f"{mantissa}E{int(exponent):+03d}"
    if "." not in text:
        text += ".0"
    return text


def format_string(text: str, keyword: str | None = None, source: str | os.PathLike[str] | None = None) -> str:
    """A double-quoted string, the one PVL encoding of text. White space with a line break is
    folded to single spaces, as every PVL reader reads it; a double quote (which PDS3 cannot
    escape), a control character or non-ASCII text is refused (EncodeError), never written."""
    check_pvl_string(text, keyword, source)
    return '"' + " ".join(text.split()) + '"' if ("\n" in text or "\r" in text or "\t" in text) else f'"{text}"'


def format_based(value: Based) -> str:
    digits = np.base_repr(value.value, value.base)
    return f"{value.base}#{digits.zfill(value.digits)}#"


def format_value(value: object) -> str:
    """Encode one keyword value (scalar, quantity, sequence) as label text."""
    if isinstance(value, Symbol):
        return str(value)
    if isinstance(value, str):
        return format_string(value)
    if isinstance(value, bool):
        raise TypeError("PDS3 has no boolean type; use Symbol('TRUE') or Symbol('FALSE')")
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return format_real(float(value))
    if isinstance(value, Quantity):
        return f"{format_value(value.value)} <{value.unit}>"
    if isinstance(value, Based):
        return format_based(value)
    if isinstance(value, Fixed):
        return f"{value.value:.{value.decimals}f}"
    if isinstance(value, _dt.datetime):
        return value.replace(tzinfo=None).isoformat(timespec="milliseconds")
    if isinstance(value, _dt.date):
        return value.isoformat()
    if isinstance(value, Sequence):
        return "(" + ", ".join(format_value(item) for item in value) + ")"
    raise TypeError(f"no PDS encoding for {type(value).__name__}: {value!r}")
