"""Describe a raster's map geometry as PDS3 IMAGE_MAP_PROJECTION keywords.

Input: the CRS and affine geotransform GDAL reports. Output: the projection type,
radii, centre, scale, resolution, projection offsets (PDS3 standard convention,
which GDAL reads back to the identical geotransform) and the latitude/longitude
bounds of the raster's outer edges. The three projections planetary archive
products use are supported, and Transverse Mercator on an ellipsoid (HRSC-AX airborne
tiles on Earth); anything else is refused rather than approximated.

Transverse Mercator is described with geodetic (PLANETOGRAPHIC) latitudes, the
latitudes of the ellipsoid the projection is computed on. GDAL's PDS reader builds
it with a scale factor of 1 and no false easting/northing (it reads no keyword for
either), so the label folds them into what GDAL does read: the offsets count from
the natural origin (false easting/northing subtracted), and MAP_SCALE is the grid
spacing divided by the scale factor - the ground distance on the central meridian of
one pixel. Every pixel then lands where the grid puts it.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
from affine import Affine
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from ..errors import PdsgenError
from .conventions import map_resolution, projection_offsets, unwrap_near, wrap_360

EQUIRECTANGULAR = "EQUIRECTANGULAR"
POLAR_STEREOGRAPHIC = "POLAR STEREOGRAPHIC"
SINUSOIDAL = "SINUSOIDAL"
TRANSVERSE_MERCATOR = "TRANSVERSE MERCATOR"
PLANETOCENTRIC = "PLANETOCENTRIC"
PLANETOGRAPHIC = "PLANETOGRAPHIC"

_SPHEROID_RE = re.compile(r'SPHEROID\["(?P<name>[^"]*)",\s*(?P<a>[-\d.eE+]+),\s*(?P<rf>[-\d.eE+]+)')
_BODY_NAMES = (
    "MERCURY", "VENUS", "EARTH", "MOON", "MARS", "PHOBOS", "DEIMOS", "CERES", "VESTA",
    "IO", "EUROPA", "GANYMEDE", "CALLISTO", "TITAN", "ENCELADUS", "PLUTO", "CHARON",
)
_LETTER_RUNS = re.compile(r"[A-Z]+")
_EARTH_HINTS = ("WGS", "GRS", "NAD", "ETRS", "CLARKE", "BESSEL", "INTERNATIONAL")
# Mean or equatorial radii (km): a CRS with an anonymous ellipsoid is matched by size.
_BODY_RADII_KM = {
    "MERCURY": 2439.7, "VENUS": 6051.8, "EARTH": 6371.0, "MOON": 1737.4, "MARS": 3389.5,
    "PHOBOS": 11.1, "DEIMOS": 6.2, "CERES": 469.7, "VESTA": 262.7, "IO": 1821.6, "EUROPA": 1560.8,
    "GANYMEDE": 2631.2, "CALLISTO": 2410.3, "TITAN": 2574.7, "ENCELADUS": 252.1, "PLUTO": 1188.3,
    "CHARON": 606.0,
}
_ANGLE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class MapGeometry:
    """Everything IMAGE_MAP_PROJECTION and NORTH_AZIMUTH need, in label units."""

    projection_type: str
    a_axis_km: float
    b_axis_km: float
    c_axis_km: float
    center_latitude: float
    center_longitude: float
    map_scale: float  # metres per pixel
    map_resolution: float  # pixels per degree
    line_projection_offset: float
    sample_projection_offset: float
    minimum_latitude: float
    maximum_latitude: float
    westernmost_longitude: float
    easternmost_longitude: float
    north_azimuth: float
    lines: int
    samples: int
    target_name: str | None  # body named by the CRS, when it names one
    latitude_type: str = PLANETOCENTRIC  # of the latitude keywords (TM: PLANETOGRAPHIC, geodetic)
    scale_factor: float = 1.0  # TM: on the central meridian (folded into map_scale, see the module)
    false_easting: float = 0.0  # metres, of the CRS's grid (the offsets count without it)
    false_northing: float = 0.0

    @property
    def is_sphere(self) -> bool:
        return self.a_axis_km == self.c_axis_km

    def transverse_mercator_note(self) -> tuple[str, ...]:
        """The label comment stating the grid folded into a Transverse Mercator label's keywords."""
        from .transverse_mercator import grid_note  # only Transverse Mercator labels need it

        return grid_note(self.scale_factor, self.false_easting, self.false_northing)


