"""Sphere map projections of PDS3 labels, forward and inverse, written out from their formulas.

Longitudes are east-positive degrees, x/y in metres. Only what the MAP rules need:
equirectangular (and simple cylindrical), sinusoidal, polar stereographic.
"""

from __future__ import annotations

import math

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
SUPPORTED = CYLINDRICAL | {"SINUSOIDAL", "POLAR_STEREOGRAPHIC"}


def normalise(name: str) -> str:
    return "_".join(name.replace('"', "").replace("'", "").upper().split())


def projection_radius_key(name: str) -> str:
    """Which label radius the projection's sphere uses (as GDAL reads it)."""
    return "C_AXIS_RADIUS" if name == "POLAR_STEREOGRAPHIC" else "A_AXIS_RADIUS"




class Sphere:
    """One projection on a sphere of radius R (metres) with its centre parameters."""

    def __init__(self, name: str, radius: float, center_lat: float, center_lon: float) -> None:
        self.name = name
        self.R = radius
        self.lat1 = math.radians(center_lat)
        self.lon0 = center_lon
        self.north = center_lat >= 0

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
