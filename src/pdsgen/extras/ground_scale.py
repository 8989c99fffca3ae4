"""True ground distances and the direction of north at one point of a map raster.

A map projection's nominal pixel size (MAP_SCALE) is exact only where the projection
has no scale error. Equirectangular is true east-west only on its standard parallel:
at latitude phi a pixel spans MAP_SCALE * cos(phi) / cos(phi_ts) metres of ground east
to west (north-south stays MAP_SCALE). Polar stereographic grows away from the pole.
A scale bar that claims "1 km" must use the true scale, so everything here measures
on the body's ellipsoid: map the point and a neighbour half a pixel either side back
to longitude/latitude with PROJ (rasterio.warp.transform) and convert the angular
difference to metres with the ellipsoid's radii of curvature. Geographic (degree)
rasters go through the same code.

Archived global maps go through the same path: GDAL reads the MOLA MEGDR label
(SIMPLE CYLINDRICAL, 3396 km sphere, 14.818 km/pixel) as an equirectangular CRS in
metres with standard parallel 0, so at its image centre (the equator) the bar uses
14818 m per product pixel; its north is up. The bar is true along image rows at the
image centre only; README.TXT and the module docstring of `annotate` say so.

North is found the same way: step a little north in latitude, project forward, and
see where that lands in pixel coordinates. On a polar stereographic map north points
to (or away from) the pole, not up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from rasterio.crs import CRS
from rasterio.errors import CRSError
from rasterio.warp import transform as warp_transform

from ..errors import PdsgenError
from ..geo.conventions import wrap_180, wrap_360
from ..geo.geometry import ellipsoid_axes
from ..geo.geometry import geographic_crs as geo_geographic_crs


@dataclass(frozen=True)
class GroundScale:
    """At one pixel: ground metres per pixel step along columns and rows, and north.

    `north_deg` is the direction of north in the image, clockwise from "up"
    (0 = north up, 90 = north to the right).
    """

    metres_per_column: float
    metres_per_row: float
    north_deg: float
    longitude: float
    latitude: float


def geographic_crs(crs: CRS) -> CRS:
    """Longitude/latitude on the same body as `crs` (no datum shift involved)."""
    return geo_geographic_crs(*ellipsoid_axes(crs))


def ground_scale_at(crs: CRS, transform: Any, col: float, row: float) -> GroundScale:
    """True ground size of one pixel at pixel position (col, row), and north there.

    `transform` is the affine geotransform of the grid the pixel belongs to (use the
    full-resolution one and multiply by the decimation factor, or the decimated
    one directly: the result is per pixel of that grid).
    """
    a, b = ellipsoid_axes(crs)
    geo = geographic_crs(crs)
    cols = [col - 0.5, col + 0.5, col, col, col]
    rows = [row, row, row - 0.5, row + 0.5, row]
    xs, ys = zip(*(transform @ (c, r) for c, r in zip(cols, rows, strict=True)), strict=True)
    try:
        lons, lats = warp_transform(crs, geo, list(xs), list(ys))
    except CRSError as exc:
        raise PdsgenError(None, f"cannot transform map coordinates ({exc})") from None
    if not all(math.isfinite(v) for v in (*lons, *lats)):
        raise PdsgenError(None, "image centre lies outside the projection's valid area")
    along_cols = _distance(a, b, lons[0], lats[0], lons[1], lats[1])
    along_rows = _distance(a, b, lons[2], lats[2], lons[3], lats[3])
    north = _north_direction(crs, geo, transform, lons[4], lats[4], along_rows, a, b)
    return GroundScale(along_cols, along_rows, north, lons[4], lats[4])


def _radii(a: float, b: float, lat_deg: float) -> tuple[float, float]:
    """Meridional (M) and prime-vertical (N) radii of curvature at a latitude."""
    e2 = 1.0 - (b * b) / (a * a)
    s = math.sin(math.radians(lat_deg))
    w = math.sqrt(1.0 - e2 * s * s)
    return a * (1.0 - e2) / w**3, a / w


def _distance(a: float, b: float, lon1: float, lat1: float, lon2: float, lat2: float) -> float:
    """Ground distance between two close points (local metric of the ellipsoid)."""
    dlon = wrap_180(lon2 - lon1)
    m, n = _radii(a, b, 0.5 * (lat1 + lat2))
    dy = m * math.radians(lat2 - lat1)
    dx = n * math.cos(math.radians(0.5 * (lat1 + lat2))) * math.radians(dlon)
    return math.hypot(dx, dy)


def _north_direction(crs: CRS, geo: CRS, transform: Any, lon: float, lat: float,
                     step_m: float, a: float, b: float) -> float:
    """Clockwise angle from image-up to north at (lon, lat), in degrees.

    At a pole north has no direction; the point is then taken a fraction of a
    pixel towards the equator (so on a pole-centred polar map the arrow shows north
    for the point just below the centre).
    """
    m, _ = _radii(a, b, lat)
    dlat = math.degrees(max(step_m, 1e-3) / m)
    if abs(lat) > 90.0 - 2 * dlat:
        lat = math.copysign(90.0 - 2 * dlat, lat)
    xs, ys = warp_transform(geo, crs, [lon, lon], [lat - dlat, lat + dlat])
    inverse = ~transform
    c0, r0 = inverse @ (xs[0], ys[0])
    c1, r1 = inverse @ (xs[1], ys[1])
    return wrap_360(math.degrees(math.atan2(c1 - c0, -(r1 - r0))))