@dataclass(frozen=True)
class _Projection:
    kind: str
    a: float  # metres
    b: float
    center_latitude: float
    center_longitude: float
    false_easting: float
    false_northing: float
    scale_factor: float = 1.0

    @property
    def latitude_type(self) -> str:
        return PLANETOGRAPHIC if self.kind == TRANSVERSE_MERCATOR else PLANETOCENTRIC


def describe_geometry(
    crs: CRS | None, transform: Affine, width: int, height: int, source: str = "input",
    bounds: tuple[float, float, float, float] | None = None,
) -> MapGeometry:
    """Compute the PDS3 map keywords of a north-up raster in a supported CRS.

    `bounds` (minimum and maximum latitude, westernmost and easternmost longitude) are taken
    as given instead of computed: a label that already states them, checked elsewhere
    (migration: a PDS3 label whose rounded MAP_SCALE puts a global grid's edge past a pole)."""
    if crs is None or not crs.to_wkt():
        raise PdsgenError(source, "raster has no coordinate reference system (map projection)")
    projection = _parse_projection(crs, source)
    grid_scale = _square_pixel_size(transform, source)
    # Projection coordinates relative to the natural origin (no false easting), in the
    # projection's units before its scale factor (see the module docstring).
    k = projection.scale_factor
    ulx = (transform.c - projection.false_easting) / k
    uly = (transform.f - projection.false_northing) / k
    scale = grid_scale / k
    radius = projection.b if projection.kind == POLAR_STEREOGRAPHIC else projection.a
    sample_offset, line_offset = projection_offsets(ulx, uly, scale)
    lat_min, lat_max, lon_west, lon_east = bounds or _bounds(crs, transform, width, height, projection, source)
    return MapGeometry(
        projection_type=projection.kind,
        a_axis_km=projection.a / 1000.0,
        b_axis_km=projection.a / 1000.0,
        c_axis_km=projection.b / 1000.0,
        center_latitude=projection.center_latitude,
        center_longitude=wrap_360(projection.center_longitude),
        map_scale=scale,
        map_resolution=map_resolution(radius, scale),
        line_projection_offset=line_offset,
        sample_projection_offset=sample_offset,
        minimum_latitude=lat_min,
        maximum_latitude=lat_max,
        westernmost_longitude=lon_west,
        easternmost_longitude=lon_east,
        north_azimuth=_north_azimuth(projection, transform, width, height, crs),
        lines=height,
        samples=width,
        target_name=_target_name(crs, projection.a),
        latitude_type=projection.latitude_type,
        scale_factor=k,
        false_easting=projection.false_easting,
        false_northing=projection.false_northing,
    )


def _parse_projection(crs: CRS, source: str) -> _Projection:
    params = crs.to_dict()
    name = params.get("proj")
    a, b = _ellipsoid_axes(crs, params, source)
    lon0 = float(params.get("lon_0", 0.0))
    x0 = float(params.get("x_0", 0.0))
    y0 = float(params.get("y_0", 0.0))
    if name == "eqc":
        lat_ts = float(params.get("lat_ts", 0.0))
        lat0 = float(params.get("lat_0", 0.0))
        # A non-zero latitude of origin only shifts northings: fold it into y0.
        y0 -= a * math.radians(lat0)
        return _Projection(EQUIRECTANGULAR, a, b, lat_ts, lon0, x0, y0)
    if name == "sinu":
        return _Projection(SINUSOIDAL, a, b, 0.0, lon0, x0, y0)
    if name == "stere" and abs(abs(float(params.get("lat_0", 0.0))) - 90.0) < _ANGLE_TOLERANCE:
        lat0 = float(params["lat_0"])
        lat_ts = float(params.get("lat_ts", lat0))
        k = float(params.get("k", params.get("k_0", 1.0)))
        if abs(lat_ts - lat0) > _ANGLE_TOLERANCE or abs(k - 1.0) > 1e-12:
            raise PdsgenError(
                source,
                "polar stereographic with true scale away from the pole "
                f"(lat_ts={lat_ts:g}, k={k:g}) cannot be described by a PDS3 label; "
                "reproject to true scale at the pole (k=1)",
            )
        return _Projection(POLAR_STEREOGRAPHIC, a, b, math.copysign(90.0, lat0), lon0, x0, y0)
    if name in ("tmerc", "utm", "etmerc"):
        k = float(params.get("k", params.get("k_0", 1.0)))
        lat0 = float(params.get("lat_0", 0.0))
        if name == "utm":
            from . import utm  # a UTM CRS only: writers of other grids start faster
            lon0, k, x0 = utm.zone_central_meridian(int(params["zone"])), utm.SCALE_FACTOR, utm.FALSE_EASTING
            y0 = utm.false_northing(bool(params.get("south")))
        return _Projection(TRANSVERSE_MERCATOR, a, b, lat0, lon0, x0, y0, k)
    if name == "ups":
        raise PdsgenError(source, "UPS is not supported; use a polar stereographic CRS with k=1")
    label = crs.to_wkt().split('PROJECTION["')[1].split('"')[0] if "PROJECTION[" in crs.to_wkt() else name
    raise PdsgenError(
        source,
        f"unsupported map projection {label!r}: pdsgen writes equirectangular, "
        "polar stereographic, sinusoidal and transverse Mercator products",
    )


