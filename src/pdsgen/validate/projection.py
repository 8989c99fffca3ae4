"""Map projections of PDS3 labels, forward and inverse, written out from their formulas.

Longitudes are east-positive degrees, x/y in metres. Only what the MAP rules need:
equirectangular (and simple cylindrical), sinusoidal, polar stereographic on a sphere,
and Transverse Mercator on an ellipsoid (Snyder 1987, USGS Professional Paper 1395,
equations 8-9 to 8-25; geodetic latitudes; scale factor 1, as a PDS3 label states it).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np

# Names GDAL's PDS driver turns into a CRS (after its quote removal and ' ' -> '_').
GDAL_PROJECTIONS = frozenset(
    {
        "EQUIRECTANGULAR",
        "SIMPLE_CYLINDRICAL",
        "EQUIDISTANT",
        "ORTHOGRAPHIC",
        "SINUSOIDAL",
        "MERCATOR",
        "STEREOGRAPHIC",
        "POLAR_STEREOGRAPHIC",
        "TRANSVERSE_MERCATOR",
        "LAMBERT_CONFORMAL_CONIC",
        "LAMBERT_AZIMUTHAL_EQUAL_AREA",
        "CYLINDRICAL_EQUAL_AREA",
        "MOLLWEIDE",
        "ALBERS",
        "BONNE",
        "GNOMONIC",
        "OBLIQUE_CYLINDRICAL",
    }
)
CYLINDRICAL = frozenset({"EQUIRECTANGULAR", "SIMPLE_CYLINDRICAL", "EQUIDISTANT"})
SUPPORTED = CYLINDRICAL | {"SINUSOIDAL", "POLAR_STEREOGRAPHIC", "TRANSVERSE_MERCATOR"}


def normalise(name: str) -> str:
    return "_".join(name.replace('"', "").replace("'", "").upper().split())


def projection_radius_key(name: str) -> str:
    """Which label radius the projection's sphere uses (as GDAL reads it)."""
    return "C_AXIS_RADIUS" if name == "POLAR_STEREOGRAPHIC" else "A_AXIS_RADIUS"


class Projection(ABC):
    """A label's map projection: its name, centre and the forward and inverse formulas.

    Sphere and TransverseMercator (on an ellipsoid) are the two kinds; the MAP rules and the
    PDS4 cart: checks hold either through this type.
    """

    def __init__(self, name: str, center_lat: float, center_lon: float) -> None:
        self.name = name
        self.lat1 = math.radians(center_lat)
        self.lon0 = center_lon
        self.north = center_lat >= 0

    @abstractmethod
    def forward(self, lat, lon):
        """(x, y) in metres of latitude/longitude in degrees (arrays welcome)."""

    @abstractmethod
    def inverse(self, x, y):
        """(latitude, longitude) in degrees of x, y in metres; longitude relative-unwrapped."""

    def contains_pole(self, x0: float, x1: float, y0: float, y1: float) -> bool:
        """Whether the rectangle [x0, x1] x [y0, y1] of projection metres holds a pole."""
        return False


class Sphere(Projection):
    """One projection on a sphere of radius R (metres) with its centre parameters."""

    def __init__(self, name: str, radius: float, center_lat: float, center_lon: float) -> None:
        super().__init__(name, center_lat, center_lon)
        self.R = radius

    def forward(self, lat, lon):
        """(x, y) in metres of latitude/longitude in degrees (arrays welcome)."""
        lat = np.radians(np.asarray(lat, dtype=float))
        dlon = np.radians(_wrap(np.asarray(lon, dtype=float) - self.lon0))
        if self.name in CYLINDRICAL:
            return self.R * dlon * math.cos(self.lat1), self.R * lat
        if self.name == "SINUSOIDAL":
            return self.R * dlon * np.cos(lat), self.R * lat
        if self.north:
            rho = 2 * self.R * np.tan(math.pi / 4 - lat / 2)
            return rho * np.sin(dlon), -rho * np.cos(dlon)
        rho = 2 * self.R * np.tan(math.pi / 4 + lat / 2)
        return rho * np.sin(dlon), rho * np.cos(dlon)

    def inverse(self, x, y):
        """(latitude, longitude) in degrees of x, y in metres; longitude relative-unwrapped."""
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        if self.name in CYLINDRICAL:
            lat = y / self.R
            dlon = x / (self.R * math.cos(self.lat1))
        elif self.name == "SINUSOIDAL":
            lat = y / self.R
            with np.errstate(divide="ignore", invalid="ignore"):
                dlon = x / (self.R * np.cos(lat))
        else:
            rho = np.hypot(x, y)
            c = 2 * np.arctan(rho / (2 * self.R))
            if self.north:
                lat = math.pi / 2 - c
                dlon = np.arctan2(x, -y)
            else:
                lat = c - math.pi / 2
                dlon = np.arctan2(x, y)
        return np.degrees(lat), self.lon0 + np.degrees(dlon)

    def contains_pole(self, x0: float, x1: float, y0: float, y1: float) -> bool:
        return self.name == "POLAR_STEREOGRAPHIC" and x0 <= 0 <= x1 and y0 <= 0 <= y1


