"""cart:Cartography of a migrated map product, from its IMAGE_MAP_PROJECTION.

Nothing is derived here: the label's projection becomes a CRS and geotransform through
the project's label georeferencing (the standard PDS3 offset convention, as GDAL reads
it); the offset convention a product family uses is the validator's decision
(`offset_convention_shift`), applied as a whole-pixel shift; and the cart: values come
from the same geometry code as pdsgen's own PDS4 products (`describe_geometry`,
`cartography`).

Two facts are the label's own, not the grid's: the body's radii (cart:a/b/c_axis_radius from
A/B/C_AXIS_RADIUS; the projection itself may be computed on a sphere of one of them, as
PDS3 defines it), and the bounds MINIMUM/MAXIMUM_LATITUDE, WESTERNMOST/EASTERNMOST_LONGITUDE,
which are compared with the grid's own extent: they are stated when they agree within half a
pixel, and where they do not, cart:Bounding_Coordinates follows the grid and a warning says so.
"""

from __future__ import annotations

import math
from dataclasses import replace

from affine import Affine
from rasterio.crs import CRS

from ..errors import PdsgenError
from ..geo.conventions import FULL_TURN, east_positive, is_positive_west, wrap_180, wrap_360
from ..geo.geometry import MapGeometry, describe_geometry
from ..geo.label_georef import LabelGeorefError, label_georeferencing
from ..label.mapping import BlockView, units_as_quantities
from ..label.tree import Block
from ..pds4.label import Cartography, cartography
from ..validate.context import FileContext
from ..validate.map_offsets import offset_convention_shift
from .objects import Refused


def migrated_cartography(ctx: FileContext, lines: int, samples: int, target: str,
                         warnings: list[str] | None = None) -> Cartography | None:
    """cart: values of the label's map projection, or None when it has none. What the cart:
    states other than the label does (bounds) is added to `warnings`."""
    block = ctx.file.projection()
    if block is None:
        return None
    try:
        # The label's text too: a folded Transverse Mercator grid is unfolded from pdsgen's note.
        placed = label_georeferencing({block.name.upper(): BlockView(block, units_as_quantities())},
                                      ctx.head.decode("latin-1"))
    except LabelGeorefError as exc:
        raise Refused(ctx.path, f"OBJECT = {block.name}: {exc}") from None
    if placed is None:
        return None
    crs, transform = placed
    shift = offset_convention_shift(ctx, block) if block.name.upper() == "IMAGE_MAP_PROJECTION" else None
    if shift is not None and shift != (0.0, 0.0):
        transform = shifted(transform, *shift)
    geometry = _geometry(ctx, block, crs, transform, lines, samples, shift is not None, warnings)
    cart = cartography(geometry, crs, transform, target)
    a_axis, b_axis, c_axis = label_radii(block, cart)
    missing = [key for key in ("B_AXIS_RADIUS", "C_AXIS_RADIUS") if _length_m(block, key) is None]
    if missing and warnings is not None:
        warnings.append(f"{ctx.path}: OBJECT = {block.name} states no usable {' or '.join(missing)}: "
                        f"cart:{'/'.join(k[0].lower() for k in missing)}_axis_radius "
                        f"{'are those' if len(missing) > 1 else 'is that'} of the sphere its grid is computed on "
                        "(A_AXIS_RADIUS, C_AXIS_RADIUS for polar stereographic)")
    return replace(cart, a_axis=a_axis, b_axis=b_axis, c_axis=c_axis)


def _geometry(ctx: FileContext, block: Block, crs: CRS, transform: Affine, lines: int, samples: int,
              offsets_checked: bool, warnings: list[str] | None) -> MapGeometry:
    """The grid's geometry, its bounds the label's where they agree with the grid's extent within
    half a pixel (and the validator found the offsets consistent with them); a disagreement is
    a warning and the grid's extent is stated. A grid whose edge passes a pole (a global grid
    whose rounded MAP_SCALE overshoots) has no extent to compare: the label's checked bounds stand."""
    stated = stated_bounds(block)
    try:
        grid = describe_geometry(crs, transform, samples, lines, str(ctx.path))
    except PdsgenError as exc:
        if stated is None or not offsets_checked:
            raise Refused(ctx.path, f"map projection: {exc.problem}") from None
        return _describe(ctx, crs, transform, lines, samples, stated)
    if stated is None:
        return grid
    differences = bounds_differences(block, stated, grid)
    if differences:
        if warnings is not None:
            warnings.append(f"{ctx.path}: OBJECT = {block.name}: the label's bounds disagree with the grid's extent "
                            f"by more than half a pixel ({'; '.join(differences)}): "
                            "cart:Bounding_Coordinates follows the grid")
        return grid
    if not offsets_checked:
        return grid
    south, north, west, east = stated
    return replace(grid, minimum_latitude=south, maximum_latitude=north, westernmost_longitude=west,
                   easternmost_longitude=east)


