"""Linear contrast stretches from percentiles of the valid data.

The stretch limits are computed once per product from a statistics sample and then
applied unchanged to the browse and the thumbnail, so both show the same contrast.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# HiRISE RDR Extras: lowest 0.1 % of values to black, highest 0.01 % to white.
ORTHO_LOW_PERCENT = 0.1
ORTHO_HIGH_PERCENT = 0.01
# DTM colour and grey range: robust against a few blunders at either end.
DTM_LOW_PERCENT = 0.5
DTM_HIGH_PERCENT = 0.5


@dataclass(frozen=True)
class Stretch:
    """Map [low, high] linearly onto [out_low, 255]; outside is clipped."""

    low: float
    high: float

    def apply(self, values: np.ndarray, out_low: int = 0) -> np.ndarray:
        span = self.high - self.low
        if not np.isfinite(span) or span <= 0:
            return np.full(values.shape, (out_low + 255) // 2, dtype=np.uint8)
        scaled = (values.astype(np.float32) - np.float32(self.low)) * np.float32(
            (255 - out_low) / span) + np.float32(out_low)
        return np.clip(np.rint(scaled), out_low, 255).astype(np.uint8)


def percentile_stretch(sample: np.ma.MaskedArray, low_percent: float,
                       high_percent: float) -> Stretch | None:
    """Stretch with `low_percent` % of the valid sample below low, `high_percent` % above high.

    None when the sample holds no valid value at all.
    """
    data = np.ma.asarray(sample).compressed()
    if data.size == 0:
        return None
    low, high = np.percentile(data, [low_percent, 100.0 - high_percent])
    if high <= low:  # constant data: widen so the value shows mid-grey, not a flat black
        low, high = float(low) - 0.5, float(high) + 0.5
    return Stretch(float(low), float(high))


HISTOGRAM_BINS = 65536


class StreamingStretch:
    """Percentile stretch of data seen block by block: memory is one histogram, not the image.

    Two passes over the same blocks: `see_range` (pass 1) finds the valid range and
    whether every value is a whole number; `count` (pass 2) fills a histogram over
    that range. Whole-number data spanning fewer than HISTOGRAM_BINS values (10- or
    16-bit DNs) get one bin per value, so the stretch points are the exact order
    statistics; other data get HISTOGRAM_BINS equal bins, a resolution of
    1/65536 of the range. A whole-image sort of a 20,000 x 60,000 mosaic would need
    gigabytes; this needs half a megabyte per band.
    """

    def __init__(self) -> None:
        self.low, self.high = math.inf, -math.inf
        self.whole = True
        self.counts: np.ndarray | None = None
        self._per_value = False
        self._edges: tuple[float, float] = (0.0, 1.0)

    @classmethod
    def for_whole_numbers(cls, low: int, high: int) -> StreamingStretch:
        """Integer data known to lie in [low, high] (a 16-bit type): one pass, one bin a value."""
        stats = cls()
        stats.low, stats.high = float(low), float(high)
        return stats

    def see_range(self, values: np.ndarray) -> None:
        """Pass 1: valid values (1-D) of one block."""
        if values.size == 0:
            return
        self.low = min(self.low, float(values.min()))
        self.high = max(self.high, float(values.max()))
        if self.whole:
            self.whole = bool(np.array_equal(values, np.floor(values)))

    def count(self, values: np.ndarray) -> None:
        """Pass 2: the same blocks' valid values again."""
        if self.counts is None:
            self._start()
        assert self.counts is not None
        if values.size == 0 or self.low > self.high:
            return
        first, width = self._edges
        index = ((values.astype(np.float64) - first) / width).astype(np.int64)
        np.clip(index, 0, self.counts.size - 1, out=index)
        self.counts += np.bincount(index, minlength=self.counts.size)

    def _start(self) -> None:
        if self.low > self.high:  # no valid value seen
            self.counts = np.zeros(1, dtype=np.int64)
            return
        span = self.high - self.low
        self._per_value = self.whole and span < HISTOGRAM_BINS
        if self._per_value:  # one bin per whole number
            bins, first, width = int(span) + 1, self.low - 0.5, 1.0
        else:
            bins, first, width = HISTOGRAM_BINS, self.low, max(span, 1e-30) / HISTOGRAM_BINS
        self.counts = np.zeros(max(1, bins), dtype=np.int64)
        self._edges = (first, width)

    def percentile(self, percent: float) -> float:
        """The value below which `percent` % of the valid values lie (nearest order statistic)."""
        assert self.counts is not None
        total = int(self.counts.sum())
        rank = math.floor(percent / 100.0 * (total - 1))
        index = int(np.searchsorted(np.cumsum(self.counts), rank, side="right"))
        first, width = self._edges
        if self._per_value:
            return self.low + index
        return min(self.high, max(self.low, first + (index + 0.5) * width))

    def stretch(self, low_percent: float, high_percent: float) -> Stretch | None:
        """The stretch with `low_percent` % below low and `high_percent` % above high."""
        if self.counts is None or self.low > self.high or not self.counts.any():
            return None
        low, high = self.percentile(low_percent), self.percentile(100.0 - high_percent)
        if high <= low:  # constant data: mid-grey, as percentile_stretch does
            low, high = low - 0.5, high + 0.5
        return Stretch(float(low), float(high))