class TransverseMercator(Projection):
    """Transverse Mercator on the ellipsoid of semi-axes a (equatorial) and c (polar), metres.

    PDS3 labels have no scale-factor keyword: a grid's scale factor is folded into MAP_SCALE,
    so the projection here is the one with scale factor 1 on the central meridian.
    """

    def __init__(self, a: float, c: float, center_lat: float, center_lon: float) -> None:
        super().__init__("TRANSVERSE_MERCATOR", center_lat, center_lon)
        self.a = a
        self.e2 = 1.0 - (c / a) ** 2
        self.ep2 = self.e2 / (1.0 - self.e2)
        self.m0 = float(self._meridian_arc(np.asarray(self.lat1)))

    def _meridian_arc(self, lat):
        """M, the distance along the meridian from the equator to latitude `lat` (radians)."""
        e2 = self.e2
        e4, e6 = e2 * e2, e2 * e2 * e2
        return self.a * ((1 - e2 / 4 - 3 * e4 / 64 - 5 * e6 / 256) * lat
                         - (3 * e2 / 8 + 3 * e4 / 32 + 45 * e6 / 1024) * np.sin(2 * lat)
                         + (15 * e4 / 256 + 45 * e6 / 1024) * np.sin(4 * lat)
                         - (35 * e6 / 3072) * np.sin(6 * lat))

    def forward(self, lat, lon):
        phi = np.radians(np.asarray(lat, dtype=float))
        dlon = np.radians(_wrap(np.asarray(lon, dtype=float) - self.lon0))
        sin, cos, tan = np.sin(phi), np.cos(phi), np.tan(phi)
        n = self.a / np.sqrt(1 - self.e2 * sin * sin)
        t, c = tan * tan, self.ep2 * cos * cos
        a = dlon * cos
        x = n * (a + (1 - t + c) * a**3 / 6 + (5 - 18 * t + t * t + 72 * c - 58 * self.ep2) * a**5 / 120)
        y = (self._meridian_arc(phi) - self.m0
             + n * tan * (a**2 / 2 + (5 - t + 9 * c + 4 * c * c) * a**4 / 24
                          + (61 - 58 * t + t * t + 600 * c - 330 * self.ep2) * a**6 / 720))
        return x, y

    def inverse(self, x, y):
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        e2, ep2 = self.e2, self.ep2
        mu = (self.m0 + y) / (self.a * (1 - e2 / 4 - 3 * e2**2 / 64 - 5 * e2**3 / 256))
        e1 = (1 - math.sqrt(1 - e2)) / (1 + math.sqrt(1 - e2))
        phi1 = (mu + (3 * e1 / 2 - 27 * e1**3 / 32) * np.sin(2 * mu)
                + (21 * e1**2 / 16 - 55 * e1**4 / 32) * np.sin(4 * mu)
                + (151 * e1**3 / 96) * np.sin(6 * mu) + (1097 * e1**4 / 512) * np.sin(8 * mu))
        sin, cos, tan = np.sin(phi1), np.cos(phi1), np.tan(phi1)
        c1, t1 = ep2 * cos * cos, tan * tan
        n1 = self.a / np.sqrt(1 - e2 * sin * sin)
        r1 = self.a * (1 - e2) / (1 - e2 * sin * sin) ** 1.5
        d = x / n1
        lat = phi1 - (n1 * tan / r1) * (d**2 / 2 - (5 + 3 * t1 + 10 * c1 - 4 * c1 * c1 - 9 * ep2) * d**4 / 24
                                        + (61 + 90 * t1 + 298 * c1 + 45 * t1 * t1 - 252 * ep2 - 3 * c1 * c1)
                                        * d**6 / 720)
        dlon = (d - (1 + 2 * t1 + c1) * d**3 / 6
                + (5 - 2 * c1 + 28 * t1 - 3 * c1 * c1 + 8 * ep2 + 24 * t1 * t1) * d**5 / 120) / cos
        return np.degrees(lat), self.lon0 + np.degrees(dlon)


def projection_for(name: str, radius: float, center_lat: float, center_lon: float,
                   polar_radius: float | None = None) -> Projection:
    """The projection of a label: radii in metres (`polar_radius`: C_AXIS_RADIUS, for Transverse
    Mercator's ellipsoid; the sphere projections use `radius` alone)."""
    if name == "TRANSVERSE_MERCATOR":
        return TransverseMercator(radius, polar_radius or radius, center_lat, center_lon)
    return Sphere(name, radius, center_lat, center_lon)


def _wrap(dlon):
    """Longitude differences into (-180, 180]."""
    return (np.asarray(dlon) + 180.0) % 360.0 - 180.0


def boundary(x0: float, x1: float, y0: float, y1: float, n: int = 64) -> tuple[np.ndarray, np.ndarray]:
    """Points along the four edges of the rectangle [x0, x1] x [y0, y1], plus the points
    where a bound can fall between samples: the boundary point nearest the projection
    origin (a polar raster's latitude extreme) and the edges' crossings of x = 0 and
    y = 0 (the central meridian and the equator)."""
    t = np.linspace(0.0, 1.0, n + 1)
    xs = [x0 + (x1 - x0) * t, np.full_like(t, x1), x1 - (x1 - x0) * t, np.full_like(t, x0)]
    ys = [np.full_like(t, y1), y1 - (y1 - y0) * t, np.full_like(t, y0), y0 + (y1 - y0) * t]
    # the foot of the perpendicular from the origin on each edge, clamped to the edge:
    # one of them is the boundary point nearest the origin
    cx, cy = min(max(0.0, x0), x1), min(max(0.0, y0), y1)
    extra_x, extra_y = [cx, cx, x0, x1], [y0, y1, cy, cy]
    if y0 <= 0.0 <= y1:
        extra_x += [x0, x1]
        extra_y += [0.0, 0.0]
    if x0 <= 0.0 <= x1:
        extra_x += [0.0, 0.0]
        extra_y += [y0, y1]
    return (np.concatenate(xs + [np.array(extra_x, dtype=float)]),
            np.concatenate(ys + [np.array(extra_y, dtype=float)]))