def bounds_differences(block: Block, stated: tuple[float, float, float, float], grid: MapGeometry) -> list[str]:
    """Each bound of the label more than half a pixel from the grid's extent, said as the label
    writes it and as the grid has it (east longitudes); empty when they agree. Longitudes are
    compared as angles (0..360 and -180..180 alike); a full turn matches a full turn."""
    south, north, west, east = stated
    half = 0.5 / grid.map_resolution  # degrees of latitude in half a pixel
    nearest = 0.0 if grid.minimum_latitude <= 0.0 <= grid.maximum_latitude else \
        min(abs(grid.minimum_latitude), abs(grid.maximum_latitude))
    parallel = grid.center_latitude if grid.projection_type == "EQUIRECTANGULAR" else nearest
    half_lon = half / max(math.cos(math.radians(parallel)), 1e-6)
    found = [f"{key} = {_written(block, key)} (grid: {value:.6g})"
             for key, said, value in (("MINIMUM_LATITUDE", south, grid.minimum_latitude),
                                      ("MAXIMUM_LATITUDE", north, grid.maximum_latitude))
             if abs(said - value) > half]
    grid_full = grid.easternmost_longitude - grid.westernmost_longitude >= FULL_TURN - half_lon
    stated_full = abs(east - west) >= FULL_TURN - half_lon
    if grid_full and stated_full:
        return found
    pairs = (("WESTERNMOST_LONGITUDE", west, grid.westernmost_longitude),
             ("EASTERNMOST_LONGITUDE", east, grid.easternmost_longitude))
    lon = [f"{key} = {_written(block, key)} ({wrap_360(said):.6g} east; grid: {value:.6g} east)"
           for key, said, value in pairs if grid_full != stated_full or abs(wrap_180(said - value)) > half_lon]
    if lon and not grid_full and not stated_full and is_positive_west(block.text("POSITIVE_LONGITUDE_DIRECTION")) \
            and all(abs(wrap_180(said - value)) <= half_lon for said, value in ((east, grid.westernmost_longitude),
                                                                                (west, grid.easternmost_longitude))):
        lon.append("the two longitudes are the grid's edges swapped: WESTERNMOST_LONGITUDE is its eastern edge "
                   "(west longitudes given as minimum and maximum)")
    return found + lon


def _written(block: Block, key: str) -> str:
    value = block.value(key)
    return value.raw if value is not None else "?"


def label_radii(block: Block, cart: Cartography) -> tuple[float, float, float]:
    """cart:a/b/c_axis_radius (metres) from the label's own A/B/C_AXIS_RADIUS: a body's radii are
    the label's fact (a Mars product stating C_AXIS_RADIUS = 3376.8 km is stated so, though its
    equirectangular grid is computed on the sphere of A_AXIS_RADIUS). A radius the label does not
    give keeps the one its projection is computed on (label_georef: A_AXIS_RADIUS, C_AXIS_RADIUS
    for polar stereographic). A grid computed on a sphere that is not the label's (Magellan MIDRs:
    the data set's own equations) keeps that sphere: its pixel scale is that sphere's."""
    radii = {"a_axis": cart.a_axis, "b_axis": cart.b_axis, "c_axis": cart.c_axis}
    stated = {field: _length_m(block, key) for key, field in
              (("A_AXIS_RADIUS", "a_axis"), ("B_AXIS_RADIUS", "b_axis"), ("C_AXIS_RADIUS", "c_axis"))}
    grid_axis = "c_axis" if cart.projection_name == "Polar Stereographic" else "a_axis"
    on_grid = stated[grid_axis]
    if on_grid is None or math.isclose(on_grid, radii[grid_axis], rel_tol=1e-9):
        radii.update({field: metres for field, metres in stated.items() if metres is not None})
    return radii["a_axis"], radii["b_axis"], radii["c_axis"]


def _length_m(block: Block, key: str) -> float | None:
    """A length keyword in metres, read as label georeferencing reads radii: kilometres when the
    unit is <KM> or absent, metres with any other unit; None when absent or not a positive number."""
    value = block.value(key)
    if value is None or not value.is_number:
        return None
    unit = (value.unit or "KM").strip().upper()
    metres = float(value.number) * (1000.0 if unit in ("KM", "KILOMETER", "KILOMETERS", "KILOMETRE",
                                                         "KILOMETRES") else 1.0)
    return metres if math.isfinite(metres) and metres > 0 else None


def stated_bounds(block: Block) -> tuple[float, float, float, float] | None:
    """(south, north, west, east) as the label states them, longitudes east-positive."""
    values = [block.number(key) for key in ("MINIMUM_LATITUDE", "MAXIMUM_LATITUDE",
                                            "WESTERNMOST_LONGITUDE", "EASTERNMOST_LONGITUDE")]
    if any(v is None for v in values):
        return None
    south, north, west, east = (float(v) for v in values)  # type: ignore[arg-type]
    direction = block.text("POSITIVE_LONGITUDE_DIRECTION")
    west, east = east_positive(west, direction), east_positive(east, direction)
    if abs(east - west) < FULL_TURN:
        west, east = wrap_360(west), wrap_360(east)
    return south, north, west, east


def shifted(transform: Affine, shift_sample: float, shift_line: float) -> Affine:
    """The grid of offsets `shift` pixels less than written (the older convention's correction)."""
    return Affine(transform.a, transform.b, transform.c + shift_sample * transform.a,
                  transform.d, transform.e, transform.f + shift_line * transform.e)


def _describe(ctx: FileContext, crs: CRS, transform: Affine, lines: int, samples: int,
              bounds: tuple[float, float, float, float]) -> MapGeometry:
    try:
        return describe_geometry(crs, transform, samples, lines, str(ctx.path), bounds)
    except PdsgenError as exc:
        raise Refused(ctx.path, f"map projection: {exc.problem}") from None