def ellipsoid_axes(crs: CRS, source: str = "input") -> tuple[float, float]:
    """Semi-major and semi-minor axes (metres) of the CRS's body."""
    return _ellipsoid_axes(crs, crs.to_dict(), source)


def _ellipsoid_axes(crs: CRS, params: dict, source: str) -> tuple[float, float]:
    if "R" in params:
        radius = float(params["R"])
        return radius, radius
    if "a" in params:
        a = float(params["a"])
        if "b" in params:
            return a, float(params["b"])
        if "rf" in params:
            return a, a * (1.0 - 1.0 / float(params["rf"]))
        return a, a
    match = _SPHEROID_RE.search(crs.to_wkt())
    if match is None:
        raise PdsgenError(source, "cannot determine the body's radii from the CRS")
    a = float(match.group("a"))
    inverse_flattening = float(match.group("rf"))
    b = a if inverse_flattening == 0 else a * (1.0 - 1.0 / inverse_flattening)
    return a, b


def _square_pixel_size(transform: Affine, source: str) -> float:
    if transform.b != 0 or transform.d != 0:
        raise PdsgenError(source, "rotated or sheared rasters cannot be described by PDS3 map keywords")
    if transform.a <= 0 or transform.e >= 0:
        raise PdsgenError(source, "raster is not north-up (pixel height must be negative)")
    if not math.isclose(transform.a, -transform.e, rel_tol=1e-9):
        raise PdsgenError(
            source, f"pixels are not square ({transform.a:g} x {-transform.e:g}); PDS3 needs one MAP_SCALE"
        )
    return float(transform.a)


def _edge_points(transform: Affine, width: int, height: int, per_side: int = 257):
    """Points along the raster's outer boundary (pixel edges, not centres). The sizes are taken
    as floats: a label's LINES may be any integer, past what numpy's integers hold."""
    cols = np.linspace(0.0, float(width), per_side)
    rows = np.linspace(0.0, float(height), per_side)
    col = np.concatenate([cols, np.full(per_side, float(width)), cols[::-1], np.zeros(per_side)])
    row = np.concatenate([np.zeros(per_side), rows, np.full(per_side, float(height)), rows[::-1]])
    xs = transform.c + col * transform.a
    ys = transform.f + row * transform.e
    return xs, ys


def geographic_crs(a: float, b: float) -> CRS:
    """Longitude/latitude (geodetic) on the ellipsoid of semi-axes a, b metres: the body of a
    projected CRS without any datum shift, for inverse projection."""
    return CRS.from_proj4(f"+proj=longlat +a={a!r} +b={b!r} +no_defs")


def _geographic_crs(projection: _Projection) -> CRS:
    return geographic_crs(projection.a, projection.b)


