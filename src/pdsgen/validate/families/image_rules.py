"""IMG family: the IMAGE object's keywords, and its statistics recomputed from the data.

Sample types map to numpy dtypes (PC_REAL = little-endian IEEE float, MSB_INTEGER =
big-endian signed ...). Special constants are checked against what the sample type
can hold; VALID_MINIMUM/MAXIMUM and MINIMUM/MAXIMUM/MEAN/STANDARD_DEVIATION are
compared with values recomputed by streaming the data (see datastats).
"""

from __future__ import annotations

import math
import re
import struct
from collections.abc import Iterator

import numpy as np

from ...label.grammar import DATA_TYPES, SAMPLE_TYPES, SPECIAL_CONSTANTS
from ...label.tree import Block, Value
from ..context import FileContext
from ..datastats import SampleLayout, Stats, image_stats
from ..model import Hit
from ..quantities import is_image
from ..registry import Rule, register

_TYPES = SAMPLE_TYPES
_EXCLUDED = SPECIAL_CONSTANTS  # values left out of the statistics
_REQUIRED = ("LINES", "LINE_SAMPLES", "SAMPLE_TYPE", "SAMPLE_BITS")
_STORAGE = ("BAND_SEQUENTIAL", "LINE_INTERLEAVED", "SAMPLE_INTERLEAVED")


def sample_dtype(block: Block) -> np.dtype | None:
    """numpy dtype of the samples, or None when the type/bits pair is not readable."""
    st, bits = block.text("SAMPLE_TYPE"), block.number("SAMPLE_BITS")
    if st is None or not isinstance(bits, int):
        return None
    entry = _TYPES.get(st.upper())
    if entry is None:
        return None
    order, kind = entry
    if kind == "f" and bits not in (32, 64):
        return None
    if kind in "iu" and bits not in (8, 16, 32, 64):
        return None
    return np.dtype(f"{order if bits > 8 else '|'}{kind}{bits // 8}")


def _int(block: Block, key: str, default: int = 0) -> int | None:
    val = block.number(key)
    if val is None:
        return default if block.get(key) is None else None
    return int(val) if isinstance(val, int) else None


def layout(block: Block, offset: int) -> SampleLayout | None:
    dtype = sample_dtype(block)
    lines, samples, bands = _int(block, "LINES", -1), _int(block, "LINE_SAMPLES", -1), _int(block, "BANDS", 1)
    prefix, suffix = _int(block, "LINE_PREFIX_BYTES"), _int(block, "LINE_SUFFIX_BYTES")
    if dtype is None or None in (lines, samples, bands, prefix, suffix):
        return None
    if lines < 0 or samples < 0 or bands < 1:  # type: ignore[operator]
        return None
    storage = "_".join((block.text("BAND_STORAGE_TYPE") or "BAND_SEQUENTIAL").upper().split())
    if storage == "SAMPLE_INTERLEAVED":
        return SampleLayout(offset, dtype, lines, samples * bands, prefix, suffix)  # type: ignore[arg-type,operator]
    if storage == "LINE_INTERLEAVED":
        return SampleLayout(offset, dtype, lines * bands, samples, prefix, suffix)  # type: ignore[operator,arg-type]
    return SampleLayout(offset, dtype, lines * bands, samples, prefix, suffix)  # type: ignore[operator,arg-type]


def object_bytes(block: Block) -> int | None:
    """Bytes an IMAGE or TABLE object occupies, from its keywords alone."""
    if block.get("ROWS") is not None and block.get("ROW_BYTES") is not None:
        rows, row_bytes = block.number("ROWS"), block.number("ROW_BYTES")
        pre, suf = _int(block, "ROW_PREFIX_BYTES"), _int(block, "ROW_SUFFIX_BYTES")
        if isinstance(rows, int) and isinstance(row_bytes, int) and pre is not None and suf is not None:
            return rows * (row_bytes + pre + suf)
        return None
    lay = layout(block, 0)
    return lay.lines * lay.line_bytes if lay is not None else None


def _images(ctx: FileContext) -> Iterator[Block]:
    for block in ctx.root.walk():
        if is_image(block):
            yield block


def check_required(ctx: FileContext) -> Iterator[Hit]:
    for block in _images(ctx):
        missing = [k for k in _REQUIRED if block.get(k) is None]
        if missing:
            yield Hit(f"OBJECT = {block.name} lacks {', '.join(missing)}", block.line, missing[0])


