"""Offsets versus bounds: the raster a label's IMAGE_MAP_PROJECTION offsets define, fitted
against its latitude/longitude bounds, and the offset convention the fit decides.

The MAP rule family (validate/families/map_rules.py) reports these fits; the PDS3 -> PDS4
migration (migrate/geometry.py) asks `offset_convention_shift` to place a grid as the
validator judges it. So the decision is here, in a plain module both import: importing it
registers no rules. It computes with the validator's own sphere formulas (projection.py),
independent of geo/ on purpose (a check must not share the computation it checks), which is
why it is not in geo/conventions.py, the writer's and reader's home of the conventions.

The label's bounds are recomputed from the raster edges that LINE/SAMPLE_PROJECTION_OFFSET
and MAP_SCALE define (standard PDS3 convention, section 4 of the project's notes), by inverse
projection of the densified boundary; each bound's residual is expressed in pixels.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..label.tree import Block, Statement
from .context import FileContext
from .projection import SUPPORTED, Projection, boundary, normalise, projection_for, projection_radius_key
from .quantities import is_image
from .quantities import kilometres as _km
from .quantities import metres_per_pixel as _scale_m
from .quantities import number as _num

_TOLERANCE_PX = 0.02  # a consistent label: bounds and offsets agree to this (plus printed digits)
_SHIFTS = (0.0, -1.0, 1.0, -0.5, 0.5)

_ROUNDED_DIGITS = 4  # values printed with fewer significant digits are taken as exact


def _printed_half_unit(stmt: Statement | None) -> float:
    """Half a unit in the last printed digit of a real that looks rounded, else 0.

    "14.818" (MAP_SCALE of a 4 px/deg map) is a rounded value; "1.0", "90.0" and "0.5"
    are exact round numbers, whatever their digit count says.
    """
    if stmt is None or stmt.value.kind != "real":
        return 0.0
    mantissa, _, exponent = stmt.value.raw.lower().lstrip("+-").partition("e")
    digits = mantissa.replace(".", "").lstrip("0")
    if len(digits.rstrip("0")) < _ROUNDED_DIGITS:
        return 0.0
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 0.5 * 10.0 ** (-decimals + (int(exponent) if exponent else 0))


def rel_precision(stmt: Statement | None) -> float:
    """Relative half-unit of the last printed digit of a rounded-looking real."""
    half = _printed_half_unit(stmt)
    value = abs(float(stmt.value.py)) if half and stmt is not None else 0.0  # type: ignore[arg-type]
    return half / value if value else 0.0


def _abs_precision(stmt: Statement | None) -> float:
    return _printed_half_unit(stmt)


def _image_size(ctx: FileContext, block: Block) -> tuple[int, int] | None:
    """(lines, samples) the projection describes: its LAST_PIXEL keywords, else the IMAGE."""
    first_l, last_l = block.number("LINE_FIRST_PIXEL") or 1, block.number("LINE_LAST_PIXEL")
    first_s, last_s = block.number("SAMPLE_FIRST_PIXEL") or 1, block.number("SAMPLE_LAST_PIXEL")
    if isinstance(last_l, int) and isinstance(last_s, int):
        return int(last_l - first_l + 1), int(last_s - first_s + 1)
    for image in ctx.root.walk():
        if is_image(image):
            lines, samples = image.number("LINES"), image.number("LINE_SAMPLES")
            if isinstance(lines, int) and isinstance(samples, int):
                return lines, samples
    return None


def _effective_scale(block: Block, radius: float | None) -> float | None:
    """Metres per pixel from MAP_SCALE, or from MAP_RESOLUTION (pixels per degree on a
    sphere of `radius` km) when that is printed more precisely and agrees (so rounded
    MAP_SCALE values do not pose as offset errors)."""
    scale = _scale_m(block)
    res = _num(block, "MAP_RESOLUTION")
    if scale is None or res is None or radius is None or res <= 0:
        return scale
    derived = math.pi * radius * 1000.0 / 180.0 / res
    p_scale = rel_precision(block.get("MAP_SCALE"))
    p_res = rel_precision(block.get("MAP_RESOLUTION"))
    if abs(derived - scale) <= (1e-6 + p_scale + p_res) * scale and p_res < p_scale:
        return derived
    return scale


@dataclass(frozen=True)
class Radius:
    """A radius a label's map arithmetic may use, and how to name it in a finding."""

    km: float
    what: str


