"""Where each input of a mosaic lies on the output grid, decided as gdal_merge.py decides it.

The output grid is the union of the inputs' extents with the first input's pixel size
(gdal_merge.py: upper-left the smallest x and largest y, size rounded to whole pixels);
each input's target and source windows use gdal_merge.py's own rounding (`+ 0.1` for an
offset, `+ 0.5` for an edge), so a mosaic made here is pixel for pixel the one
`gdal_merge.py -n ND -a_nodata ND -init ND` makes from the same inputs in the same order.

Nothing is read but headers: the checks that refuse a mosaic (one CRS, one kind, one
sample encoding, aligned grids) run before any output exists.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from affine import Affine
from rasterio.crs import CRS

from ..errors import InputError, ParamsError, param
from ..formats.raster import open_raster

ORDERS = ("given", "reverse")
# A grid whose origin lies within this fraction of a pixel of the first input's grid is
# aligned to it (floating-point noise in georeferencing); anything more is a different grid.
ALIGNMENT_TOLERANCE = 1e-3
# The methods a GDAL VRT source resamples with (its `resampling` attribute), in GDAL's spelling.
RESAMPLING_METHODS = ("nearest", "bilinear", "cubic", "cubicspline", "lanczos", "average", "mode")


@dataclass(frozen=True)
class MosaicInput:
    """One input raster as the mosaic needs it: its grid, sample type and identity."""

    path: Path
    product_id: str
    kind: str  # "dtm" or "ortho", as `pdsgen dtm` / `pdsgen ortho` decide it
    crs: CRS
    transform: Affine
    width: int
    height: int
    dtype: str
    band_count: int
    nodata: float | None
    scale: float
    offset: float
    shown: str = ""  # the file a message names (a tile's own file, not the VRT read for it)

    @property
    def name(self) -> str:
        return self.shown or str(self.path)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(ulx, uly, lrx, lry) as gdal_merge.py computes them."""
        t = self.transform
        return t.c, t.f, t.c + t.a * self.width, t.f + t.e * self.height


@dataclass(frozen=True)
class Window2:
    """A pixel window: column and line offset, width and height (floats only when resampling)."""

    x: float
    y: float
    width: float
    height: float


@dataclass(frozen=True)
class Placement:
    """Which part of an input (source) goes where on the output grid (target)."""

    source: MosaicInput
    source_window: Window2
    target_window: Window2


@dataclass(frozen=True)
class MosaicPlan:
    """The output grid and the inputs placed on it, bottom first."""

    crs: CRS
    transform: Affine
    width: int
    height: int
    dtype: str
    band_count: int
    kind: str
    scale: float
    offset: float
    placements: tuple[Placement, ...]
    resampling: str | None  # a GDAL method name when the user asked for resampling

    @property
    def inputs(self) -> tuple[MosaicInput, ...]:
        return tuple(p.source for p in self.placements)


def describe_input(path: str | os.PathLike[str], kind: str | None = None, shown: str = "") -> MosaicInput:
    """An input's header facts; InputError naming it when GDAL cannot read it."""
    from ..extras.product_source import open_product  # the one DTM/orthoimage decision

    with open_raster(path) as dataset:  # the one-line refusal of an unreadable file
        facts = (dataset.crs, dataset.transform, dataset.width, dataset.height, dataset.dtypes[0],
                 dataset.count, dataset.nodata, float(dataset.scales[0]), float(dataset.offsets[0]))
        tagged_id = dataset.tags().get("PRODUCT_ID", "").strip()  # an iMars strip's GeoTIFF names itself
    source = open_product(path, kind)
    crs, transform, width, height, dtype, count, nodata, scale, offset = facts
    product_id = source.product_id if source.label_path is not None or not tagged_id else tagged_id
    if crs is None or transform.is_identity:
        raise InputError(path, "has no map projection; a mosaic places inputs by their georeferencing")
    if transform.b or transform.d:
        raise InputError(path, "has a rotated grid; a mosaic needs north-up grids")
    return MosaicInput(Path(path), product_id, source.kind, crs, transform, width, height, dtype, count,
                       nodata, scale, offset, shown)


