"""The elevation colour ramp and its blend with shaded relief.

Ramp: viridis (S. van der Walt and N. Smith, 2015; the default colour map of
matplotlib since 2.0 and of R's viridisLite), a perceptually uniform sequential map:
lightness rises steadily from dark blue-violet (low) to yellow (high), it stays
readable for colour-blind viewers and in greyscale print, and unlike a rainbow it
has no bands that suggest false contours. It is rebuilt here from 17 published
control points (every 16th entry of the 256-entry table) by linear interpolation in
sRGB, which stays within a few units of the full table.

Blend: the colour is modulated by the shading relative to a flat surface, so a
flat area shows exactly the ramp colour the legend promises; slopes facing the light
are lightened towards white, slopes facing away darkened towards black.
"""

from __future__ import annotations

import math

import numpy as np

RAMP_NAME = "viridis"
_VIRIDIS_HEX = (
    "440154", "48186a", "472d7b", "424086", "3b528b", "33638d", "2c728e", "26828e",
    "21918c", "1fa088", "28ae80", "3fbc73", "5ec962", "84d44b", "addc30", "d8e219",
    "fde725",
)
CONTROL_POINTS = np.array([[int(h[i:i + 2], 16) for i in (0, 2, 4)] for h in _VIRIDIS_HEX],
                          dtype=np.float32)
_POSITIONS = np.array([min(16 * i, 255) / 255.0 for i in range(len(_VIRIDIS_HEX))],
                      dtype=np.float32)
_LUT_SIZE = 1024
_LUT = np.stack([np.interp(np.linspace(0, 1, _LUT_SIZE), _POSITIONS, CONTROL_POINTS[:, c])
                 for c in range(3)], axis=-1).astype(np.float32)

DARKEN_STRENGTH = 0.8   # how far slopes facing away go towards black
LIGHTEN_STRENGTH = 0.5  # how far slopes facing the light go towards white (less: keeps hue)


def first_colour() -> tuple[int, int, int]:
    return tuple(int(v) for v in CONTROL_POINTS[0])  # type: ignore[return-value]


def ramp_colours(values: np.ndarray, low: float, high: float) -> np.ndarray:
    """Float RGB (0..255) for `values`; `low` gets the first colour, `high` the last."""
    span = high - low if high > low else 1.0
    t = np.clip((values.astype(np.float32) - np.float32(low)) / np.float32(span), 0.0, 1.0)
    index = np.rint(t * np.float32(_LUT_SIZE - 1)).astype(np.intp)
    return _LUT[index]


def blend_with_shade(rgb: np.ndarray, shade: np.ndarray, altitude: float) -> np.ndarray:
    """Light or darken ramp colours by shading relative to flat ground (sin(altitude))."""
    flat = np.float32(math.sin(math.radians(altitude)))
    shade = shade.astype(np.float32)[..., None]
    darker = rgb * (1.0 - np.float32(DARKEN_STRENGTH) * (1.0 - shade / flat))
    lighter = rgb + (255.0 - rgb) * (np.float32(LIGHTEN_STRENGTH) * (shade - flat)
                                     / np.float32(max(1.0 - float(flat), 1e-6)))
    out = np.where(shade < flat, darker, lighter)
    return np.clip(np.rint(out), 0, 255).astype(np.uint8)