def check_sample_type(ctx: FileContext) -> Iterator[Hit]:
    for block in _images(ctx):
        st, bits = block.get("SAMPLE_TYPE"), block.get("SAMPLE_BITS")
        if st is None or bits is None:
            continue
        if st.value.text.upper() not in _TYPES:
            if st.value.text.upper() not in DATA_TYPES:
                yield Hit(f"SAMPLE_TYPE {st.value.text} is not a PDS3 sample type", st.line, "SAMPLE_TYPE")
            continue
        if sample_dtype(block) is None:
            yield Hit(f"SAMPLE_TYPE {st.value.text} cannot have SAMPLE_BITS = {bits.value.raw}",
                      bits.line, "SAMPLE_BITS")


def check_bit_mask(ctx: FileContext) -> Iterator[Hit]:
    for block in _images(ctx):
        mask, bits = block.get("SAMPLE_BIT_MASK"), block.number("SAMPLE_BITS")
        if mask is None or not isinstance(bits, int) or not mask.value.is_number:
            continue
        value = int(mask.value.number)
        if value < 0 or value.bit_length() > bits:  # not 1 << bits: SAMPLE_BITS is the label's word
            yield Hit(f"SAMPLE_BIT_MASK {mask.value.raw} has bits beyond SAMPLE_BITS = {bits}",
                      mask.line, "SAMPLE_BIT_MASK")
        elif mask.value.kind == "based" and mask.value.raw.startswith("2#"):
            digits = mask.value.raw.split("#")[1]
            if len(digits) != bits:
                yield Hit(f"SAMPLE_BIT_MASK {mask.value.raw} has {len(digits)} binary digits, "
                          f"expected SAMPLE_BITS = {bits}", mask.line, "SAMPLE_BIT_MASK")


def constant_value(val: Value, dtype: np.dtype) -> tuple[float | None, str | None]:
    """(value as stored in the samples, problem) for a special-constant keyword."""
    if not val.is_number:
        return None, None
    bits = dtype.itemsize * 8
    if dtype.kind == "f":
        if val.kind == "based":
            pattern = int(val.number)
            if pattern < 0 or pattern >= 1 << bits:
                return None, f"bit pattern {val.raw} does not fit {bits}-bit samples"
            fmt = ">I" if bits == 32 else ">Q"
            return struct.unpack(">f" if bits == 32 else ">d", struct.pack(fmt, pattern))[0], None
        number = float(val.number)
        if bits == 32 and math.isfinite(number) and abs(number) > float(np.finfo(np.float32).max):
            return None, f"{val.raw} is beyond the float32 range"
        return number, None
    info = np.iinfo(dtype)
    number = val.number
    if val.kind == "real":
        if not float(number).is_integer():
            return None, f"{val.raw} is not an integer, samples are {dtype.kind}int{bits}"
        number = int(number)
    if val.kind == "based" and dtype.kind == "i" and int(number) >= 1 << (bits - 1):
        number = int(number) - (1 << bits) if int(number) < 1 << bits else number
    if not info.min <= int(number) <= info.max:
        return None, f"{val.raw} is outside {info.min}..{info.max} of the sample type"
    return float(number), None


def check_constants(ctx: FileContext) -> Iterator[Hit]:
    for block in _images(ctx):
        dtype = sample_dtype(block)
        if dtype is None:
            continue
        mask = block.value("SAMPLE_BIT_MASK")
        for key in SPECIAL_CONSTANTS:
            stmt = block.get(key)
            if stmt is None:
                continue
            value, problem = constant_value(stmt.value, dtype)
            if (problem is None and value is not None and dtype.kind == "u" and mask is not None
                    and mask.is_number and int(value) & ~int(mask.number) != 0):
                problem = f"{stmt.value.raw} has bits outside SAMPLE_BIT_MASK {mask.raw}"
            if problem:
                yield Hit(f"{key}: {problem} ({block.text('SAMPLE_TYPE')}, "
                          f"{block.number('SAMPLE_BITS')} bits)", stmt.line, key)


def check_valid_range_order(ctx: FileContext) -> Iterator[Hit]:
    for block in _images(ctx):
        lo, hi = block.number("VALID_MINIMUM"), block.number("VALID_MAXIMUM")
        if lo is not None and hi is not None and lo > hi:
            stmt = block.get("VALID_MINIMUM")
            yield Hit(f"VALID_MINIMUM {lo} is above VALID_MAXIMUM {hi}", stmt.line if stmt else None,
                      "VALID_MINIMUM")


