"""MAP family: IMAGE_MAP_PROJECTION arithmetic - resolution vs scale vs radius, offsets vs bounds.

The label's latitude/longitude bounds are recomputed from the raster edges that
LINE/SAMPLE_PROJECTION_OFFSET and MAP_SCALE define (standard PDS3 convention, section 4
of the project's notes), by inverse projection of the densified boundary. The residual
of each bound is expressed in pixels. Offsets one pixel apart on both axes are the
older convention; half a pixel is centre/corner confusion; anything else is an error.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ...label.tree import Block, Statement
from ..context import FileContext
from ..model import Hit
from ..profiles import is_hrsc
from ..projection import (
    GDAL_PROJECTIONS,
    SUPPORTED,
    Projection,
    boundary,
    normalise,
    projection_for,
    projection_radius_key,
)
from ..quantities import kilometres as _km
from ..quantities import metres_per_pixel as _scale_m
from ..quantities import number as _num
from ..registry import Rule, register
from .image_rules import is_image

_REQUIRED = (
    "MAP_PROJECTION_TYPE",
    "A_AXIS_RADIUS",
    "C_AXIS_RADIUS",
    "CENTER_LATITUDE",
    "CENTER_LONGITUDE",
    "MAP_SCALE",
    "LINE_PROJECTION_OFFSET",
    "SAMPLE_PROJECTION_OFFSET",
    "MAXIMUM_LATITUDE",
    "MINIMUM_LATITUDE",
    "EASTERNMOST_LONGITUDE",
    "WESTERNMOST_LONGITUDE",
)
_TOLERANCE_PX = 0.02  # a consistent label: bounds and offsets agree to this (plus printed digits)
_NEAR_PX = 1.0  # beyond this the bounds and offsets describe different rasters
_SHIFTS = (0.0, -1.0, 1.0, -0.5, 0.5)


def _maps(ctx: FileContext) -> Iterator[Block]:
    yield from ctx.root.find("IMAGE_MAP_PROJECTION")


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


def _rel_precision(stmt: Statement | None) -> float:
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
    p_scale = _rel_precision(block.get("MAP_SCALE"))
    p_res = _rel_precision(block.get("MAP_RESOLUTION"))
    if abs(derived - scale) <= (1e-6 + p_scale + p_res) * scale and p_res < p_scale:
        return derived
    return scale


def check_required(ctx: FileContext) -> Iterator[Hit]:
    for block in _maps(ctx):
        missing = [k for k in _REQUIRED if block.get(k) is None]
        if block.get("MAP_SCALE") is None and block.get("MAP_RESOLUTION") is not None:
            missing.remove("MAP_SCALE")
        if missing:
            yield Hit(f"IMAGE_MAP_PROJECTION lacks {', '.join(missing)}", block.line, missing[0])


# Map projections the PDS3 standard describes that GDAL's PDS reader does not georeference
# (a label using one is valid; GDAL reads its pixels without a CRS)
PDS3_ONLY_PROJECTIONS = frozenset({
    "POINT_PERSPECTIVE", "PERSPECTIVE", "ORTHOGRAPHIC", "OBLIQUE_CYLINDRICAL", "GNOMONIC", "AITOFF",
    "ALBERS", "BONNE", "HAMMER", "MOLLWEIDE", "STEREOGRAPHIC", "VAN_DER_GRINTEN", "WERNER",
    "CYLINDRICAL_PERSPECTIVE", "BRIESEMEISTER", "HENDU",
})


def check_projection_name(ctx: FileContext) -> Iterator[Hit]:
    """An error for a name no reader knows; a warning for a PDS3 projection GDAL does not
    georeference (Galileo NIMS cubes in POINT_PERSPECTIVE)."""
    for block in _maps(ctx):
        stmt = block.get("MAP_PROJECTION_TYPE")
        name = normalise(stmt.value.text) if stmt is not None else ""
        if stmt is not None and name not in GDAL_PROJECTIONS:
            level = "warning" if name in PDS3_ONLY_PROJECTIONS else None
            yield Hit(f"MAP_PROJECTION_TYPE {stmt.value.raw} is not a projection GDAL's PDS reader "
                      "knows (e.g. EQUIRECTANGULAR, SINUSOIDAL, POLAR STEREOGRAPHIC)", stmt.line,
                      "MAP_PROJECTION_TYPE", severity=level)


def check_radii(ctx: FileContext) -> Iterator[Hit]:
    for block in _maps(ctx):
        a, b, c = (_km(block, k) for k in ("A_AXIS_RADIUS", "B_AXIS_RADIUS", "C_AXIS_RADIUS"))
        stmt = block.get("A_AXIS_RADIUS")
        line = stmt.line if stmt else block.line
        radii = [r for r in (a, b, c) if r is not None]
        if any(r <= 0 for r in radii):
            yield Hit(f"axis radii must be positive, found {radii}", line, "A_AXIS_RADIUS")
        elif a is not None and c is not None and not (a >= (b if b is not None else c) >= c):
            yield Hit(f"radii out of order: A {a} km, B {b} km, C {c} km; expected A >= B >= C",
                      line, "A_AXIS_RADIUS")


def check_last_pixel(ctx: FileContext) -> Iterator[Hit]:
    for block in _maps(ctx):
        for image in ctx.root.walk():
            if not is_image(image):
                continue
            for last, size in (("LINE_LAST_PIXEL", "LINES"), ("SAMPLE_LAST_PIXEL", "LINE_SAMPLES")):
                stmt, expected = block.get(last), image.number(size)
                first = block.number(last.replace("LAST", "FIRST"))
                if stmt is None or expected is None or not stmt.value.is_number:
                    continue
                want = expected + (first - 1 if isinstance(first, int) else 0)
                if stmt.value.py != want:
                    yield Hit(f"{last} = {stmt.value.raw}, expected {want} ({size} = {expected})",
                              stmt.line, last)
            break


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


def check_resolution(ctx: FileContext) -> Iterator[Hit]:
    """MAP_RESOLUTION against MAP_SCALE on the radius the label's arithmetic uses: the
    projection's own radius says nothing; another convention that fits is named in a
    warning (genuine archives use ISIS's local radius; GDAL's PDS driver does not); an
    error only when none fits."""
    for block in _maps(ctx):
        name = normalise(block.text("MAP_PROJECTION_TYPE") or "")
        if name not in SUPPORTED:  # scale and resolution relate by other formulas there
            continue
        res_stmt = block.get("MAP_RESOLUTION")
        res, scale = _num(block, "MAP_RESOLUTION"), _scale_m(block)
        key = projection_radius_key(name)
        conventions = radius_conventions(block, name)
        if res is None or scale is None or not conventions or res <= 0 or scale <= 0:
            continue
        implied = res * scale * 180.0 / math.pi / 1000.0
        tol = 1e-6 + _rel_precision(res_stmt) + _rel_precision(block.get("MAP_SCALE"))
        fits = [r for r in conventions if abs(implied - r.km) <= tol * r.km]
        line = res_stmt.line if res_stmt else block.line
        if fits and fits[0] == conventions[0]:
            continue
        if fits:
            yield Hit(f"MAP_RESOLUTION = {res_stmt.value.raw} <PIX/DEG> with MAP_SCALE = {scale!r} m/pixel "  # type: ignore[union-attr]
                      f"uses {fits[0].what} = {fits[0].km:.6f} km, not {conventions[0].what} = "
                      f"{conventions[0].km} km: readers that take {key} (GDAL's PDS driver) put the "
                      "map's latitudes and longitudes on that sphere instead", line, "MAP_RESOLUTION",
                      severity="warning")
            continue
        radius = conventions[0].km
        expected = math.pi * radius * 1000.0 / 180.0 / scale
        tried = ", ".join(f"{r.what} {r.km:.6f} km" for r in conventions[1:])
        yield Hit(
            f"MAP_RESOLUTION = {res_stmt.value.raw} <PIX/DEG> with MAP_SCALE = {scale!r} m/pixel "  # type: ignore[union-attr]
            f"implies a radius of {implied:.6f} km, but {key} = {radius} km; expected "
            f"MAP_RESOLUTION = {expected!r}" + (f" (no other radius fits either: {tried})" if tried else ""),
            line,
            "MAP_RESOLUTION",
        )


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


def _radius_fit(ctx: FileContext, block: Block) -> tuple[Geometry, Fit, Fit, str] | None:
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
    fitted = _radius_fit(ctx, block)
    if fitted is None:
        return None
    _, standard, best, _ = fitted
    if standard.consistent:
        return 0.0, 0.0
    if best.consistent and abs(best.shift_sample) == 1 and best.shift_sample == best.shift_line:
        return best.shift_sample, best.shift_line
    return None


def _describe(f: Fit) -> str:
    short = {"MINIMUM_LATITUDE": "S", "MAXIMUM_LATITUDE": "N", "WESTERNMOST_LONGITUDE": "W",
             "EASTERNMOST_LONGITUDE": "E"}
    return ", ".join(f"{short[k]} {v:+.3f} px" for k, v in f.residuals.items())


def _offset_findings(ctx: FileContext) -> list[tuple[str, Hit]]:
    cache = ctx.cache.setdefault("_map_offsets", None)
    if cache is not None:
        return cache
    found: list[tuple[str, Hit]] = []
    # the older convention is HRSC's own (DSMAP.CAT): information there, a warning elsewhere
    hrsc = is_hrsc(ctx)
    old_rule = "MAP-011" if hrsc else "MAP-005"
    old_whose = ", the HRSC archive's own (DSMAP.CAT)" if hrsc else ""
    for block in _maps(ctx):
        fitted = _radius_fit(ctx, block)
        if fitted is None:
            name = block.text("MAP_PROJECTION_TYPE")
            if name is not None:
                found.append(("MAP-009", Hit(f"bounds versus offsets not checked for {name} "
                                             "(no formulas here, rotated, or keywords missing)",
                                             block.line)))
            continue
        geo, standard, best, on = fitted
        stmt = block.get("SAMPLE_PROJECTION_OFFSET")
        line = stmt.line if stmt else block.line
        if standard.consistent:
            found.append(("MAP-004", Hit(f"offsets follow the standard PDS3 convention{on} "
                                         f"(residuals {_describe(standard)})", line)))
        elif best.consistent and abs(best.shift_sample) == 1 and best.shift_sample == best.shift_line:
            found.append((old_rule, Hit(
                f"offsets follow the older one-pixel-apart convention{old_whose}{on}: SAMPLE/LINE_PROJECTION_OFFSET "
                f"are {best.shift_sample:+.0f} px from the standard values {geo.spo - best.shift_sample!r}"
                f" / {geo.lpo - best.shift_line!r}; GDAL reads this 1 px off", line,
                "SAMPLE_PROJECTION_OFFSET")))
        elif best.consistent:
            what = "centre/corner confusion" if 0.5 in (abs(best.shift_sample), abs(best.shift_line)) \
                else "mixed conventions"
            if best.shift_sample == 0:  # only the line offset is off: point at it
                stmt = block.get("LINE_PROJECTION_OFFSET") or stmt
                line = stmt.line if stmt else block.line
            found.append(("MAP-003", Hit(
                f"offsets disagree with the latitude/longitude bounds by {best.shift_sample:+g} px "
                f"(samples) and {best.shift_line:+g} px (lines), {what}{on}: expected "
                f"SAMPLE_PROJECTION_OFFSET = {geo.spo - best.shift_sample!r}, LINE_PROJECTION_OFFSET = "
                f"{geo.lpo - best.shift_line!r} (residuals {_describe(standard)})", line,
                "LINE_PROJECTION_OFFSET" if best.shift_sample == 0 else "SAMPLE_PROJECTION_OFFSET")))
        else:
            near = min((fit(geo, d, d) for d in (0.0, 1.0, -1.0)), key=lambda f: f.worst)
            if near.worst <= _NEAR_PX:
                name = "standard" if near.shift_sample == 0 else "older one-pixel-apart"
                rule = "MAP-004" if near.shift_sample == 0 else old_rule
                found.append((rule, Hit(f"offsets follow the {name} convention"
                                        f"{old_whose if rule == old_rule else ''}{on} (residuals "
                                        f"{_describe(near)})", line, "SAMPLE_PROJECTION_OFFSET")))
                found.append(("MAP-010", Hit(
                    f"latitude/longitude bounds are up to {near.worst:.3f} px off the raster edges "
                    f"the offsets define ({name} convention{on}; residuals {_describe(near)})", line,
                    "SAMPLE_PROJECTION_OFFSET")))
            else:
                found.append(("MAP-003", Hit(
                    f"offsets disagree with the latitude/longitude bounds by more than {_NEAR_PX:g} px "
                    f"under either convention{on}: residuals {_describe(standard)} (standard), "
                    f"{_describe(fit(geo, 1.0, 1.0))} (older)", line, "SAMPLE_PROJECTION_OFFSET")))
    ctx.cache["_map_offsets"] = found
    return found


def _offset_rule(rule: str):
    def check(ctx: FileContext) -> Iterator[Hit]:
        for rid, hit in _offset_findings(ctx):
            if rid == rule:
                yield hit

    check.__name__ = f"check_{rule.replace('-', '_').lower()}"
    return check


check_offsets = _offset_rule("MAP-003")
check_convention_standard = _offset_rule("MAP-004")
check_convention_old = _offset_rule("MAP-005")
check_not_checked = _offset_rule("MAP-009")
check_bounds_imprecise = _offset_rule("MAP-010")
check_convention_hrsc = _offset_rule("MAP-011")


register(
    Rule("MAP-001", "error", "IMAGE_MAP_PROJECTION has the keywords a reader needs",
         check_required),
    Rule("MAP-002", "error", "MAP_RESOLUTION = pi R / 180 / MAP_SCALE for the projection's radius",
         check_resolution, note="warning naming the radius when MAP_RESOLUTION fits another "
         "convention: the equatorial, the local radius at CENTER_LATITUDE (ISIS) or the mean radius"),
    Rule("MAP-003", "error", "offsets agree with the latitude/longitude bounds (residual in px)",
         check_offsets),
    Rule("MAP-004", "info", "offset convention detected: standard", check_convention_standard),
    Rule("MAP-005", "warning", "offset convention detected: older one-pixel-apart",
         check_convention_old),
    Rule("MAP-006", "error", "axis radii are positive and A >= B >= C", check_radii),
    Rule("MAP-007", "error", "MAP_PROJECTION_TYPE is a projection GDAL knows",
         check_projection_name, note="warning for a PDS3 projection GDAL does not georeference "
         "(POINT_PERSPECTIVE, ORTHOGRAPHIC ...)"),
    Rule("MAP-008", "error", "LINE/SAMPLE_LAST_PIXEL match the image size", check_last_pixel),
    Rule("MAP-009", "info", "bounds not checked (projection without formulas here)",
         check_not_checked),
    Rule("MAP-010", "warning", "bounds within 1 px of the edges but not exact (imprecise bounds)",
         check_bounds_imprecise),
    Rule("MAP-011", "info", "offset convention detected: older one-pixel-apart, HRSC's own (DSMAP.CAT)",
         check_convention_hrsc),
)
