"""Write a raster band as PDS3 image records after a label, streaming by strips.

The label states statistics (VALID_MINIMUM/MAXIMUM) that are only known after
the data has been read, but it sits in front of the data. We reserve the label
records for the widest values the label could hold, stream the data once after
them, then write the final label; if the final label needs fewer records, the
data is moved up in place so LABEL_RECORDS stays minimal and exact.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from dataclasses import dataclass
from typing import BinaryIO, Literal

import numpy as np
from rasterio.io import DatasetReader
from rasterio.windows import Window

from ..errors import PdsgenError
from ..label.grammar import ISIS_NULL_BITS
from ..label.render import RecordLayout, pad_label, settle_attached_label
from ..label.values import shortest_float32
from ..progress import advance, is_large
from ..storage.staging import InterruptSafeExecutor
from .nodata import invalid_mask, nodata_sample, valid_samples
from .raster import row_strips

# ISIS special pixels (NULL, LRS, LIS, HIS, HRS) are the five most negative float32
# values; NULL (16#FF7FFFFB#) is the one PDS DTMs use as MISSING_CONSTANT.
MISSING_CONSTANT = np.frombuffer(bytes.fromhex("FF7FFFFB"), dtype=">f4")[0].astype(np.float32)
MISSING_BITS = ISIS_NULL_BITS
# A value no real label statistic can be wider than when written (shortest round-trip
# form); writers that round statistics (Fixed) keep it as it is (see products/dtm.valid_bound).
RESERVATION_STATISTIC = -1.2345678901234567e-300
_COPY_CHUNK = 8 * 1024 * 1024
# Bytes handed to one write() call. Measured on Linux/ext4: 244 MB written in 16 MB
# calls took 0.17-0.65 s of system time, in 1 MB calls 0.06-0.07 s (a whole multiple
# of every sample size, so a writer that parses samples never gets a partial one).
WRITE_CHUNK = 1024 * 1024
# Samples examined together by the float32 fast path: the chunk and its two masks
# stay in the core's cache across the comparisons, reductions and the encoding.
CHUNK_SAMPLES = 128 * 1024
# Strip buffers the float32 fast path reads into, in turn: one being read, one being
# worked on, the rest waiting to be written (StripWriter keeps two pending).
READ_SLOTS = 3


@dataclass(frozen=True)
class BandStatistics:
    """Valid-pixel count and extremes, written as the shortest float32 decimals."""

    valid_count: int
    minimum: float
    maximum: float


# Physical values of one strip, with the strip's window, before encoding.
Adjust = Callable[[np.ndarray, Window], np.ndarray]
# Encode valid physical values (float32) into stored samples; invalid pixels get the
# product's missing value. Returns the array to write (native byte order).
Encode = Callable[[np.ndarray, "np.ndarray | None"], np.ndarray]


def physical_strips(
    dataset: DatasetReader, adjust: Adjust | None = None
) -> Iterator[tuple[np.ndarray, np.ndarray | None, Window]]:
    """Band 1 as float32 strips with the mask of missing pixels (None: none missing).

    Missing means: the dataset's nodata value, NaN or infinity, and ISIS special
    pixels. `adjust` may change the physical values (e.g. add an areoid), and
    pixels it turns into NaN become missing too.
    """
    for native, window in native_strips(dataset):
        values, invalid = physical_values(dataset, native)
        if adjust is not None:
            values = adjust(values, window).astype(np.float32, copy=False)
            lost = ~np.isfinite(values)
            if lost.any():
                invalid = lost if invalid is None else (invalid | lost)
        yield values, invalid, window


def native_strips(dataset: DatasetReader, reuse: bool = False) -> Iterator[tuple[np.ndarray, Window]]:
    """Band 1 as stored, in the strips physical_strips reads (progress reported as they pass):
    a writer converting a strip a part at a time (physical_values) reads what it does.

    `reuse`: every strip is read into the first one's array, for a consumer done with a strip
    before it asks for the next; the allocator then never sees a strip freed and another
    asked for (glibc kept such memory: a higher peak than the strips themselves)."""
    large = is_large(dataset.width * dataset.height)
    buffer: np.ndarray | None = None
    for window in row_strips(dataset):
        if reuse:
            if buffer is None:
                buffer = np.empty((window.height, window.width), dataset.dtypes[0])
            yield dataset.read(1, window=window, out=buffer[:window.height]), window
        else:
            yield dataset.read(1, window=window), window
        if large:
            advance(window.row_off + window.height, dataset.height, "lines")


def physical_values(dataset: DatasetReader, native: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """Samples of `dataset` as read (a strip or any part of one) as float32 values with the mask of
    missing ones: physical_strips' conversion, pixel by pixel, so a part converts as the whole."""
    native_type = np.dtype(dataset.dtypes[0])
    with np.errstate(over="ignore"):
        values = native.astype(np.float32, copy=False)
    invalid = invalid_mask(native, dataset.nodata)
    if native_type.kind == "f" and native_type.itemsize > 4:
        _refuse_float32_overflow(dataset, native, values, invalid)
    return values, invalid