def check_band_storage(ctx: FileContext) -> Iterator[Hit]:
    for block in _images(ctx):
        stmt = block.get("BAND_STORAGE_TYPE")
        if stmt is None or stmt.value.text.upper() in _STORAGE:
            continue
        spelled = "_".join(stmt.value.text.upper().split())
        if spelled in _STORAGE:  # Kaguya's "BAND SEQUENTIAL": readers take it, the meaning is plain
            yield Hit(f"BAND_STORAGE_TYPE {stmt.value.raw} is {spelled} written with spaces",
                      stmt.line, "BAND_STORAGE_TYPE", severity="warning")
        else:
            yield Hit(f"BAND_STORAGE_TYPE {stmt.value.text} is not one of {', '.join(_STORAGE)}",
                      stmt.line, "BAND_STORAGE_TYPE")


# -- statistics from the data -------------------------------------------------------
_STAT_KEYS = ("VALID_MINIMUM", "VALID_MAXIMUM", "MINIMUM", "MAXIMUM", "MEAN", "STANDARD_DEVIATION")


def _stats_for(ctx: FileContext, block: Block) -> tuple[Stats, Block] | None:
    cache = ctx.cache.setdefault("_img_stats", {})
    if id(block) in cache:
        return cache[id(block)]
    result = None
    ptr = next((p for p in ctx.data_pointers() if ctx.object_for(p) is block), None)
    if ptr is not None and not ctx.labels_only and not ctx.data_absent and not _inside_label(ctx, ptr):
        path, offset = ctx.target_path(ptr), ctx.pointer_offset(ptr)
        lay = layout(block, offset) if offset is not None else None
        if path is not None and lay is not None and lay.lines * lay.samples > 0:
            specials = []
            # the IMAGE's own special constants, and HRSC's MEX:DTM_MISSING_DN (group MEX:DTM)
            stmts = [block.get(key) for key in _EXCLUDED]
            stmts += [g.get("MEX:DTM_MISSING_DN") for g in ctx.root.walk()]
            for stmt in stmts:
                if stmt is not None:
                    value, problem = constant_value(stmt.value, lay.dtype)
                    if value is not None and problem is None:
                        specials.append(value)
            moments = block.get("MEAN") is not None or block.get("STANDARD_DEVIATION") is not None
            result = (image_stats(path, lay, specials, moments), block)
    cache[id(block)] = result
    return result


def _inside_label(ctx: FileContext, ptr) -> bool:
    """An attached object said to start inside the label text (PTR-004): its "samples"
    would be the label's own bytes, so no statistics are computed from them."""
    offset = ctx.pointer_offset(ptr)
    return ptr.attached and offset is not None and offset < ctx.label.label_end


def _close(a: float, b: float, rel: float) -> bool:
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-30)


def _as_stored_and_physical(data_value: float, block: Block) -> tuple[float, ...]:
    """The data value as stored, and after SCALING_FACTOR/OFFSET when the object has both:
    a label may state either."""
    scale, off = block.number("SCALING_FACTOR"), block.number("OFFSET")
    if scale is not None and off is not None:
        return data_value, data_value * scale + off
    return (data_value,)


def _matches(label_value: float, data_value: float, block: Block, rel: float) -> bool:
    """Equal as stored, or equal after SCALING_FACTOR/OFFSET (physical value)."""
    return any(_close(label_value, value, rel) for value in _as_stored_and_physical(data_value, block))


_PLAIN_DECIMAL = re.compile(r"^[+-]?\d*\.(\d+)$")
_BOUNDS = {"VALID_MINIMUM": -1, "VALID_MAXIMUM": +1}  # which side of the data a bound must lie on


def _last_place(raw: str) -> float | None:
    """One unit in the last decimal place of a value written without an exponent ("-4553.91"
    -> 0.01), or None: a label states a value only to the decimals it writes."""
    found = _PLAIN_DECIMAL.match(raw.strip())
    return 10.0 ** -len(found.group(1)) if found else None


def _stated_to_precision(key: str, label_value: float, data: float, step: float) -> str | None:
    """How a value stated to `step` relates to the data value: "exact" (the data rounded to
    the nearest step, or a bound rounded outwards by less than a step), "inside" (a bound
    rounded to the nearest step that falls inside the data's range), or None (no match)."""
    slack = step * 1e-6  # decimal text against binary floating point
    side = _BOUNDS.get(key)
    difference = label_value - data
    if side is not None and -slack <= difference * side < step:
        return "exact"  # outwards by less than a step: still bounds every valid sample
    if abs(difference) <= step / 2 + slack:
        return "exact" if side is None else "inside"
    return None


