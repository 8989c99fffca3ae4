"""HRSC family: Mars Express HRSC level-4 labels agree with their own conventions.

The `MEX:DTM` group repeats, for HRSC's tools, what the IMAGE object says for everyone
else (missing DN, scaling, offset) and names the height reference (pds3-products.md
section 7): DT4 heights above the 3396.0 km sphere (group radii 3396.0, "HEIGHT ABOVE
SPHEROID"), DA4 heights above the GM3 areoid (radii -1e+32, "HEIGHT ABOVE
GM3-AREOID"). Non-DTM products (ND4, IR4 ...) fill the group with N/A and -1e+32
placeholders, which are not compared. The map itself is on the 3396.0 km sphere,
sinusoidal within +-85 degrees of the equator and polar stereographic poleward.

Real HRSC archive labels may leave MISSING_CONSTANT, SCALING_FACTOR or OFFSET out of
the IMAGE object (HRSC's own readers take them from the group); only values given in
both places are compared.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from ...label.grammar import PLACEHOLDERS
from ...label.tree import Block, Statement
from ...missions.hrsc import AREOID_DESC, NOT_APPLICABLE, POLAR_LIMIT_DEG, SPHERE_DESC, SPHERE_KM
from ..context import FileContext
from ..map_offsets import geometry
from ..model import Hit
from ..profiles import hrsc_kind, is_hrsc
from ..projection import normalise
from ..quantities import is_image
from ..quantities import kilometres as _km
from ..registry import Rule, register

HRSC_SPHERE_KM = SPHERE_KM
NOT_SET = NOT_APPLICABLE  # HRSC's "not applicable" number
_DESC_BY_KIND = {"dt4": SPHERE_DESC, "da4": AREOID_DESC}
_PLACEHOLDERS = PLACEHOLDERS | {""}


def _group(ctx: FileContext) -> Block | None:
    if not is_hrsc(ctx):
        return None
    return next(ctx.root.find("MEX:DTM"), None)


def _image(ctx: FileContext) -> Block | None:
    return next((b for b in ctx.root.walk() if is_image(b)), None)


def _desc(group: Block) -> tuple[str | None, Statement | None]:
    stmt = group.get("MEX:DTM_DESC")
    if stmt is None or stmt.value.items is not None:
        return None, stmt
    return " ".join(stmt.value.text.upper().split()), stmt


def _describes_dtm(group: Block) -> bool:
    desc, _ = _desc(group)
    return desc is not None and desc not in _PLACEHOLDERS


def _same(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-9 * max(1.0, abs(a), abs(b))


def _num(stmt: Statement | None) -> float | None:
    if stmt is None or not stmt.value.is_number:
        return None
    return float(stmt.value.number)


def check_missing_dn(ctx: FileContext) -> Iterator[Hit]:
    """HRSC-001: MEX:DTM_MISSING_DN = the IMAGE's MISSING_CONSTANT."""
    group, image = _group(ctx), _image(ctx)
    if group is None or image is None or not _describes_dtm(group):
        return
    ours, theirs = group.get("MEX:DTM_MISSING_DN"), image.get("MISSING_CONSTANT")
    a, b = _num(ours), _num(theirs)
    if ours is not None and theirs is not None and a is not None and b is not None and not _same(a, b):
        yield Hit(f"MEX:DTM_MISSING_DN = {ours.value.raw} but the IMAGE's MISSING_CONSTANT = "
                  f"{theirs.value.raw} (line {theirs.line}); expected MEX:DTM_MISSING_DN = "
                  f"{theirs.value.raw}", ours.line, "MEX:DTM_MISSING_DN")


def check_scaling(ctx: FileContext) -> Iterator[Hit]:
    """HRSC-002: MEX:DTM_SCALING_FACTOR / MEX:DTM_OFFSET = the IMAGE's SCALING_FACTOR / OFFSET."""
    group, image = _group(ctx), _image(ctx)
    if group is None or image is None or not _describes_dtm(group):
        return
    for key in ("SCALING_FACTOR", "OFFSET"):
        ours, theirs = group.get(f"MEX:DTM_{key}"), image.get(key)
        a, b = _num(ours), _num(theirs)
        if ours is not None and theirs is not None and a is not None and b is not None and not _same(a, b):
            yield Hit(f"MEX:DTM_{key} = {ours.value.raw} but the IMAGE's {key} = {theirs.value.raw} "
                      f"(line {theirs.line}): heights read through the group and through the IMAGE "
                      f"differ; expected MEX:DTM_{key} = {theirs.value.raw}", ours.line,
                      f"MEX:DTM_{key}")


def _radii(group: Block) -> list[tuple[str, float | None]]:
    return [(k, _km(group, f"MEX:DTM_{k}_AXIS_RADIUS")) for k in ("A", "B", "C")]


def check_desc_radii(ctx: FileContext) -> Iterator[Hit]:
    """HRSC-003: MEX:DTM_DESC agrees with the group's radii (3396.0 sphere, -1e+32 areoid)."""
    group = _group(ctx)
    if group is None or not _describes_dtm(group):
        return
    desc, stmt = _desc(group)
    if stmt is None:
        return
    if desc == SPHERE_DESC:
        expected, wanted = HRSC_SPHERE_KM, "3396.0 <KM> (the sphere the heights are above)"
    elif desc == AREOID_DESC:
        expected, wanted = NOT_SET, "-1e+32 <KM> (areoid heights have no sphere)"
    else:
        return
    wrong = [(k, r) for k, r in _radii(group) if r is not None and not _same(r, expected)]
    if wrong:
        found = ", ".join(f"MEX:DTM_{k}_AXIS_RADIUS = {r:g}" for k, r in wrong)
        yield Hit(f"MEX:DTM_DESC = \"{desc}\" but {found}; expected {wanted}", stmt.line,
                  "MEX:DTM_DESC")