def _refuse_float32_overflow(dataset, native: np.ndarray, values: np.ndarray, invalid) -> None:
    """float64 input beyond float32's range would silently become infinite: refuse it."""
    overflow = ~np.isfinite(values) & np.isfinite(native)
    if invalid is not None:
        overflow &= ~invalid
    if overflow.any():
        example = native[overflow].flat[0]
        raise PdsgenError(dataset.name, f"holds values beyond the 32-bit float range (e.g. {example:g}); "
                                        "they cannot be stored in the product")


def valid_extremes(values: np.ndarray, invalid: np.ndarray | None) -> tuple[int, float, float]:
    """Count, minimum and maximum of the valid pixels of one strip."""
    if invalid is None:
        return values.size, float(values.min()), float(values.max())
    valid = ~invalid
    count = int(np.count_nonzero(valid))
    if count == 0:
        return 0, math.inf, -math.inf
    if values.dtype.kind == "f":
        low_start, high_start = np.inf, -np.inf
    else:
        low_start, high_start = np.iinfo(values.dtype).max, np.iinfo(values.dtype).min
    low = float(np.min(values, where=valid, initial=low_start))
    high = float(np.max(values, where=valid, initial=high_start))
    return count, low, high


def scan_band(dataset: DatasetReader, adjust: Adjust | None = None) -> BandStatistics:
    """Statistics of the physical values, read-only (for encodings that need the range first)."""
    count, low, high = 0, math.inf, -math.inf
    for values, invalid, _ in physical_strips(dataset, adjust):
        n, lo, hi = valid_extremes(values, invalid)
        count, low, high = count + n, min(low, lo), max(high, hi)
    return _statistics(count, low, high)


def band_statistics(count: int, low: float, high: float) -> BandStatistics:
    """`count` valid values between `low` and `high` stated as scan_band states them, for a writer
    that gathers them while it writes instead of in a pass of their own."""
    return _statistics(count, low, high)


def encode_float32(values: np.ndarray, invalid: np.ndarray | None) -> np.ndarray:
    """PC_REAL/IEEE_REAL DTM samples: the values, missing set to MISSING_CONSTANT."""
    if invalid is not None:
        np.copyto(values, MISSING_CONSTANT, where=invalid)
    return values


def stream_band(
    dataset: DatasetReader,
    out: BinaryIO,
    big_endian: bool,
    encode: Encode = encode_float32,
    adjust: Adjust | None = None,
) -> BandStatistics:
    """Encode band 1 strip by strip and write it; statistics of the stored valid samples.

    Writing happens on a second thread (the file write releases the GIL), so
    reading and converting the next strip overlaps writing the previous one;
    at most two strips are in flight, so memory stays bounded. float32 input in
    the standard encoding takes a faster path of its own (_stream_float32_input:
    three strip buffers, the same bytes and statistics).
    """
    if encode is encode_float32 and adjust is None and np.dtype(dataset.dtypes[0]) == np.float32:
        return _stream_float32_input(dataset, out, big_endian)
    count, low, high = 0, math.inf, -math.inf
    with StripWriter(out) as writer:
        for values, invalid, _ in physical_strips(dataset, adjust):
            stored = encode(values, invalid)
            n, lo, hi = valid_extremes(stored, invalid)
            count, low, high = count + n, min(low, lo), max(high, hi)
            order: Literal[">", "<"] = ">" if big_endian else "<"
            writer.submit(np.ascontiguousarray(stored.astype(stored.dtype.newbyteorder(order), copy=False)))
    return _statistics(count, low, high)


