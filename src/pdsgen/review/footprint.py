"""A product's true outline on its body: the edges of its grid, as the label places it.

The label's map projection object gives the CRS and the grid (the Extras' label
georeferencing, geo/label_georef.py, the one label -> CRS reading for PDS3 labels);
the four pixel edges of the grid are densified and inverse projected to longitude and
latitude with PROJ. The outline is what the grid covers, whatever the data inside
hold, so its extremes are the label's MINIMUM/MAXIMUM_LATITUDE and WESTERN/EASTERNMOST
_LONGITUDE when those are right.

Outlines are asked for product by product and projected together, one PROJ call per
CRS: a delivery of 10,000 products in one projection costs one transformation.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from ..geo.geometry import ellipsoid_axes, geographic_crs
from ..geo.label_georef import LabelGeorefError, label_georeferencing

# points per edge before simplification: enough for a sinusoidal or polar edge to curve
EDGE_POINTS = 33


@dataclass(frozen=True)
class Outline:
    """The outline as longitudes (east, degrees, -180..180 as PROJ gives them) and
    latitudes (the label's CRSs are spheres: planetocentric), one closed ring of the grid's
    four edges (EDGE_POINTS - 1 steps each, from the upper-left corner, clockwise) without
    the repeated first point; `polar`: the product is in a polar projection."""

    lons: np.ndarray
    lats: np.ndarray
    polar: bool
    north: bool


def _edge_ring(lines: int, samples: int) -> tuple[np.ndarray, np.ndarray]:
    """(column, row) of the grid's outer pixel edges: top, right, bottom, left. The sizes are
    taken as floats: a label's LINES may be any integer, past what numpy's integers hold."""
    cols = np.linspace(0.0, float(samples), EDGE_POINTS)
    rows = np.linspace(0.0, float(lines), EDGE_POINTS)
    n = EDGE_POINTS - 1  # each corner once
    col = np.concatenate([cols[:-1], np.full(n, float(samples)), cols[::-1][:-1], np.zeros(n)])
    row = np.concatenate([np.zeros(n), rows[:-1], np.full(n, float(lines)), rows[::-1][:-1]])
    return col, row


class OutlineBatch:
    """Outlines of many products, projected together by CRS when `run` is called."""

    def __init__(self) -> None:
        self._groups: dict[str, list[tuple[CRS, np.ndarray, np.ndarray, Callable[[Outline | None, str], None]]]] = {}

    def add(self, label: Mapping[str, Any], lines: int | None, samples: int | None,
            done: Callable[[Outline | None, str], None]) -> None:
        """Queue a product's outline; `done(outline, why_not)` is called by `run` (or now, when
        the label places no grid)."""
        if not lines or not samples:
            return done(None, "the label gives no LINES and LINE_SAMPLES")
        try:
            georef = label_georeferencing(label)
        except LabelGeorefError as exc:
            return done(None, str(exc))
        if georef is None:
            return done(None, "the label has no map projection")
        crs, transform = georef
        col, row = _edge_ring(lines, samples)
        xs = transform.c + col * transform.a
        ys = transform.f + row * transform.e
        self._groups.setdefault(crs.to_proj4(), []).append((crs, xs, ys, done))
        return None

    def run(self) -> None:
        for members in self._groups.values():
            crs = members[0][0]
            lonlat = geographic_crs(*ellipsoid_axes(crs))
            xs = np.concatenate([m[1] for m in members])
            ys = np.concatenate([m[2] for m in members])
            lons, lats = (np.asarray(v, dtype=float) for v in warp_transform(crs, lonlat, xs, ys))
            params = crs.to_dict()
            polar = params.get("proj") == "stere"
            start = 0
            for _, mx, _, done in members:
                end = start + len(mx)
                done(*_outline(lons[start:end], lats[start:end], polar, float(params.get("lat_0", 0.0))))
                start = end
        self._groups.clear()


def _outline(lons: np.ndarray, lats: np.ndarray, polar: bool, lat0: float) -> tuple[Outline | None, str]:
    """The outline, or why there is none: an edge off the body - not finite, or a latitude
    past a pole, where a label's LINES of 10^20 puts an equirectangular grid (the map view's
    graticule would then draw a line every 30 degrees across 10^18 of them)."""
    if not (np.all(np.isfinite(lons)) and np.all(np.isfinite(lats)) and np.all(np.abs(lats) <= 90.0 + 1e-9)):
        return None, "the grid's edges do not all fall on the body"
    north = lat0 > 0 if polar else bool(np.mean(lats) >= 0)
    return Outline(lons, lats, polar, north), ""