def check_desc_file_name(ctx: FileContext) -> Iterator[Hit]:
    """HRSC-004: MEX:DTM_DESC agrees with the file name (_dt4 sphere, _da4 areoid)."""
    group = _group(ctx)
    kind = hrsc_kind(ctx.path.name)
    if group is None or kind is None:
        return
    desc, stmt = _desc(group)
    if desc is None or stmt is None:
        return
    expected = _DESC_BY_KIND.get(kind)
    if expected is not None and desc != expected:
        yield Hit(f"MEX:DTM_DESC = \"{desc}\" but the file name {ctx.path.name} says {kind.upper()} "
                  f"(expected \"{expected}\")", stmt.line, "MEX:DTM_DESC")
    elif expected is None and desc not in _PLACEHOLDERS:
        yield Hit(f"MEX:DTM_DESC = \"{desc}\" describes heights but the file name {ctx.path.name} says "
                  f"{kind.upper()}, not a DTM (DT4 or DA4); expected \"N/A\"", stmt.line,
                  "MEX:DTM_DESC")


def _maps(ctx: FileContext) -> Iterator[Block]:
    if is_hrsc(ctx):
        yield from ctx.root.find("IMAGE_MAP_PROJECTION")


def check_reference_body(ctx: FileContext) -> Iterator[Hit]:
    """HRSC-005: the map reference body is the 3396.0 km sphere (DSMAP.CAT)."""
    for block in _maps(ctx):
        radii = [(k, _km(block, f"{k}_AXIS_RADIUS")) for k in ("A", "B", "C")]
        wrong = [(k, r) for k, r in radii if r is not None and abs(r - HRSC_SPHERE_KM) > 1e-6]
        if wrong:
            stmt = block.get(f"{wrong[0][0]}_AXIS_RADIUS")
            found = ", ".join(f"{k}_AXIS_RADIUS = {r:g} km" for k, r in wrong)
            yield Hit(f"HRSC maps are on the 3396.0 km sphere, found {found}; expected A = B = C = "
                      "3396.0 <KM>", stmt.line if stmt else block.line, f"{wrong[0][0]}_AXIS_RADIUS")


def centre_latitude(ctx: FileContext, block: Block) -> float | None:
    """Planetocentric latitude of the raster's centre: from the offsets and scale where the
    projection has formulas here, else the middle of the label's latitude bounds."""
    geo = geometry(ctx, block)
    if geo is not None:
        x = (geo.samples / 2.0 - geo.spo - 0.5) * geo.scale
        y = (geo.lpo + 0.5 - geo.lines / 2.0) * geo.scale
        lat, _ = geo.sphere.inverse(x, y)
        if math.isfinite(float(lat)):
            return float(lat)
    low, high = block.number("MINIMUM_LATITUDE"), block.number("MAXIMUM_LATITUDE")
    if low is None or high is None:
        return None
    return (float(low) + float(high)) / 2.0


def _single_orbit(ctx: FileContext) -> bool:
    """A per-orbit level-4 product (`hOOOO_NNNN_xx4` by file name or PRODUCT_ID): the
    products DSMAP.CAT's projection rule is for (HRSC's mosaics follow other schemes)."""
    pid = ctx.root.text("PRODUCT_ID") or ""
    return hrsc_kind(ctx.path.name) is not None or hrsc_kind(pid.strip()) is not None


def check_projection_by_latitude(ctx: FileContext) -> Iterator[Hit]:
    """HRSC-006: sinusoidal for centre latitudes within +-85 degrees, polar stereographic poleward."""
    if not _single_orbit(ctx):
        return
    for block in _maps(ctx):
        stmt = block.get("MAP_PROJECTION_TYPE")
        lat = centre_latitude(ctx, block)
        if stmt is None or lat is None:
            continue
        expected = "POLAR_STEREOGRAPHIC" if abs(lat) > POLAR_LIMIT_DEG else "SINUSOIDAL"
        if normalise(stmt.value.text) != expected:
            yield Hit(f"MAP_PROJECTION_TYPE = {stmt.value.raw} at centre latitude {lat:.2f}; HRSC's "
                      f"convention there is {expected.replace('_', ' ')} (sinusoidal within "
                      f"+-{POLAR_LIMIT_DEG:g} deg, polar stereographic poleward)", stmt.line,
                      "MAP_PROJECTION_TYPE")


register(
    Rule("HRSC-001", "error", "MEX:DTM_MISSING_DN equals the IMAGE's MISSING_CONSTANT",
         check_missing_dn),
    Rule("HRSC-002", "error", "MEX:DTM_SCALING_FACTOR/OFFSET equal the IMAGE's SCALING_FACTOR/OFFSET",
         check_scaling),
    Rule("HRSC-003", "error", "MEX:DTM_DESC agrees with the MEX:DTM radii (3396.0 sphere, -1e+32 areoid)",
         check_desc_radii),
    Rule("HRSC-004", "error", "MEX:DTM_DESC agrees with the file name (_dt4 sphere, _da4 areoid)",
         check_desc_file_name),
    Rule("HRSC-005", "error", "the map reference body is the 3396.0 km sphere", check_reference_body),
    Rule("HRSC-006", "warning", "sinusoidal within +-85 deg centre latitude, polar stereographic poleward",
         check_projection_by_latitude),
)
