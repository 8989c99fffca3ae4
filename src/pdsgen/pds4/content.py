"""What a PDS4 label states about its data file, computed while the file is written.

A `ContentTap` sits between the streaming writer and the file: every byte written
goes into the MD5 digest and the byte count, and the samples (decoded with the
array's data type) into the Object_Statistics of the valid ones. One pass, flat
memory, nothing read back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import BinaryIO

import numpy as np

from ..formats import checksum
from ..label.values import shortest_float32

_SAMPLES_PER_STEP = 1 << 20  # statistics of at most this many samples at a time (8 MB of float64)


@dataclass(frozen=True)
class ArrayStatistics:
    """Object_Statistics of the valid samples (the missing constant excluded)."""

    count: int
    minimum: float
    maximum: float
    mean: float
    standard_deviation: float


@dataclass(frozen=True)
class FileContent:
    size: int
    md5: str


class ContentTap:
    """A write-only file wrapper: digests bytes and accumulates sample statistics
    (with no file, it only measures: for data written before its PDS4 label).

    Statistics use Chan et al.'s pairwise update of (count, mean, M2), which stays
    accurate over billions of samples where a running sum of squares would not.
    """

    def __init__(self, out: BinaryIO | None, dtype: str | None = None, special: tuple[float, ...] = (),
                 start: int = 0) -> None:
        self._out = out
        self._md5 = checksum.md5()
        self._size = 0
        self._dtype = np.dtype(dtype) if dtype else None
        # Special constants (missing, saturation) as stored samples: excluded from the statistics.
        self._special = np.asarray(special, dtype=self._dtype) if self._dtype is not None else None
        self._start = start  # bytes written before the array (not samples)
        self.count = 0
        self._mean = 0.0
        self._m2 = 0.0
        self._low = math.inf
        self._high = -math.inf

    def write(self, data) -> int:  # noqa: ANN001 - bytes or memoryview, like a file
        view = memoryview(data).cast("B")
        self._md5.update(view)
        if self._dtype is not None:
            self._add_samples(view)
        self._size += len(view)
        return self._out.write(view) if self._out is not None else len(view)

    def _add_samples(self, view: memoryview) -> None:
        skip = max(0, self._start - self._size)
        if skip >= len(view):
            return
        stored = np.frombuffer(view[skip:], dtype=self._dtype)
        for first in range(0, stored.size, _SAMPLES_PER_STEP):  # bounds the float64 scratch
            self._add_part(stored[first:first + _SAMPLES_PER_STEP])

    def _add_part(self, stored: np.ndarray) -> None:
        if self._special is not None and self._special.size:
            special = np.isin(stored, self._special)
            if special.any():
                stored = stored[~special]
        n = stored.size
        if n == 0:
            return
        samples = stored.astype(np.float64)
        mean = float(samples.mean())
        samples -= mean
        m2 = float(samples @ samples)
        total = self.count + n
        delta = mean - self._mean
        self._mean += delta * n / total
        self._m2 += m2 + delta * delta * self.count * n / total
        self.count = total
        self._low = min(self._low, float(stored.min()))
        self._high = max(self._high, float(stored.max()))

    def statistics(self) -> ArrayStatistics:
        if self.count == 0:
            return ArrayStatistics(0, math.nan, math.nan, math.nan, math.nan)
        return ArrayStatistics(
            self.count,
            shortest_float32(self._low),
            shortest_float32(self._high),
            self._mean,
            math.sqrt(self._m2 / self.count),
        )

    def content(self) -> FileContent:
        return FileContent(self._size, self._md5.hexdigest())


def digest_file(path) -> FileContent:  # noqa: ANN001
    """Size and MD5 of a finished file, read in blocks (for data written before its label)."""
    return FileContent(*checksum.size_and_md5(path))