def _local_radius(a: float, c: float, latitude: float) -> float:
    """The ellipsoid's radius at a planetocentric latitude (degrees)."""
    phi = math.radians(latitude)
    return a * c / math.hypot(c * math.cos(phi), a * math.sin(phi))


def radius_conventions(block: Block, name: str) -> list[Radius]:
    """The radii MAP_RESOLUTION and the offsets may be computed on, the projection's own
    first (the one GDAL's PDS reader takes: A_AXIS_RADIUS, or C for polar stereographic),
    then the equatorial, the local radius of the ellipsoid at CENTER_LATITUDE (ISIS's
    convention for equirectangular maps of an ellipsoid: the radii keep the ellipsoid, the
    map arithmetic uses that sphere) and the mean radius. A sphere has one radius."""
    key = projection_radius_key(name)
    a, b, c = (_km(block, k) for k in ("A_AXIS_RADIUS", "B_AXIS_RADIUS", "C_AXIS_RADIUS"))
    found: list[Radius] = []

    def add(km: float | None, what: str) -> None:
        if km is not None and km > 0 and all(abs(km - r.km) > 1e-9 * km for r in found):
            found.append(Radius(km, what))

    add(_km(block, key), f"{key} ({'polar' if key.startswith('C') else 'equatorial'})")
    add(a, "A_AXIS_RADIUS (equatorial)")
    lat = _num(block, "CENTER_LATITUDE")
    if a is not None and c is not None and a > 0 and c > 0 and lat is not None and abs(lat) <= 90:
        add(_local_radius(a, c, lat), f"the local radius at CENTER_LATITUDE {lat:g}")
        kind = (block.text("PROJECTION_LATITUDE_TYPE") or block.text("COORDINATE_SYSTEM_NAME") or "").upper()
        if "GRAPHIC" in kind and abs(lat) < 90:  # a planetographic centre latitude, as planetocentric
            centric = math.degrees(math.atan((c / a) ** 2 * math.tan(math.radians(lat))))
            add(_local_radius(a, c, centric), f"the local radius at planetographic CENTER_LATITUDE {lat:g}")
        add((a + (b if b is not None else a) + c) / 3.0, "the mean radius (A + B + C) / 3")
    return found


# -- offsets versus bounds ------------------------------------------------------------
@dataclass
class Geometry:
    sphere: Projection
    scale: float
    spo: float
    lpo: float
    lines: int
    samples: int
    bounds: dict[str, float]  # MINIMUM_LATITUDE ... east-positive longitudes
    slack: dict[str, float]  # printed precision of each bound, degrees


@dataclass
class Fit:
    shift_sample: float
    shift_line: float
    residuals: dict[str, float]  # pixels, per bound
    slack: dict[str, float]  # pixels each bound may be off because of its printed digits

    @property
    def worst(self) -> float:
        return max(abs(r) for r in self.residuals.values())

    @property
    def consistent(self) -> bool:
        return all(abs(r) <= _TOLERANCE_PX + self.slack[k] for k, r in self.residuals.items())


_BOUND_KEYS = ("MINIMUM_LATITUDE", "MAXIMUM_LATITUDE", "WESTERNMOST_LONGITUDE", "EASTERNMOST_LONGITUDE")


