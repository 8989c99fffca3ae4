"""PDS4 content checks against the data: file size, MD5, array statistics, special constants.

Each data file is read once, in chunks (memory stays flat): its MD5 and the
statistics of every array in it come from the same pass. The computation is the
validator's own (numpy over the bytes), independent of the writer's.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from lxml import etree

from ...formats import checksum
from ...formats.nodata import ISIS_SPECIAL_LIMIT  # ISIS special pixels: float32 values at or below NULL
from ...pds4.model import NUMPY_TYPES
from .label_tree import P, Pds4Hits, data_path, file_areas, number

_READ_BYTES = 8 * 1024 * 1024  # one read of a data file
_SAMPLES_PER_STEP = 1 << 20  # samples whose statistics are taken at a time (8 MB of float64)


def check_data(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """Each data file read once: its size, its MD5, and the statistics of every array in it."""
    for area in file_areas(tree):
        path = data_path(report, area)
        if path is None:
            continue
        file = area.find(f"{P}File")
        size = path.stat().st_size
        size_element = file.find(f"{P}file_size")
        if size_element is not None and number(file, f"{P}file_size") != size:
            report.add("PDS4-011", f"file_size = {size_element.text} but {path.name} has {size} bytes",
                       size_element.sourceline, "file_size")
        arrays = [a for a in _area_arrays(area) if _fits(report, a, path, size)]
        md5_element = file.find(f"{P}md5_checksum")
        md5 = checksum.md5()
        position = 0
        for block in checksum.blocks(path, _READ_BYTES):
            md5.update(block)
            for array in arrays:
                array.feed(position, block)
            position += len(block)
        if md5_element is not None and md5_element.text and md5.hexdigest() != md5_element.text.strip().lower():
            report.add("PDS4-012", f"md5_checksum = {md5_element.text.strip()} but {path.name} has MD5 "
                                   f"{md5.hexdigest()}", md5_element.sourceline, "md5_checksum")
        for array in arrays:
            array.report(report)


class _ArrayStatistics:
    """Extremes, mean and deviation of one array's samples not flagged special, fed the
    file's bytes in order (samples split across two reads are carried over)."""

    def __init__(self, element: etree._Element, offset: int, elements: int, dtype: np.dtype) -> None:
        self.element = element
        self.start, self.end = offset, offset + elements * dtype.itemsize
        self.dtype = dtype
        constants = [v for v in _special_constants(element, dtype).values() if _storable(v, dtype)]
        # as stored: a decimal constant of a float32 array flags the float32 nearest to it
        self.flagged = np.array(constants, dtype=np.float64).astype(dtype).astype(np.float64)
        self.pending = b""
        self.count, self.total, self.squares = 0, 0.0, 0.0
        self.low, self.high = math.inf, -math.inf
        self.shift: float | None = None  # sums of (value - first value) stay accurate
        self.undeclared = 0

    def feed(self, position: int, block: bytes) -> None:
        low, high = max(self.start, position), min(self.end, position + len(block))
        if low >= high:
            return
        data = self.pending + block[low - position:high - position]
        usable = len(data) - len(data) % self.dtype.itemsize
        self.pending = data[usable:]
        stored = np.frombuffer(data[:usable], dtype=self.dtype)
        for first in range(0, stored.size, _SAMPLES_PER_STEP):  # bounds the float64 scratch
            self._add(stored[first:first + _SAMPLES_PER_STEP].astype(np.float64))

    def _add(self, values: np.ndarray) -> None:
        valid = ~np.isin(values, self.flagged) & np.isfinite(values)
        if self.dtype.kind == "f":
            special = values <= float(ISIS_SPECIAL_LIMIT)
            self.undeclared += int(np.count_nonzero(special & valid))
            valid &= ~special
        chosen = values[valid]
        if chosen.size == 0:
            return
        self.shift = float(chosen[0]) if self.shift is None else self.shift
        self.low, self.high = min(self.low, float(chosen.min())), max(self.high, float(chosen.max()))
        chosen -= self.shift
        self.count += chosen.size
        self.total += float(chosen.sum())
        self.squares += float(chosen @ chosen)

    def report(self, report: Pds4Hits) -> None:
        if self.undeclared:
            report.add("PDS4-022", f"{self.undeclared} samples hold ISIS special-pixel values (e.g. NULL "
                                   f"{float(ISIS_SPECIAL_LIMIT)!r}) but Special_Constants does not declare them",
                       self.element.sourceline, "missing_constant")
        stats = self.element.find(f"{P}Object_Statistics")
        if stats is None or self.count == 0 or self.shift is None:
            return
        mean = self.shift + self.total / self.count
        deviation = math.sqrt(max(0.0, self.squares / self.count - (self.total / self.count) ** 2))
        _compare_bound(report, stats, "minimum", self.low, -1.0, _float32_tolerance(self.low, self.dtype))
        _compare_bound(report, stats, "maximum", self.high, 1.0, _float32_tolerance(self.high, self.dtype))
        spread = max(abs(self.high - self.low), 1e-12)
        _compare(report, stats, "mean", mean, "PDS4-021", 1e-6 * spread)
        _compare(report, stats, "standard_deviation", deviation, "PDS4-021", 1e-6 * spread)


