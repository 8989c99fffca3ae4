"""A product's true outline on its body: the edges of its grid, as the label places it.

The label's map projection object gives the CRS and the grid (the Extras' label
georeferencing, extras/label_georef.py, the one label -> CRS reading for PDS3 labels);
the four pixel edges of the grid are densified and inverse projected to longitude and
latitude with PROJ. The outline is what the grid covers, whatever the data inside
hold, so its extremes are the label's MINIMUM/MAXIMUM_LATITUDE and WESTERN/EASTERNMOST
_LONGITUDE when those are right.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from ..extras.label_georef import LabelGeorefError, label_georeferencing
from ..geo.geometry import ellipsoid_axes
from .labels import LabelView

# points per edge before simplification: enough for a sinusoidal or polar edge to curve
EDGE_POINTS = 33


@dataclass(frozen=True)
class Outline:
    """The outline as longitudes (east, degrees, -180..180 as PROJ gives them) and
    planetocentric latitudes (a sphere: PROJ's latitudes), one closed ring without the
    repeated first point; `polar`: the product is in a polar projection."""

    lons: np.ndarray
    lats: np.ndarray
    polar: bool
    north: bool


def product_outline(label: LabelView, lines: int | None, samples: int | None) -> tuple[Outline | None, str]:
    """The product's outline, or None and why it cannot be drawn."""
    if not lines or not samples:
        return None, "the label gives no LINES and LINE_SAMPLES"
    try:
        georef = label_georeferencing(label)
    except LabelGeorefError as exc:
        return None, str(exc)
    if georef is None:
        return None, "the label has no map projection"
    crs, transform = georef
    cols = np.linspace(0.0, samples, EDGE_POINTS)
    rows = np.linspace(0.0, lines, EDGE_POINTS)
    n = EDGE_POINTS - 1  # each corner once: the ring goes top, right, bottom, left
    col = np.concatenate([cols[:-1], np.full(n, float(samples)), cols[::-1][:-1], np.zeros(n)])
    row = np.concatenate([np.zeros(n), rows[:-1], np.full(n, float(lines)), rows[::-1][:-1]])
    xs = transform.c + col * transform.a
    ys = transform.f + row * transform.e
    a, b = ellipsoid_axes(crs)
    lonlat = CRS.from_proj4(f"+proj=longlat +a={a!r} +b={b!r} +no_defs +type=crs")
    lons, lats = (np.asarray(v, dtype=float) for v in warp_transform(crs, lonlat, xs, ys))
    if not (np.all(np.isfinite(lons)) and np.all(np.isfinite(lats))):
        return None, "the grid's edges do not all fall on the body"
    params = crs.to_dict()
    polar = params.get("proj") == "stere"
    north = float(params.get("lat_0", 0.0)) > 0 if polar else bool(np.mean(lats) >= 0)
    return Outline(lons, lats, polar, north), ""
