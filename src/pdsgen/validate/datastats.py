"""Streamed statistics of an IMAGE object's samples: flat memory whatever the raster size.

The file is read a block of lines at a time into one reused buffer; prefix/suffix bytes
are sliced off and the samples viewed in place with numpy. Special values (missing
constants, NaN) are excluded, so the result is comparable with VALID_MINIMUM/MAXIMUM.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..bounded import file_size

_BLOCK_BYTES = 1024 * 1024


@dataclass(slots=True)
class Stats:
    count: int  # valid samples
    special: int  # samples equal to a special constant or NaN
    minimum: float | None
    maximum: float | None
    mean: float | None
    std: float | None


@dataclass(slots=True)
class SampleLayout:
    """Where the samples are: byte offset, dtype, and the line structure around them."""

    offset: int
    dtype: np.dtype
    lines: int  # number of stored lines (LINES x BANDS for band-sequential)
    samples: int  # samples per stored line (LINE_SAMPLES x BANDS when interleaved)
    prefix: int = 0
    suffix: int = 0

    @property
    def line_bytes(self) -> int:
        return self.prefix + self.samples * self.dtype.itemsize + self.suffix


def image_stats(path: Path, layout: SampleLayout, specials: list[float], want_moments: bool) -> Stats:
    """Min, max (and mean, std if asked) of the valid samples, read block by block.

    Blocks are small enough to stay in the CPU cache, so the few passes over each (min,
    max, and only where a special value is an extreme, a mask) cost little next to the
    read itself. A special constant inside the data range cannot change min or max, so
    only one that *is* the block's extreme is masked out.
    """
    native = layout.dtype.newbyteorder("=")
    swap = layout.dtype.byteorder not in ("=", "|") and layout.dtype != native
    # the label's line length against the bytes the file holds past the offset, before the
    # buffer is made: a LINE_SAMPLES of 10^12 asked for a terabyte; no whole line, no samples
    there = file_size(path) - layout.offset
    if layout.line_bytes <= 0 or layout.line_bytes > there:
        return Stats(0, 0, None, None, None, None)
    lines_per_block = max(1, _BLOCK_BYTES // layout.line_bytes)
    buf = bytearray(lines_per_block * layout.line_bytes)
    is_float = native.kind == "f"
    special_values = [native.type(v) for v in specials]
    count = special = 0
    lo, hi = math.inf, -math.inf
    total_mean, total_m2 = 0.0, 0.0
    packed = layout.prefix == 0 and layout.suffix == 0
    with open(path, "rb") as fh:
        fh.seek(layout.offset)
        remaining = layout.lines
        while remaining > 0:
            n = min(lines_per_block, remaining)
            view = memoryview(buf)[: n * layout.line_bytes]
            got = fh.readinto(view)
            if got < len(view):
                n = got // layout.line_bytes
                remaining = n  # truncated file: use the whole lines that are there, then stop
                if n == 0:
                    break
            if packed:
                block = np.frombuffer(buf, dtype=layout.dtype, count=n * layout.samples)
            else:
                rows = np.frombuffer(buf, dtype=np.uint8, count=n * layout.line_bytes).reshape(n, -1)
                data = rows[:, layout.prefix : layout.prefix + layout.samples * layout.dtype.itemsize]
                block = np.ascontiguousarray(data).view(layout.dtype).reshape(-1)
            if swap:  # in place: the buffer is ours, and native order is what SIMD loops want
                block = block.byteswap(inplace=True).view(native)
            valid, bmin, bmax, values = _block_extremes(block, special_values, is_float, want_moments)
            special += block.size - valid
            if valid:
                lo, hi = min(lo, bmin), max(hi, bmax)
                if want_moments:
                    total_mean, total_m2 = _merge(count, total_mean, total_m2, values)
                count += valid
            remaining -= n
    if count == 0:
        return Stats(0, special, None, None, None, None)
    std = math.sqrt(total_m2 / count) if want_moments else None
    return Stats(count, special, lo, hi, total_mean if want_moments else None, std)


def _block_extremes(block: np.ndarray, specials: list, is_float: bool, want_moments: bool):
    """(valid count, min, max, valid values or None) of one block; may overwrite the block."""
    bmin, bmax = block.min(), block.max()
    if is_float and (math.isnan(bmin) or math.isnan(bmax)):
        return _masked(block, specials, is_float, want_moments)
    valid = block.size
    touching = [v for v in specials if bmin <= v <= bmax]
    if touching and want_moments:
        return _masked(block, specials, is_float, want_moments)
    for value in touching:
        hits = block == value
        count = int(np.count_nonzero(hits))
        if not count:
            continue
        valid -= count
        if valid == 0:
            return 0, None, None, None
        if value == bmin or value == bmax:
            # the special value is an extreme: replace it by the other extreme and look again
            np.putmask(block, hits, bmax if value == bmin else bmin)
            bmin, bmax = block.min(), block.max()
    return valid, float(bmin), float(bmax), (block if want_moments else None)


def _masked(block: np.ndarray, specials: list, is_float: bool, want_moments: bool):
    mask = ~np.isnan(block) if is_float else np.ones(block.shape, dtype=bool)
    for value in specials:
        mask &= block != value
    values = block[mask]
    if values.size == 0:
        return 0, None, None, None
    return values.size, float(values.min()), float(values.max()), (values if want_moments else None)


def _merge(count: int, mean: float, m2: float, values: np.ndarray) -> tuple[float, float]:
    """Chan's parallel update of mean and sum of squared deviations."""
    v = values.astype(np.float64)
    n = v.size
    bmean = float(v.mean())
    bm2 = float(((v - bmean) ** 2).sum())
    total = count + n
    delta = bmean - mean
    return mean + delta * n / total, m2 + bm2 + delta * delta * count * n / total
