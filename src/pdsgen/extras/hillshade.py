"""Shaded relief (hillshade) of an elevation grid, with holes that cast no shadows.

Slopes use Horn's 3 x 3 weighted differences (the same estimator as `gdaldem
hillshade`), computed with the true ground spacing of the grid in metres, so the
z-factor is 1 for elevations in metres. The light comes from `azimuth` degrees
clockwise from image up at `altitude` degrees above the horizon (defaults 315, 45:
from the upper left, the convention under which relief is not seen inverted).

No-data: a missing neighbour is replaced by the centre pixel's own height before the
differences are taken, so a hole's rim is shaded from the valid pixels alone and
never shows the huge fake cliff that the no-data value would make. Missing pixels
themselves have no shade (returned masked).
"""

from __future__ import annotations

import math

import numpy as np

# Horn's kernel: (row offset, column offset, weight)
_EAST = ((-1, 1, 1.0), (0, 1, 2.0), (1, 1, 1.0))
_WEST = ((-1, -1, 1.0), (0, -1, 2.0), (1, -1, 1.0))
_SOUTH = ((1, -1, 1.0), (1, 0, 2.0), (1, 1, 1.0))
_NORTH = ((-1, -1, 1.0), (-1, 0, 2.0), (-1, 1, 1.0))


# Automatic vertical exaggeration: a DTM shown at a much coarser scale than its posts
# (a global map at tens of km per preview pixel) has slopes of a fraction of a degree
# and would shade as a flat grey. The exaggeration is raised through 1, 2, 5, 10 ...
# until the steeper slopes (90th percentile) reach about 8 degrees; it is never below
# 1 and is printed on the annotated image and in README.TXT.
_TARGET_SLOPE = math.tan(math.radians(8.0))
_NICE_FACTORS = (1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0)


def hillshade(elevation: np.ma.MaskedArray, metres_per_column: float, metres_per_row: float,
              azimuth: float = 315.0, altitude: float = 45.0,
              exaggeration: float = 1.0) -> np.ma.MaskedArray:
    """Illumination in [0, 1] (cosine of the angle between surface normal and light)."""
    dz_east, dz_up, valid = slopes(elevation, metres_per_column, metres_per_row)
    return shade_from_slopes(dz_east * np.float32(exaggeration), dz_up * np.float32(exaggeration),
                             valid, azimuth, altitude)


def auto_exaggeration(dz_east: np.ndarray, dz_up: np.ndarray, valid: np.ndarray) -> float:
    """The smallest nice factor making the 90th-percentile slope about 8 degrees or more."""
    gradient = np.hypot(dz_east[valid], dz_up[valid])
    if gradient.size == 0:
        return 1.0
    steep = float(np.percentile(gradient, 90.0))
    if steep <= 0.0:  # flat: no exaggeration shows anything
        return 1.0
    for factor in _NICE_FACTORS:
        if steep * factor >= _TARGET_SLOPE * 0.7:
            return factor
    return _NICE_FACTORS[-1]


def slopes(elevation: np.ma.MaskedArray, metres_per_column: float,
           metres_per_row: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Horn's dz/d(east) and dz/d(up) per metre, and the validity mask."""
    z = np.ma.getdata(elevation).astype(np.float32)
    valid = ~np.ma.getmaskarray(elevation)
    centre = np.where(valid, z, np.float32(0.0))
    padded = np.pad(centre, 1, mode="edge")
    padded_valid = np.pad(valid, 1, mode="edge")

    def weighted(offsets: tuple) -> np.ndarray:
        total = np.zeros_like(centre)
        rows, cols = centre.shape
        for dr, dc, weight in offsets:
            neighbour = padded[1 + dr: 1 + dr + rows, 1 + dc: 1 + dc + cols]
            ok = padded_valid[1 + dr: 1 + dr + rows, 1 + dc: 1 + dc + cols]
            total += np.float32(weight) * np.where(ok, neighbour, centre)
        return total

    dz_east = (weighted(_EAST) - weighted(_WEST)) / np.float32(8.0 * metres_per_column)
    dz_up = (weighted(_NORTH) - weighted(_SOUTH)) / np.float32(8.0 * metres_per_row)
    return dz_east, dz_up, valid


def shade_from_slopes(dz_east: np.ndarray, dz_up: np.ndarray, valid: np.ndarray,
                      azimuth: float, altitude: float) -> np.ma.MaskedArray:
    """Lambertian illumination of the surface with these slopes."""
    az, alt = math.radians(azimuth), math.radians(altitude)
    light = (math.sin(az) * math.cos(alt), math.cos(az) * math.cos(alt), math.sin(alt))
    shade = (np.float32(light[2]) - np.float32(light[0]) * dz_east
             - np.float32(light[1]) * dz_up) / np.sqrt(1.0 + dz_east**2 + dz_up**2)
    return np.ma.MaskedArray(np.clip(shade, 0.0, 1.0).astype(np.float32), mask=~valid)