def _area_arrays(area: etree._Element) -> Iterator[_ArrayStatistics]:
    for element in area:
        if not (isinstance(element.tag, str) and element.tag.startswith(f"{P}Array")):
            continue
        data_type = element.findtext(f"{P}Element_Array/{P}data_type") or ""
        offset = number(element, f"{P}offset")
        axes = [int(number(axis, f"{P}elements") or 0) for axis in element.findall(f"{P}Axis_Array")]
        if data_type in NUMPY_TYPES and offset is not None and axes:
            yield _ArrayStatistics(element, int(offset), math.prod(axes), np.dtype(NUMPY_TYPES[data_type]))


def _fits(report: Pds4Hits, array: _ArrayStatistics, path: Path, size: int) -> bool:
    if array.end <= size:
        return True
    report.add("PDS4-013", f"the array needs bytes up to {array.end} but {path.name} has {size}",
               array.element.sourceline, array.element.tag[len(P):])
    return False


def _special_constants(element: etree._Element, dtype: np.dtype | None = None) -> dict[str, float]:
    """The array's special constants (not its valid range) as numbers. A constant written
    in hexadecimal (0xFF7FFFFB) is the bit pattern of a sample of the array's type."""
    found = {}
    special = element.find(f"{P}Special_Constants")
    for child in special if special is not None else ():
        if isinstance(child.tag, str) and not child.tag.endswith(("valid_maximum", "valid_minimum")):
            value = constant_value(child.text or "", dtype)
            if value is not None:
                found[child.tag.split("}")[1]] = value
    return found


def constant_value(text: str, dtype: np.dtype | None) -> float | None:
    """A special constant's value: a decimal number, or (PDS4 allows it for any field
    type) a hexadecimal bit pattern of the stored sample - for reals, of the IEEE 754
    number (0xFF7FFFFB is the float32 -3.4028226e38); for signed integers, two's
    complement (0xFFFF of a 2-byte signed sample is -1). NaN for a pattern wider than
    the type (no sample can hold it); None when neither."""
    text = text.strip()
    if text[:2].lower() == "0x":
        try:
            bits = int(text[2:], 16)
        except ValueError:
            return None
        if dtype is None:
            return float(bits)
        if bits >= 1 << (8 * dtype.itemsize):
            return math.nan
        raw = np.array([bits], dtype=f"{dtype.byteorder if dtype.byteorder in '<>' else '='}u{dtype.itemsize}")
        return float(raw.view(dtype)[0])
    try:
        return float(text)
    except ValueError:
        return None


def check_special_constants(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """A special constant the array's data type cannot hold can never flag a sample."""
    for element in tree.iter():
        if not (isinstance(element.tag, str) and element.tag.startswith(f"{P}Array")):
            continue
        data_type = element.findtext(f"{P}Element_Array/{P}data_type") or ""
        if data_type not in NUMPY_TYPES:
            continue
        dtype = np.dtype(NUMPY_TYPES[data_type])
        for name, value in _special_constants(element, dtype).items():
            if not _storable(value, dtype):
                constant = element.find(f"{P}Special_Constants/{P}{name}")
                written = (constant.text or "").strip() if constant is not None else repr(value)
                report.add("PDS4-023", f"{name} = {written} cannot be stored as {data_type}",
                           constant.sourceline if constant is not None else element.sourceline, name)


def _storable(value: float, dtype: np.dtype) -> bool:
    """Integers: a whole number in range; reals: finite within range (decimals round to the type)."""
    if dtype.kind == "f":
        return math.isfinite(value) and abs(value) <= float(np.finfo(dtype).max)
    info = np.iinfo(dtype)
    return float(value).is_integer() and info.min <= value <= info.max


def _float32_tolerance(value: float, dtype: np.dtype) -> float:
    if dtype.kind != "f":
        return 0.0
    return float(np.spacing(np.float32(abs(value)))) if math.isfinite(value) else 0.0


def _compare_bound(report: Pds4Hits, stats: etree._Element, name: str, actual: float, outwards: float,
                   tolerance: float) -> None:
    """A stated extreme: valid samples beyond it are an error (a reader trusting it would
    clip or misscale data); a bound that is looser than the data, as rounded statistics
    are, only a warning (NASA's validator does not compare them at all)."""
    element = stats.find(f"{P}{name}")
    stated = number(stats, f"{P}{name}")
    if element is None or stated is None or abs(stated - actual) <= tolerance:
        return
    if (actual - stated) * outwards > 0:
        report.add("PDS4-020", f"{name} = {element.text} but the valid samples reach {actual:.10g}",
                   element.sourceline, name)
    else:
        report.add("PDS4-024", f"{name} = {element.text} is looser than the valid samples' {actual:.10g}",
                   element.sourceline, name)


def _compare(report: Pds4Hits, stats: etree._Element, name: str, actual: float, rule: str, tolerance: float) -> None:
    element = stats.find(f"{P}{name}")
    stated = number(stats, f"{P}{name}")
    if element is None or stated is None:
        return
    if not abs(stated - actual) <= tolerance:
        report.add(rule, f"{name} = {element.text} but the valid samples give {actual:.10g}",
                   element.sourceline, name)
