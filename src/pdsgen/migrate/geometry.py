"""cart:Cartography of a migrated map product, from its IMAGE_MAP_PROJECTION.

Nothing is derived here: the label's projection becomes a CRS and geotransform through
the project's label georeferencing (the standard PDS3 offset convention, as GDAL reads
it); the offset convention a product family uses is the validator's decision
(`offset_convention_shift`), applied as a whole-pixel shift; and the cart: values come
from the same geometry code as pdsgen's own PDS4 products (`describe_geometry`,
`cartography`).
"""

from __future__ import annotations

from affine import Affine
from rasterio.crs import CRS

from ..errors import PdsgenError
from ..geo.conventions import FULL_TURN, east_positive, wrap_360
from ..geo.geometry import describe_geometry
from ..geo.label_georef import LabelGeorefError, label_georeferencing
from ..label.mapping import BlockView, units_as_quantities
from ..label.tree import Block
from ..pds4.label import Cartography, cartography
from ..validate.context import FileContext
from ..validate.map_offsets import offset_convention_shift
from .objects import Refused


def migrated_cartography(ctx: FileContext, lines: int, samples: int, target: str) -> Cartography | None:
    """cart: values of the label's map projection, or None when it has none."""
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
    # Bounds the validator found consistent with the offsets are the label's to state.
    bounds = stated_bounds(block) if shift is not None else None
    return _cartography(ctx, crs, transform, lines, samples, target, bounds)


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


def _cartography(ctx: FileContext, crs: CRS, transform: Affine, lines: int, samples: int, target: str,
                 bounds: tuple[float, float, float, float] | None) -> Cartography:
    try:
        geometry = describe_geometry(crs, transform, samples, lines, str(ctx.path), bounds)
    except PdsgenError as exc:
        raise Refused(ctx.path, f"map projection: {exc.problem}") from None
    return cartography(geometry, crs, transform, target)
