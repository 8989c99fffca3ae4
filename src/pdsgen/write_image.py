"""Write a raster band as PDS3 image records after a label, in one streaming pass.

The label states statistics (VALID_MINIMUM/MAXIMUM) that are only known after
the data has been read, but it sits in front of the data. We reserve the label
records for the widest values the label could hold, stream the data once after
them, then write the final label; if the final label needs fewer records, the
data is moved up in place so LABEL_RECORDS stays minimal and exact.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import BinaryIO

import numpy as np
from rasterio.io import DatasetReader

from .label.render import RecordLayout, pad_label, settle_attached_label
from .label.values import shortest_float32
from .read_raster import row_strips

# ISIS special pixels (NULL, LRS, LIS, HIS, HRS) are the five most negative float32
# values; NULL (16#FF7FFFFB#) is the one PDS DTMs use as MISSING_CONSTANT.
MISSING_CONSTANT = np.frombuffer(bytes.fromhex("FF7FFFFB"), dtype=">f4")[0].astype(np.float32)
MISSING_BITS = 0xFF7FFFFB
# A value no real label statistic can be wider than when written.
_WIDEST_STATISTIC = -1.2345678901234567e-300
_COPY_CHUNK = 8 * 1024 * 1024


@dataclass(frozen=True)
class BandStatistics:
    """Valid-pixel count and extremes, written as the shortest float32 decimals."""

    valid_count: int
    minimum: float
    maximum: float


def stream_float32_band(
    dataset: DatasetReader, out: BinaryIO, big_endian: bool
) -> BandStatistics:
    """Copy band 1 as float32 records, missing pixels set to MISSING_CONSTANT.

    Missing means: the dataset's nodata value, NaN or infinity, and ISIS special
    pixels. Returns min/max of the valid pixels, computed in the same pass.
    Writing happens on a second thread (the file write releases the GIL), so
    reading and converting the next strip overlaps writing the previous one;
    at most two strips are in flight, so memory stays bounded.
    """
    nodata = dataset.nodata
    is_float_input = np.dtype(dataset.dtypes[0]).kind == "f"
    count, low, high = 0, np.inf, -np.inf
    with StripWriter(out) as writer:
        for window in row_strips(dataset):
            native = dataset.read(1, window=window)
            values = native.astype(np.float32, copy=False)
            invalid = _invalid_mask(native, values, nodata, is_float_input)
            if invalid is None:
                count += values.size
                low = min(low, float(values.min()))
                high = max(high, float(values.max()))
            else:
                np.copyto(values, MISSING_CONSTANT, where=invalid)
                valid = ~invalid
                n_valid = int(np.count_nonzero(valid))
                if n_valid:
                    count += n_valid
                    low = min(low, float(np.min(values, where=valid, initial=np.inf)))
                    high = max(high, float(np.max(values, where=valid, initial=-np.inf)))
            if big_endian:
                values.byteswap(inplace=True)
            writer.submit(np.ascontiguousarray(values))
    if count == 0:
        return BandStatistics(0, math.nan, math.nan)
    return BandStatistics(count, shortest_float32(low), shortest_float32(high))


class StripWriter:
    """Write arrays to a file in order on one background thread, two at most pending."""

    def __init__(self, out: BinaryIO, depth: int = 2) -> None:
        self._out = out
        self._depth = depth
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="pdsgen-write")
        self._pending: deque[Future] = deque()

    def submit(self, array: np.ndarray) -> None:
        while len(self._pending) >= self._depth:
            self._pending.popleft().result()
        self._pending.append(self._pool.submit(self._out.write, memoryview(array)))

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


def _invalid_mask(native, values, nodata, is_float_input):
    invalid = None
    if is_float_input:
        invalid = ~np.isfinite(values)
        invalid |= values <= MISSING_CONSTANT
    if nodata is not None and not np.isnan(nodata):
        hit = native == np.asarray(nodata).astype(native.dtype) if _representable(nodata, native.dtype) else None
        if hit is not None:
            invalid = hit if invalid is None else (invalid | hit)
    if invalid is not None and not invalid.any():
        return None
    return invalid


def _representable(value: float, dtype: np.dtype) -> bool:
    dtype = np.dtype(dtype)
    if dtype.kind == "f":
        return True
    info = np.iinfo(dtype)
    return float(value).is_integer() and info.min <= value <= info.max


def write_attached_product(
    path,
    render: Callable[[RecordLayout, BandStatistics], str],
    record_bytes: int,
    data_records: int,
    write_data: Callable[[BinaryIO], BandStatistics],
) -> tuple[RecordLayout, str, BandStatistics]:
    """Label + data in one file, the data written in one pass after reserved records."""
    widest = BandStatistics(1, _WIDEST_STATISTIC, _WIDEST_STATISTIC)
    reserved, _ = settle_attached_label(lambda r: render(r, widest), record_bytes, data_records)
    with open(path, "r+b") as handle:
        handle.seek(reserved.label_bytes)
        stats = write_data(handle)
        layout, text = settle_attached_label(lambda r: render(r, stats), record_bytes, data_records)
        if layout.label_records > reserved.label_records:
            raise RuntimeError("final label outgrew its reserved records")
        if layout.label_records < reserved.label_records:
            _move_down(handle, reserved.label_bytes, layout.label_bytes, data_records * record_bytes)
        handle.seek(0)
        handle.write(pad_label(text, layout))
        handle.truncate(layout.file_bytes)
    return layout, text, stats


def _move_down(handle: BinaryIO, source: int, target: int, length: int) -> None:
    """Move `length` bytes from `source` to an earlier offset, chunk by chunk."""
    done = 0
    while done < length:
        size = min(_COPY_CHUNK, length - done)
        handle.seek(source + done)
        chunk = handle.read(size)
        handle.seek(target + done)
        handle.write(chunk)
        done += size