def geometry(ctx: FileContext, block: Block, radius: float | None = None) -> Geometry | None:
    """The raster the offsets define, on a sphere of `radius` km (the projection's own
    radius when not given: see radius_conventions)."""
    name = normalise(block.text("MAP_PROJECTION_TYPE") or "")
    if name not in SUPPORTED or (_num(block, "MAP_PROJECTION_ROTATION") or 0.0) != 0.0:
        return None
    if radius is None:
        radius = _km(block, projection_radius_key(name))
    values = {k: _num(block, k) for k in ("CENTER_LATITUDE", "CENTER_LONGITUDE",
                                          "SAMPLE_PROJECTION_OFFSET", "LINE_PROJECTION_OFFSET")}
    bounds = {k: _num(block, k) for k in _BOUND_KEYS}
    scale, size = _effective_scale(block, radius), _image_size(ctx, block)
    if radius is None or scale is None or size is None or None in values.values() or None in bounds.values():
        return None
    west = (block.text("POSITIVE_LONGITUDE_DIRECTION") or "EAST").upper() == "WEST"
    sign = -1.0 if west else 1.0
    center_lon = sign * values["CENTER_LONGITUDE"]  # type: ignore[operator]
    east_bounds = dict(bounds)
    east_bounds["WESTERNMOST_LONGITUDE"] = sign * bounds["WESTERNMOST_LONGITUDE"]  # type: ignore[operator]
    east_bounds["EASTERNMOST_LONGITUDE"] = sign * bounds["EASTERNMOST_LONGITUDE"]  # type: ignore[operator]
    sphere = projection_for(name, radius * 1000.0, values["CENTER_LATITUDE"], center_lon,  # type: ignore[arg-type]
                            1000.0 * (_km(block, "C_AXIS_RADIUS") or radius))
    slack = {k: _abs_precision(block.get(k)) for k in _BOUND_KEYS}
    return Geometry(sphere, scale, values["SAMPLE_PROJECTION_OFFSET"], values["LINE_PROJECTION_OFFSET"],  # type: ignore[arg-type]
                    size[0], size[1], east_bounds, slack)  # type: ignore[arg-type]


def _lon_diff(a: float, b: float) -> float:
    return (a - b + 180.0) % 360.0 - 180.0


def fit(geo: Geometry, shift_sample: float, shift_line: float) -> Fit:
    """Residuals (pixels) of the label bounds against the edges the offsets define."""
    s = geo.scale
    x0 = -(geo.spo - shift_sample + 0.5) * s
    y1 = (geo.lpo - shift_line + 0.5) * s
    x1, y0 = x0 + geo.samples * s, y1 - geo.lines * s
    xs, ys = boundary(x0, x1, y0, y1)
    lat, lon = geo.sphere.inverse(xs, ys)
    ok = np.isfinite(lat) & np.isfinite(lon)
    lat, lon = lat[ok], lon[ok]
    if lat.size == 0:
        return Fit(shift_sample, shift_line, dict.fromkeys(_BOUND_KEYS, math.inf),
                   dict.fromkeys(_BOUND_KEYS, 0.0))
    pole = geo.sphere.contains_pole(x0, x1, y0, y1)
    residuals: dict[str, float] = {}
    slack: dict[str, float] = {}
    imin, imax = int(np.argmin(lat)), int(np.argmax(lat))
    computed = {
        "MINIMUM_LATITUDE": (-90.0 if pole and not geo.sphere.north else float(lat[imin]), float(lon[imin])),
        "MAXIMUM_LATITUDE": (90.0 if pole and geo.sphere.north else float(lat[imax]), float(lon[imax])),
    }
    for key, (value, at_lon) in computed.items():
        residuals[key], slack[key] = _px_lat(geo, geo.bounds[key], value, at_lon, geo.slack[key])
    west, east = geo.bounds["WESTERNMOST_LONGITUDE"], geo.bounds["EASTERNMOST_LONGITUDE"]
    label_span = (east - west) % 360.0 or (360.0 if east != west else 0.0)
    if pole:
        # a pole inside the raster: every longitude is in it
        for key in ("WESTERNMOST_LONGITUDE", "EASTERNMOST_LONGITUDE"):
            residuals[key] = 0.0 if label_span >= 360.0 - 1e-6 else math.inf
            slack[key] = 0.0
        return Fit(shift_sample, shift_line, residuals, slack)
    if float(lon.max() - lon.min()) >= 360.0 - 1e-6 and geo.sphere.name != "POLAR_STEREOGRAPHIC":
        # all the way round: the left and right edges are the bounds (cylindrical maps)
        mid = (y0 + y1) / 2
        for key, x in (("WESTERNMOST_LONGITUDE", x0), ("EASTERNMOST_LONGITUDE", x1)):
            elat, elon = (float(v) for v in geo.sphere.inverse(x, mid))
            residuals[key], slack[key] = _px_lon(geo, geo.bounds[key], elon, elat, geo.slack[key])
        return Fit(shift_sample, shift_line, residuals, slack)
    iw, ie = int(np.argmin(lon)), int(np.argmax(lon))
    for key, idx in (("WESTERNMOST_LONGITUDE", iw), ("EASTERNMOST_LONGITUDE", ie)):
        residuals[key], slack[key] = _px_lon(geo, geo.bounds[key], float(lon[idx]), float(lat[idx]),
                                             geo.slack[key])
    return Fit(shift_sample, shift_line, residuals, slack)