def _stream_float32_input(dataset: DatasetReader, out: BinaryIO, big_endian: bool) -> BandStatistics:
    """stream_band for float32 input stored as float32 (the DTM case), in fewer passes.

    The general path makes a strip-sized mask in several passes, then reduces with
    where= (slow) and copies for the byte order. Here each strip is read into a
    reused buffer on a reading thread, then examined CHUNK_SAMPLES at a time while
    the chunk is in cache: mask, count, extremes, missing pixels and byte order
    set in place. Same stored bytes and statistics as the general path.
    """
    sample = nodata_sample(dataset.nodata, np.dtype(np.float32))
    chunk = min(CHUNK_SAMPLES, dataset.width * dataset.height)
    valid, scratch = np.empty(chunk, bool), np.empty(chunk, bool)
    swapped = np.empty(chunk, ">f4") if big_endian else None
    count, low, high = 0, math.inf, -math.inf
    large = is_large(dataset.width * dataset.height)
    with StripWriter(out) as writer, StripReader(dataset) as reader:
        for values, window in reader.strips():
            flat = values.reshape(-1)
            for start in range(0, flat.size, chunk):
                part = flat[start:start + chunk]
                n, lo, hi = _encode_float32_chunk(part, sample, valid[:part.size], scratch[:part.size])
                count, low, high = count + n, min(low, lo), max(high, hi)
                if swapped is not None:
                    _to_big_endian(part, swapped[:part.size])
            reader.written(writer.submit(values))
            if large:
                advance(window.row_off + window.height, dataset.height, "lines")
    return _statistics(count, low, high)


def _encode_float32_chunk(part: np.ndarray, sample: np.generic | None, valid: np.ndarray,
                          invalid: np.ndarray) -> tuple[int, float, float]:
    """Count and extremes of the valid samples of `part`; missing ones set to MISSING_CONSTANT.

    The extremes need no where=: missing pixels are set to +inf for the minimum, then
    to MISSING_CONSTANT, which is below every valid value, for the maximum. +inf is
    left out of the mask (one comparison fewer a sample); a maximum of +inf shows it
    was there, and only then is it looked for and made missing.
    """
    valid_samples(part, sample, valid, invalid, keep_positive_infinity=True)
    n = int(np.count_nonzero(valid))
    if n == 0:
        part.fill(MISSING_CONSTANT)
        return 0, math.inf, -math.inf
    if n < part.size:
        np.logical_not(valid, out=invalid)
        np.copyto(part, np.float32(np.inf), where=invalid)
        low = float(part.min())
        np.copyto(part, MISSING_CONSTANT, where=invalid)
    else:
        low = float(part.min())
    high = float(part.max())
    if high == math.inf:
        np.equal(part, np.float32(np.inf), out=invalid)
        n -= int(np.count_nonzero(invalid))
        np.copyto(part, MISSING_CONSTANT, where=invalid)
        if n == 0:
            return 0, math.inf, -math.inf
        high = float(part.max())
    return n, low, high


def _to_big_endian(part: np.ndarray, swapped: np.ndarray) -> None:
    """Reorder the bytes of `part` in place through `swapped` (a ">f4" scratch): numpy's
    casting copy and a plain copy back take about half the time of ndarray.byteswap."""
    np.copyto(swapped, part)
    np.copyto(part.view(np.uint32), swapped.view(np.uint32))


def stream_float32_band(dataset: DatasetReader, out: BinaryIO, big_endian: bool) -> BandStatistics:
    """The float32 DTM case of `stream_band`."""
    return stream_band(dataset, out, big_endian, encode_float32)


def _statistics(count: int, low: float, high: float) -> BandStatistics:
    if count == 0:
        return BandStatistics(0, math.nan, math.nan)
    return BandStatistics(count, shortest_float32(low), shortest_float32(high))


