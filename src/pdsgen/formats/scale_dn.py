"""Map orthoimage values to the DNs of a PDS3 image, keeping the special DNs free.

An orthoimage product stores unsigned DNs of 8, 10 or 16 bits. The lowest and
highest DNs are reserved (section 5 of the product notes): null, low and high
saturation. Physical values come back as ``DN * SCALING_FACTOR + OFFSET``.

Two cases:
- integer input whose valid values already lie in 0 .. 2**bits - 1 is kept as
  it is (SCALING_FACTOR 1, OFFSET 0); only nodata pixels become CORE_NULL;
- anything else (floats such as I/F, or integers that do not fit) is mapped
  linearly from a range [low, high] onto the valid DNs, so that every value in
  the range comes back within half a DN step. The range is the data's own
  minimum and maximum (one streamed pass) or the caller's; values outside a
  caller's range become the representation-saturation DNs.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from rasterio.io import DatasetReader
from rasterio.windows import Window

from ..errors import PdsgenError
from .nodata import invalid_mask
from .raster import row_strips

BIT_DEPTHS = (8, 10, 16)


@dataclass(frozen=True)
class SpecialDns:
    """The reserved DNs of one bit depth and the range left for valid data.

    8-bit (HiRISE convention): 0 null, 1..254 valid, 255 saturated; there is no
    free DN below the valid range, so low saturation shares DN 1 with the lowest
    valid value. 10-bit (HiRISE): 0 null, 1 low representation, 2 low
    instrument saturation, 3..1021 valid, 1022 high instrument, 1023 high
    representation saturation. 16-bit: the same pattern as 10-bit at the ends
    of 0..65535 (0, 1, 2 | 3..65533 | 65534, 65535).
    """

    bits: int
    null: int
    low_repr: int
    low_instr: int
    high_instr: int
    high_repr: int
    valid_min: int
    valid_max: int

    @property
    def dtype(self) -> np.dtype:
        return np.dtype(np.uint8) if self.bits <= 8 else np.dtype(np.uint16)

    @property
    def max_dn(self) -> int:
        return (1 << self.bits) - 1


SPECIAL_DNS = {
    8: SpecialDns(8, null=0, low_repr=1, low_instr=1, high_instr=255, high_repr=255, valid_min=1, valid_max=254),
    10: SpecialDns(10, null=0, low_repr=1, low_instr=2, high_instr=1022, high_repr=1023, valid_min=3, valid_max=1021),
    16: SpecialDns(
        16, null=0, low_repr=1, low_instr=2, high_instr=65534, high_repr=65535, valid_min=3, valid_max=65533
    ),
}


@dataclass(frozen=True)
class DnMapping:
    """How input values become DNs; `scaling_factor`/`offset` go into the label."""

    special: SpecialDns
    scaling_factor: float
    offset: float
    low: float | None = None  # None: integer DNs kept as they are
    high: float | None = None

    @property
    def keeps_values(self) -> bool:
        return self.low is None


def default_bits(dtype: np.dtype) -> int:
    """8 bits for byte input, 16 for anything wider (floats included)."""
    dtype = np.dtype(dtype)
    return 8 if dtype.kind in "iu" and dtype.itemsize == 1 else 16


def dtype_fits(dtype: np.dtype, bits: int) -> bool:
    """Whether every value of an integer type is a DN of `bits` bits."""
    dtype = np.dtype(dtype)
    if dtype.kind != "u":
        return False
    return np.iinfo(dtype).max <= (1 << bits) - 1


def valid_range(dataset: DatasetReader, windows: Iterable[Window]) -> tuple[float, float] | None:
    """Minimum and maximum of the valid pixels of all bands, in one streamed pass."""
    low, high = math.inf, -math.inf
    for window in windows:
        data = dataset.read(window=window)
        for band, nodata in zip(data, dataset.nodatavals, strict=True):
            invalid = invalid_mask(band, nodata)
            if invalid is None:
                low, high = min(low, float(band.min())), max(high, float(band.max()))
            elif not invalid.all():
                valid = band[~invalid]
                low, high = min(low, float(valid.min())), max(high, float(valid.max()))
    if low > high:
        return None
    return low, high


def linear_mapping(special: SpecialDns, low: float, high: float) -> DnMapping:
    """DN = valid_min + round((value - low) / SCALING_FACTOR), inverse exact to half a step."""
    if not (math.isfinite(low) and math.isfinite(high)) or high < low:
        raise PdsgenError(None, f"value range {low:g} .. {high:g} is not a finite, increasing range")
    steps = special.valid_max - special.valid_min
    scaling_factor = (high - low) / steps if high > low else 1.0
    offset = low - special.valid_min * scaling_factor
    return DnMapping(special, scaling_factor, offset, low, high)


def identity_mapping(special: SpecialDns) -> DnMapping:
    return DnMapping(special, 1.0, 0.0)


def to_dns(values: np.ndarray, nodata: float | None, mapping: DnMapping, source: str) -> np.ndarray:
    """Convert one block of one band to DNs of `mapping.special.dtype`."""
    special = mapping.special
    invalid = invalid_mask(values, nodata)
    if mapping.keeps_values:
        dns = _kept_dns(values, invalid, special, source)
    else:
        dns = _scaled_dns(values, mapping)
    if invalid is not None:
        dns[invalid] = special.null
    return dns


def _kept_dns(values: np.ndarray, invalid: np.ndarray | None, special: SpecialDns, source: str) -> np.ndarray:
    if not dtype_fits(values.dtype, special.bits):
        valid = values if invalid is None else values[~invalid]
        if valid.size and (valid.min() < 0 or valid.max() > special.max_dn):
            raise PdsgenError(
                source,
                f"values {valid.min()} .. {valid.max()} do not fit {special.bits}-bit DNs "
                "(data changed while it was read?)",
            )
    return values.astype(special.dtype, copy=True)


def _scaled_dns(values: np.ndarray, mapping: DnMapping) -> np.ndarray:
    special = mapping.special
    assert mapping.low is not None, "a scaling mapping has the low end of its range"
    with np.errstate(invalid="ignore", over="ignore"):
        scaled = (values.astype(np.float64) - mapping.low) / mapping.scaling_factor
        np.rint(scaled, out=scaled)
        scaled += special.valid_min
        below = scaled < special.valid_min
        above = scaled > special.valid_max
        np.clip(scaled, special.valid_min, special.valid_max, out=scaled)
        scaled[~np.isfinite(scaled)] = special.null
        dns = scaled.astype(special.dtype)
    dns[below] = special.low_repr
    dns[above] = special.high_repr
    return dns


def null_zero_byte_mapping(
    dataset: DatasetReader, value_range: tuple[float, float] | None, source: str
) -> DnMapping:
    """8-bit DNs for images whose DN 0 means no data (HRSC ND4, iMars ORI).

    Byte input keeps its DNs; anything else is mapped linearly from `value_range`
    or, failing that, from the valid range found in one streamed pass.
    """
    special = SPECIAL_DNS[8]
    if value_range is not None:
        return linear_mapping(special, *value_range)
    if np.dtype(dataset.dtypes[0]) == np.uint8:
        return identity_mapping(special)
    found = valid_range(dataset, row_strips(dataset))
    if found is None:
        raise PdsgenError(source, "has no valid pixels (all nodata)")
    return linear_mapping(special, *found)


def dn_encoder(mapping: DnMapping, source: str):
    """An encoder for write_image.stream_band: DNs, with no-data pixels set to CORE_NULL."""

    def encode(values: np.ndarray, invalid: np.ndarray | None) -> np.ndarray:
        dns = to_dns(values, None, mapping, source)
        if invalid is not None:
            dns[invalid] = mapping.special.null
        return dns

    return encode