def _data_blocks(ctx: FileContext) -> Iterator[Block]:
    if ctx.labels_only:
        return
    for block in _images(ctx):
        if any(block.get(k) is not None for k in _STAT_KEYS):
            yield block


def check_extremes(ctx: FileContext) -> Iterator[Hit]:
    for block in _data_blocks(ctx):
        found = _stats_for(ctx, block)
        if found is None:
            continue
        stats = found[0]
        for key, data in (
            ("VALID_MINIMUM", stats.minimum),
            ("VALID_MAXIMUM", stats.maximum),
            ("MINIMUM", stats.minimum),
            ("MAXIMUM", stats.maximum),
        ):
            stmt = block.get(key)
            if stmt is None or not stmt.value.is_number:
                continue
            dtype = sample_dtype(block)
            label_value = constant_value(stmt.value, dtype)[0] if dtype is not None else None
            if label_value is None:
                continue
            if data is None:
                yield Hit(f"{key} = {stmt.value.raw} but the data hold no valid samples",
                          stmt.line, key)
            elif not _matches(label_value, data, block, 1e-6):
                shown = str(np.float32(data)) if dtype is not None and dtype.itemsize == 4 and \
                    dtype.kind == "f" else repr(data)
                step = _last_place(stmt.value.raw)
                precision = None if step is None else _precision_match(key, label_value, data, block, step)
                if precision == "inside":
                    yield Hit(f"{key} = {stmt.value.raw} is the data's {shown} rounded to the nearest "
                              f"{step:g}, on the inside: the extreme valid samples fall "
                              "outside the stated range", stmt.line, key, severity="warning")
                elif precision is None:
                    yield Hit(f"{key} = {stmt.value.raw} but the data give {shown} "
                              f"({stats.count} valid samples)", stmt.line, key)


def _precision_match(key: str, label_value: float, data: float, block: Block, step: float) -> str | None:
    """`_stated_to_precision` against the stored and the physical value: "exact" if either
    is, else "inside" if either is, else None."""
    found = {_stated_to_precision(key, label_value, value, step) for value in _as_stored_and_physical(data, block)}
    return next((verdict for verdict in ("exact", "inside") if verdict in found), None)


def check_moments(ctx: FileContext) -> Iterator[Hit]:
    for block in _data_blocks(ctx):
        found = _stats_for(ctx, block)
        if found is None or found[0].mean is None:
            continue
        stats = found[0]
        for key, data in (("MEAN", stats.mean), ("STANDARD_DEVIATION", stats.std)):
            stmt = block.get(key)
            if stmt is None or not stmt.value.is_number or data is None:
                continue
            if not _matches(float(stmt.value.py), data, block, 1e-3):  # type: ignore[arg-type]
                yield Hit(f"{key} = {stmt.value.raw} but the data give {data:.6g}", stmt.line, key)


register(
    Rule("IMG-001", "error", "IMAGE objects have LINES, LINE_SAMPLES, SAMPLE_TYPE, SAMPLE_BITS",
         check_required),
    Rule("IMG-002", "error", "SAMPLE_TYPE is known and fits SAMPLE_BITS", check_sample_type),
    Rule("IMG-003", "error", "SAMPLE_BIT_MASK has no bits beyond SAMPLE_BITS", check_bit_mask),
    Rule("IMG-004", "error", "special constants are representable in the sample type",
         check_constants),
    Rule("IMG-005", "error", "VALID_MINIMUM <= VALID_MAXIMUM", check_valid_range_order),
    Rule("IMG-006", "error", "BAND_STORAGE_TYPE is a PDS3 storage type", check_band_storage,
         note="warning for a standard type spelled with spaces (BAND SEQUENTIAL)"),
    Rule("IMG-007", "error", "VALID_MINIMUM/MAXIMUM and MINIMUM/MAXIMUM match the data",
         check_extremes, needs_data=True,
         note="to the last decimal written, bounds rounded outwards too; warning for a bound rounded inside "
              "the data"),
    Rule("IMG-008", "warning", "MEAN and STANDARD_DEVIATION match the data", check_moments,
         needs_data=True),
)
