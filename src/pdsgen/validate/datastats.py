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

_BLOCK_BYTES = 8 * 1024 * 1024


@dataclass(slots=True)
class Stats:
    count: int  # valid samples
    special: int  # samples equal to a special constant or NaN
    minimum: float | None
    maximum: float | None
    mean: float | None
    std: float | None


@dataclass(slots=True)
class Layout:
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


def image_stats(path: Path, layout: Layout, specials: list[float], want_moments: bool) -> Stats:
    """Min, max (and mean, std if asked) of the valid samples, read block by block."""
    lines_per_block = max(1, _BLOCK_BYTES // max(1, layout.line_bytes))
    buf = bytearray(lines_per_block * layout.line_bytes)
    is_float = layout.dtype.kind == "f"
    special_values = np.array(specials, dtype=layout.dtype) if specials else None
    count = special = 0
    lo, hi = math.inf, -math.inf
    total_mean, total_m2 = 0.0, 0.0
    with open(path, "rb") as fh:
        fh.seek(layout.offset)
        remaining = layout.lines
        while remaining > 0:
            n = min(lines_per_block, remaining)
            view = memoryview(buf)[: n * layout.line_bytes]
            got = fh.readinto(view)
            if got < len(view):
                n = got // layout.line_bytes
                remaining = n  # truncated file: use what is there, then stop
                if n == 0:
                    break
            rows = np.frombuffer(buf, dtype=np.uint8, count=n * layout.line_bytes).reshape(
                n, layout.line_bytes
            )
            data_bytes = rows[:, layout.prefix : layout.prefix + layout.samples * layout.dtype.itemsize]
            block = np.ascontiguousarray(data_bytes).view(layout.dtype).reshape(-1)
            bmin, bmax = block.min(), block.max()
            needs_mask = (is_float and (math.isnan(bmin) or math.isnan(bmax))) or (
                special_values is not None
                and bool(((special_values >= bmin) & (special_values <= bmax)).any())
            )
            if needs_mask:
                mask = np.ones(block.shape, dtype=bool)
                if is_float:
                    mask &= ~np.isnan(block)
                if special_values is not None:
                    for value in special_values:
                        mask &= block != value
                valid = int(mask.sum())
                special += block.size - valid
                if valid:
                    bmin = block.min(where=mask, initial=np.inf if is_float else np.iinfo(block.dtype).max)
                    bmax = block.max(where=mask, initial=-np.inf if is_float else np.iinfo(block.dtype).min)
                    values = block[mask] if want_moments else None
            else:
                valid = block.size
                values = block if want_moments else None
            if valid:
                lo, hi = min(lo, float(bmin)), max(hi, float(bmax))
                if want_moments:
                    total_mean, total_m2 = _merge(count, total_mean, total_m2, values)  # type: ignore[arg-type]
                count += valid
            remaining -= n
    if count == 0:
        return Stats(0, special, None, None, None, None)
    std = math.sqrt(total_m2 / count) if want_moments else None
    return Stats(count, special, lo, hi, total_mean if want_moments else None, std)


def _merge(count: int, mean: float, m2: float, values: np.ndarray) -> tuple[float, float]:
    """Chan's parallel update of mean and sum of squared deviations."""
    v = values.astype(np.float64)
    n = v.size
    bmean = float(v.mean())
    bm2 = float(((v - bmean) ** 2).sum())
    total = count + n
    delta = bmean - mean
    return mean + delta * n / total, m2 + bm2 + delta * delta * count * n / total