class StripWriter:
    """Write arrays to a file in order on one background thread, two at most pending."""

    def __init__(self, out: BinaryIO, depth: int = 2) -> None:
        self._out = out
        self._depth = depth
        self._pool = InterruptSafeExecutor(max_workers=1, thread_name_prefix="pdsgen-write")
        self._pending: deque[Future] = deque()

    def submit(self, array: np.ndarray) -> Future:
        """Queue `array` (its bytes as they are); the Future is done once it is written."""
        while len(self._pending) >= self._depth:
            self._pending.popleft().result()
        future = self._pool.submit(self._write, array)
        self._pending.append(future)
        return future

    def _write(self, array: np.ndarray) -> None:
        """One strip in WRITE_CHUNK pieces (see WRITE_CHUNK: large write() calls cost more)."""
        raw = array.reshape(-1).view(np.uint8)
        for start in range(0, raw.size, WRITE_CHUNK):
            self._out.write(raw[start:start + WRITE_CHUNK].data)

    def __enter__(self) -> StripWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            while self._pending:
                future = self._pending.popleft()
                if exc_type is None:
                    future.result()
                else:
                    future.cancel()
        finally:
            self._pool.shutdown(wait=True)


class StripReader:
    """Read band 1 of a float32 raster strip by strip on a background thread, one strip ahead.

    GDAL releases the GIL while it reads, so reading strip k+1 overlaps the work on
    strip k. Strips go into a ring of reused buffers (no fresh page-faulted memory per
    strip); a buffer is read into again only after the writer has written it out.
    """

    def __init__(self, dataset: DatasetReader, slots: int | None = None) -> None:
        slots = max(2, slots or READ_SLOTS)  # the strip worked on, and the one read ahead
        self._dataset = dataset
        self._windows = list(row_strips(dataset))
        rows = max(window.height for window in self._windows)
        self._buffers = [np.empty((rows, dataset.width), np.float32) for _ in range(min(slots, len(self._windows)))]
        self._writes: list[Future | None] = [None] * len(self._buffers)
        self._pool = InterruptSafeExecutor(max_workers=1, thread_name_prefix="pdsgen-read")
        self._current = 0

    def _read(self, index: int) -> np.ndarray:
        slot = index % len(self._buffers)
        done = self._writes[slot]
        if done is not None:
            done.result()
        window = self._windows[index]
        buffer = self._buffers[slot][:window.height]
        self._dataset.read(1, window=window, out=buffer)
        return buffer

    def strips(self) -> Iterator[tuple[np.ndarray, Window]]:
        """Each strip's samples (a reused buffer) and window, in order."""
        ahead = self._pool.submit(self._read, 0)
        for index, window in enumerate(self._windows):
            values = ahead.result()
            if index + 1 < len(self._windows):
                ahead = self._pool.submit(self._read, index + 1)
            self._current = index
            yield values, window

    def written(self, future: Future) -> None:
        """The current strip's buffer is free again once `future` (its write) is done."""
        self._writes[self._current % len(self._buffers)] = future

    def __enter__(self) -> StripReader:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)


def write_attached_product(
    path,
    render: Callable[[RecordLayout, BandStatistics], str],
    record_bytes: int,
    data_records: int,
    write_data: Callable[[BinaryIO], BandStatistics],
) -> tuple[RecordLayout, str, BandStatistics]:
    """Label + data in one file, the data written in one pass after reserved records."""
    widest = BandStatistics(1, RESERVATION_STATISTIC, RESERVATION_STATISTIC)
    reserved, _ = settle_attached_label(lambda r: render(r, widest), record_bytes, data_records)
    with open(path, "r+b") as handle:
        handle.seek(reserved.label_bytes)
        stats = write_data(handle)
        layout, text = settle_attached_label(lambda r: render(r, stats), record_bytes, data_records)
        if layout.label_records != reserved.label_records:  # shorter, or (rarely) wider than reserved
            _move_data(handle, reserved.label_bytes, layout.label_bytes, data_records * record_bytes)
        handle.seek(0)
        handle.write(pad_label(text, layout))
        handle.truncate(layout.file_bytes)
    return layout, text, stats


def _move_data(handle: BinaryIO, source: int, target: int, length: int) -> None:
    """Move `length` bytes from `source` to `target` in place, chunk by chunk: from the
    front when moving to an earlier offset, from the end when moving to a later one, so no
    chunk overwrites bytes not yet moved."""
    done = 0
    while done < length:
        size = min(_COPY_CHUNK, length - done)
        start = done if target < source else length - done - size
        handle.seek(source + start)
        chunk = handle.read(size)
        handle.seek(target + start)
        handle.write(chunk)
        done += size