def plan_mosaic(inputs: Sequence[MosaicInput], order: str = "given", resampling: str | None = None) -> MosaicPlan:
    """The output grid and placements; a one-line error for inputs that cannot be mosaicked."""
    if not inputs:
        raise ParamsError(None, "a mosaic needs at least one input")
    if order not in ORDERS:
        raise ParamsError(None, f"{param('order')} must be one of {', '.join(ORDERS)}")
    if resampling is not None and resampling not in RESAMPLING_METHODS:
        raise ParamsError(None, f"{param('resampling')} must be a GDAL method: {', '.join(RESAMPLING_METHODS)}")
    stack = list(inputs) if order == "given" else list(reversed(inputs))
    first = stack[0]
    for other in stack[1:]:
        _check_same_kind(first, other)
        if resampling is None:
            _check_aligned(first, other)
    ulx = min(i.bounds[0] for i in stack)
    uly = max(i.bounds[1] for i in stack)
    lrx = max(i.bounds[2] for i in stack)
    lry = min(i.bounds[3] for i in stack)
    psize_x, psize_y = first.transform.a, first.transform.e
    width = int((lrx - ulx) / psize_x + 0.5)
    height = int((lry - uly) / psize_y + 0.5)
    transform = Affine(psize_x, 0.0, ulx, 0.0, psize_y, uly)
    placements = []
    for source in stack:
        placement = (_placed(source, transform, width, height) if resampling is None
                     else _resampled(source, transform, width, height))
        if placement is not None:
            placements.append(placement)
    return MosaicPlan(first.crs, transform, width, height, first.dtype, first.band_count, first.kind,
                      first.scale, first.offset, tuple(placements), resampling)


def _check_same_kind(first: MosaicInput, other: MosaicInput) -> None:
    pair = f"{first.name} and {other.name}"
    if other.kind != first.kind:
        raise InputError(other.name, f"is {_kind_name(other.kind)} but {first.name} is {_kind_name(first.kind)}; "
                                     "a mosaic is of one kind")
    if other.crs != first.crs:
        raise InputError(other.name, f"has a different CRS from {first.name}; reproject one of {pair} first")
    if other.band_count != first.band_count:
        raise InputError(other.name, f"has {other.band_count} band(s), {first.name} {first.band_count}")
    if (other.scale, other.offset) != (first.scale, first.offset):
        raise InputError(other.name, f"stores values as DN * {other.scale:g} + {other.offset:g}, "
                                     f"{first.name} as DN * {first.scale:g} + {first.offset:g}; "
                                     "a mosaic copies DNs, so they must agree")


def _kind_name(kind: str) -> str:
    return "a DTM" if kind == "dtm" else "an orthoimage"


def _check_aligned(first: MosaicInput, other: MosaicInput) -> None:
    """Same pixel size, origins a whole number of pixels apart; otherwise a one-line refusal."""
    a, b = first.transform, other.transform
    how = f"use {param('resampling', 'nearest')} (or another GDAL method) to resample"
    if not (math.isclose(a.a, b.a, rel_tol=1e-9) and math.isclose(a.e, b.e, rel_tol=1e-9)):
        raise InputError(other.name, f"has pixels of {abs(b.a):g} x {abs(b.e):g}, {first.name} "
                                     f"{abs(a.a):g} x {abs(a.e):g}: grids differ; {how}")
    for shift, size in ((b.c - a.c, a.a), (b.f - a.f, a.e)):
        pixels = shift / size
        if abs(pixels - round(pixels)) > ALIGNMENT_TOLERANCE:
            raise InputError(other.name, f"is not aligned to the grid of {first.name} "
                                         f"(offset by {pixels - math.floor(pixels):.3f} pixel); {how}")


def _placed(source: MosaicInput, grid: Affine, width: int, height: int) -> Placement | None:
    """gdal_merge.py's windows: the overlap of the input with the output, rounded as it rounds."""
    ulx, uly, lrx, lry = source.bounds
    t_ulx, t_uly = grid.c, grid.f
    t_lrx, t_lry = grid.c + width * grid.a, grid.f + height * grid.e
    x0, x1 = max(t_ulx, ulx), min(t_lrx, lrx)
    y0, y1 = (min(t_uly, uly), max(t_lry, lry)) if grid.e < 0 else (max(t_uly, uly), min(t_lry, lry))
    if x0 >= x1 or (grid.e < 0 and y0 <= y1) or (grid.e > 0 and y0 >= y1):
        return None
    target = _merge_window(grid, x0, y0, x1, y1)
    own = _merge_window(source.transform, x0, y0, x1, y1)
    if min(target.width, target.height, own.width, own.height) < 1:
        return None
    return Placement(source, own, target)


def _merge_window(t: Affine, x0: float, y0: float, x1: float, y1: float) -> Window2:
    xoff = int((x0 - t.c) / t.a + 0.1)
    yoff = int((y0 - t.f) / t.e + 0.1)
    return Window2(xoff, yoff, int((x1 - t.c) / t.a + 0.5) - xoff, int((y1 - t.f) / t.e + 0.5) - yoff)


def _resampled(source: MosaicInput, grid: Affine, width: int, height: int) -> Placement:
    """The whole input at its exact (fractional) place on the output grid, for GDAL to resample."""
    col, row = ~grid * (source.transform.c, source.transform.f)
    cols = source.width * source.transform.a / grid.a
    rows = source.height * source.transform.e / grid.e
    return Placement(source, Window2(0, 0, source.width, source.height), Window2(col, row, cols, rows))


def source_ids(plan: MosaicPlan) -> tuple[str, ...]:
    """The source products' IDs, each once, in the mosaic's order."""
    return tuple(dict.fromkeys(i.product_id for i in plan.inputs))