def _px_per_degree(geo: Geometry, lat: float, lon: float, along_lat: bool) -> float:
    """Pixels per degree of latitude (along_lat) or longitude at a point, numerically."""
    step = 1e-6
    if along_lat:
        lat2 = lat - step if lat + step > 90.0 else lat + step
        xa, ya = geo.sphere.forward(lat, lon)
        xb, yb = geo.sphere.forward(lat2, lon)
    else:
        xa, ya = geo.sphere.forward(lat, lon)
        xb, yb = geo.sphere.forward(lat, lon + step)
    return float(math.hypot(float(xa - xb), float(ya - yb))) / geo.scale / step


def _px_lat(geo: Geometry, label: float, computed: float, at_lon: float, slack: float
            ) -> tuple[float, float]:
    """(signed residual, allowance for the printed digits) in pixels for a latitude bound."""
    rate = _px_per_degree(geo, computed, at_lon, along_lat=True)
    return (label - computed) * rate, slack * rate


def _px_lon(geo: Geometry, label: float, computed: float, at_lat: float, slack: float
            ) -> tuple[float, float]:
    rate = _px_per_degree(geo, at_lat, computed, along_lat=False)
    return _lon_diff(label, computed) * rate, slack * rate


def best_fit(geo: Geometry) -> tuple[Fit, Fit]:
    """(fit with the offsets as written, best fit over whole/half pixel shifts)."""
    standard = fit(geo, 0.0, 0.0)
    if standard.consistent:
        return standard, standard
    fits = [standard] + [fit(geo, a, b) for a, b in itertools.product(_SHIFTS, _SHIFTS) if a or b]
    best = min(fits, key=lambda f: (not f.consistent, round(f.worst, 6),
                                    abs(f.shift_sample) + abs(f.shift_line)))
    return standard, best


def radius_fit(ctx: FileContext, block: Block) -> tuple[Geometry, Fit, Fit, str] | None:
    """(geometry, fit as written, best shifted fit, which radius) on the first radius
    convention (see radius_conventions) under which the offsets and bounds agree as written,
    else the first under which a shifted fit agrees, else the one the bounds come nearest
    to. The last item names the radius when it is not the projection's own ("" when it is)."""
    name = normalise(block.text("MAP_PROJECTION_TYPE") or "")
    tried: list[tuple[Geometry, Fit, Fit, str]] = []
    for n, radius in enumerate(radius_conventions(block, name) or [None]):
        geo = geometry(ctx, block, radius.km if radius is not None else None)
        if geo is None:
            return None
        standard, best = best_fit(geo)
        on = f" on {radius.what} ({radius.km:.6f} km)" if radius is not None and n else ""
        tried.append((geo, standard, best, on))
        if standard.consistent:
            return tried[-1]
    return next((t for t in tried if t[2].consistent), None) or min(tried, key=lambda t: t[1].worst)


def offset_convention_shift(ctx: FileContext, block: Block) -> tuple[float, float] | None:
    """(sample, line) pixels to subtract from the offsets as written to get the standard PDS3
    convention's: (0, 0) for a standard label, (1, 1) for the older one-pixel-apart convention;
    None when the bounds decide neither (the offsets are then taken as written). For readers
    of a label (migration) that must place the grid as the validator judges it."""
    fitted = radius_fit(ctx, block)
    if fitted is None:
        return None
    _, standard, best, _ = fitted
    if standard.consistent:
        return 0.0, 0.0
    if best.consistent and abs(best.shift_sample) == 1 and best.shift_sample == best.shift_line:
        return best.shift_sample, best.shift_line
    return None
