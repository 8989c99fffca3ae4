"""Which pixels hold no data: one rule for every product pdsgen writes.

No data is the raster's nodata value, NaN or infinity, and the ISIS special
pixels (NULL, LRS, LIS, HIS, HRS: the most negative float32 values, at or below
NULL = 16#FF7FFFFB#), which ISIS cubes carry in place of nodata.
"""

from __future__ import annotations

import math

import numpy as np

ISIS_SPECIAL_LIMIT = np.float32(-3.4028226550889045e38)


def invalid_mask(values: np.ndarray, nodata: float | None) -> np.ndarray | None:
    """Pixels that hold no data: the nodata value, NaN/inf, ISIS special pixels.

    Returns None when every pixel is valid, so the common case costs no mask.
    """
    sample = nodata_sample(nodata, values.dtype)
    if values.dtype.kind != "f" and sample is None:
        return None
    valid = valid_samples(values, sample, np.empty(values.shape, bool), np.empty(values.shape, bool))
    if valid.all():
        return None
    return np.logical_not(valid, out=valid)


def nodata_sample(nodata: float | None, dtype: np.dtype) -> np.generic | None:
    """The nodata value as a sample of `dtype`, or None when no sample can be equal to it:
    no nodata, a NaN nodata (NaN is missing anyway), an integer type that cannot hold it."""
    if nodata is None or math.isnan(nodata) or not _representable(nodata, dtype):
        return None
    with np.errstate(over="ignore"):  # a float nodata beyond float32 becomes infinite: missing anyway
        return np.dtype(dtype).type(nodata)


def valid_samples(values: np.ndarray, sample: np.generic | None, out: np.ndarray, scratch: np.ndarray, *,
                  keep_positive_infinity: bool = False) -> np.ndarray:
    """Set `out` True where a pixel holds data (the complement of invalid_mask) and return it.

    `sample` is nodata_sample's result; `out` and `scratch` are boolean arrays of the
    shape of `values`, owned by the caller, so a raster streamed in pieces allocates
    nothing per piece. For floats, v > ISIS_SPECIAL_LIMIT is false for NaN, -inf and
    the special pixels, and v < inf false for NaN and +inf: two comparisons cover them all.
    keep_positive_infinity leaves +inf marked valid, one comparison fewer, for a caller
    that finds +inf itself (img's float32 path sees it as the maximum) and removes it.
    """
    if values.dtype.kind == "f":
        np.greater(values, ISIS_SPECIAL_LIMIT, out=out)
        if not keep_positive_infinity:
            np.less(values, np.inf, out=scratch)
            np.logical_and(out, scratch, out=out)
    else:
        out.fill(True)
    if sample is not None:
        np.not_equal(values, sample, out=scratch)
        np.logical_and(out, scratch, out=out)
    return out


def _representable(value: float, dtype: np.dtype) -> bool:
    if dtype.kind == "f":
        return True
    info = np.iinfo(dtype)
    return float(value).is_integer() and info.min <= value <= info.max
