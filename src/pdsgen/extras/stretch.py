"""Linear contrast stretches from percentiles of the valid data.

The stretch limits are computed once per product from a statistics sample and then
applied unchanged to the browse and the thumbnail, so both show the same contrast.
"""

from __future__ import annotations

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