def _bounds(crs: CRS, transform: Affine, width: int, height: int, projection: _Projection, source: str):
    xs, ys = _edge_points(transform, width, height)
    lons, lats = warp_transform(crs, _geographic_crs(projection), xs, ys)
    lons = np.asarray(lons, dtype=float)
    lats = np.asarray(lats, dtype=float)
    if projection.latitude_type == PLANETOCENTRIC:
        lats = _planetocentric(lats, projection)
    if not (np.all(np.isfinite(lats)) and np.all(np.isfinite(lons)) and np.all(np.abs(lats) <= 90.0 + 1e-9)):
        raise PdsgenError(
            source, "raster extends beyond the body (its edges do not map to latitudes within -90..90); "
                    "check its georeferencing and CRS",
        )
    lat_min, lat_max = float(lats.min()), float(lats.max())
    if projection.kind == POLAR_STEREOGRAPHIC and _contains_pole(transform, width, height, projection):
        if projection.center_latitude > 0:
            lat_max = 90.0
        else:
            lat_min = -90.0
        return lat_min, lat_max, 0.0, 360.0
    centre_lon, _ = warp_transform(
        crs, _geographic_crs(projection), [transform.c + transform.a * width / 2],
        [transform.f + transform.e * height / 2],
    )
    unwrapped = unwrap_near(lons, centre_lon[0])
    west, east = float(unwrapped.min()), float(unwrapped.max())
    if east - west >= 360.0 - 1e-9:
        return lat_min, lat_max, 0.0, 360.0
    return lat_min, lat_max, wrap_360(west), wrap_360(east)


def _planetocentric(geodetic_lat: np.ndarray, projection: _Projection) -> np.ndarray:
    """PROJ returns geodetic latitudes; PDS keywords here are planetocentric."""
    if projection.a == projection.b:
        return geodetic_lat
    ratio = (projection.b / projection.a) ** 2
    return np.degrees(np.arctan(ratio * np.tan(np.radians(geodetic_lat))))


def _contains_pole(transform: Affine, width: int, height: int, projection: _Projection) -> bool:
    col, row = ~transform @ (projection.false_easting, projection.false_northing)
    return 0.0 <= col <= width and 0.0 <= row <= height


def _north_azimuth(projection: _Projection, transform: Affine, width: int, height: int, crs: CRS) -> float:
    """Clockwise angle from the image's +sample axis to north, at the image centre.

    North is straight up (270 degrees) in cylindrical and sinusoidal products;
    in polar stereographic products it points along the meridian, toward the
    pole in the north and away from it in the south; in Transverse Mercator it
    leans by the grid convergence away from the central meridian (from the
    projection itself: a step north of the centre, projected).
    """
    if projection.kind == TRANSVERSE_MERCATOR:
        return _projected_north(crs, projection, transform, width, height)
    if projection.kind != POLAR_STEREOGRAPHIC:
        return 270.0
    x, y = transform @ (width / 2.0, height / 2.0)
    dx, dy = x - projection.false_easting, y - projection.false_northing
    if dx == 0.0 and dy == 0.0:
        return 270.0
    sign = -1.0 if projection.center_latitude > 0 else 1.0
    north_x, north_y = sign * dx, sign * dy  # map coordinates, y up
    angle = math.degrees(math.atan2(-north_y, north_x))  # image y runs down
    return wrap_360(angle)


def _projected_north(crs: CRS, projection: _Projection, transform: Affine, width: int, height: int) -> float:
    x, y = transform @ (width / 2.0, height / 2.0)
    geographic = _geographic_crs(projection)
    (lon,), (lat,) = warp_transform(crs, geographic, [x], [y])
    xs, ys = warp_transform(geographic, crs, [lon, lon], [lat, lat + 1e-4])
    angle = math.degrees(math.atan2(-(ys[1] - ys[0]), xs[1] - xs[0]))  # image y runs down
    return round(wrap_360(angle), 6)


def _target_name(crs: CRS, semi_major_m: float) -> str | None:
    """The body named by the CRS, else the body whose size matches within 1 %."""
    wkt = crs.to_wkt().upper()
    match = _SPHEROID_RE.search(crs.to_wkt())
    names = [match.group("name").upper()] if match else []
    names.append(wkt)
    for text in names:
        words = set(_LETTER_RUNS.findall(text))  # a body name counts only as a whole word
        for body in _BODY_NAMES:
            if body in words:
                return body
        if any(hint in text for hint in _EARTH_HINTS):
            return "EARTH"
    radius_km = semi_major_m / 1000.0
    for body, reference in _BODY_RADII_KM.items():
        if abs(radius_km - reference) <= 0.01 * reference:
            return body
    return None
