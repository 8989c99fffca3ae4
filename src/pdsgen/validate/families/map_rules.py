"""MAP family: IMAGE_MAP_PROJECTION arithmetic - resolution vs scale vs radius, offsets vs bounds.

The label's latitude/longitude bounds are recomputed from the raster edges that
LINE/SAMPLE_PROJECTION_OFFSET and MAP_SCALE define, and each bound's residual expressed in
pixels, by validate/map_offsets.py (a plain module the migration reads its offset convention
from too). Offsets one pixel apart on both axes are the older convention; half a pixel is
centre/corner confusion; anything else is an error.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from ...label.tree import Block
from ..context import FileContext
from ..map_offsets import Fit, fit, radius_conventions, radius_fit, rel_precision
from ..model import Hit
from ..profiles import is_hrsc
from ..projection import GDAL_PROJECTIONS, SUPPORTED, normalise, projection_radius_key
from ..quantities import is_image
from ..quantities import kilometres as _km
from ..quantities import metres_per_pixel as _scale_m
from ..quantities import number as _num
from ..registry import Rule, register

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
_NEAR_PX = 1.0  # beyond this the bounds and offsets describe different rasters


def _maps(ctx: FileContext) -> Iterator[Block]:
    yield from ctx.root.find("IMAGE_MAP_PROJECTION")


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
        tol = 1e-6 + rel_precision(res_stmt) + rel_precision(block.get("MAP_SCALE"))
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
        fitted = radius_fit(ctx, block)
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
