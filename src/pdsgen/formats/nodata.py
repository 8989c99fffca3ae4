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
    invalid = None
    if values.dtype.kind == "f":
        invalid = ~np.isfinite(values)
        invalid |= values <= ISIS_SPECIAL_LIMIT
    if nodata is not None and not math.isnan(nodata) and _representable(nodata, values.dtype):
        hit = values == np.asarray(nodata).astype(values.dtype)
        invalid = hit if invalid is None else (invalid | hit)
    if invalid is not None and not invalid.any():
        return None
    return invalid


def _representable(value: float, dtype: np.dtype) -> bool:
    if dtype.kind == "f":
        return True
    info = np.iinfo(dtype)
    return float(value).is_integer() and info.min <= value <= info.max


