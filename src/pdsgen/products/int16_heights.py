"""Heights stored as 16-bit integers (HRSC level-4 and iMars DTMs): the encoding, its choice,
and the sphere/areoid datum conversion both writers share.

Physical height (m) = DN * scaling_factor + offset; DN -32767..32767, -32768
(MISSING_DN, missions/hrsc.py) means no data.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np
from rasterio.enums import Resampling
from rasterio.io import DatasetReader
from rasterio.warp import reproject, transform_bounds
from rasterio.windows import Window, from_bounds
from rasterio.windows import transform as window_transform

from ..errors import PdsgenError, param
from ..formats.img import Adjust, BandStatistics
from ..formats.raster import open_raster, require_single_band
from ..missions.hrsc import DN_LIMIT, MISSING_DN, SPHERE_M


@dataclass(frozen=True)
class Int16Encoding:
    """Heights (m) = DN * scaling_factor + offset; DN in -32767..32767."""

    scaling_factor: float
    offset: float

    def encode(self, values: np.ndarray, invalid: np.ndarray | None) -> np.ndarray:
        dn = np.rint((values - np.float32(self.offset)) / np.float32(self.scaling_factor))
        if invalid is not None:
            np.copyto(dn, MISSING_DN, where=invalid)
        return dn.astype(np.int16)


def check_datum_conversion(
    kind: str, output_datum: str, vertical_datum: str, areoid: str | os.PathLike[str] | None
) -> None:
    """A product above one datum from heights above another needs the areoid between them."""
    if vertical_datum not in ("sphere", "areoid"):
        raise PdsgenError(None, f"{param('vertical_datum')} must be sphere or areoid")
    if output_datum != vertical_datum and areoid is None:
        raise PdsgenError(
            None,
            f"{kind.upper()} holds heights above the {output_datum} but the input is above the "
            f"{vertical_datum}: give an areoid raster as {param('areoid')} to convert, "
            f"or {param('vertical_datum', output_datum)}",
        )
    if output_datum == vertical_datum and areoid is not None:
        raise PdsgenError(
            areoid, f"an areoid is only used to convert between datums; the input is already above the {output_datum}"
        )


def choose_encoding(stats: BandStatistics, precision: float, source: str) -> Int16Encoding:
    """Offset 0 when the heights fit, else the range's centre; refuse when they cannot fit,
    or when the precision is so coarse that the heights would collapse to a few values."""
    if not (math.isfinite(precision) and precision > 0):
        raise PdsgenError(None, f"{param('precision')} must be a positive number of metres, got {precision:g}")
    low, high = stats.minimum, stats.maximum
    if high > low and (high - low) / precision < 16:
        raise PdsgenError(
            source,
            f"{param('precision')} {precision:g} m is too coarse for heights {low:g} .. {high:g} m "
            "(fewer than 16 distinct levels)",
        )
    for offset in (0.0, round((low + high) / 2.0 / precision) * precision):
        if (high - offset) / precision <= DN_LIMIT and (low - offset) / precision >= -DN_LIMIT:
            return Int16Encoding(float(precision), float(offset))
    needed = (high - low) / (2 * DN_LIMIT)
    raise PdsgenError(
        source,
        f"heights {low:g} .. {high:g} m do not fit 16-bit samples at {precision:g} m precision "
        f"(needs at least {needed:.3g} m); use a coarser {param('precision')}",
    )


def areoid_adjustment(areoid_path: str | os.PathLike[str] | None, grid: DatasetReader, sign: float) -> Adjust:
    """Add (sign=+1) or subtract (sign=-1) areoid heights resampled onto each strip.

    The areoid grid (heights of the areoid above the 3396.0 km sphere, metres, any
    CRS GDAL knows) is read once, only over the DTM's footprint, and warped onto
    each strip with bilinear interpolation.
    """
    if areoid_path is None:
        raise PdsgenError(None, f"converting between the sphere and the areoid needs {param('areoid')}")
    with open_raster(areoid_path) as areoid:
        require_single_band(areoid, "an areoid grid")
        if areoid.crs is None:
            raise PdsgenError(areoid_path, "areoid grid has no coordinate reference system")
        left, bottom, right, top = transform_bounds(grid.crs, areoid.crs, *grid.bounds, densify_pts=51)
        window = from_bounds(left, bottom, right, top, areoid.transform).round_offsets().round_lengths()
        window = Window(window.col_off - 2, window.row_off - 2, window.width + 5, window.height + 5)
        data = areoid.read(1, window=window, boundless=True, fill_value=np.nan, out_dtype="float64")
        if areoid.nodata is not None:
            data[data == areoid.nodata] = np.nan
        source_transform = window_transform(window, areoid.transform)
        source_crs = areoid.crs
    grid_transform, grid_crs = grid.transform, grid.crs

    def adjust(values: np.ndarray, strip: Window) -> np.ndarray:
        heights = np.full(values.shape, np.nan, dtype=np.float32)
        reproject(
            data, heights, src_transform=source_transform, src_crs=source_crs, src_nodata=np.nan,
            dst_transform=window_transform(strip, grid_transform), dst_crs=grid_crs, dst_nodata=np.nan,
            resampling=Resampling.bilinear,
        )
        return values + np.float32(sign) * heights

    return adjust


def source_body(dataset: DatasetReader) -> tuple[float, float] | None:
    """(a, c) in metres of the reference body the input's heights are measured from:
    the ellipsoid (or sphere) of its CRS. None when the CRS names no body."""
    if dataset.crs is None:
        return None
    from ..geo.geometry import ellipsoid_axes

    return ellipsoid_axes(dataset.crs, str(dataset.name))


def body_radius(a: float, c: float, latitude_deg: np.ndarray) -> np.ndarray:
    """Distance (m) from the centre of an ellipsoid of revolution (axes a, c) to its surface
    at the latitude its CRS uses (geodetic, as PROJ's latitudes on an ellipsoid are):
    R = sqrt(((a^2 cos(lat))^2 + (c^2 sin(lat))^2) / ((a cos(lat))^2 + (c sin(lat))^2))."""
    phi = np.radians(latitude_deg)
    cos, sin = np.cos(phi), np.sin(phi)
    return np.sqrt(((a * a * cos) ** 2 + (c * c * sin) ** 2) / ((a * cos) ** 2 + (c * sin) ** 2))


def sphere_change(body: tuple[float, float], grid: DatasetReader) -> Adjust:
    """Heights above the input's body -> heights above the 3396.0 km sphere, post by post.

    radius = R_in(lat) + h and h' = radius - 3396.0 km, where lat is the latitude of the
    post, which the warp carries over unchanged from the input's CRS. For a sphere input
    the change is the constant R_in - 3396.0 km (190 m from a 3396.19 km sphere).
    """
    a, c = body
    if math.isclose(a, c, rel_tol=0, abs_tol=1e-6):
        constant = np.float32(a - SPHERE_M)
        return lambda values, strip: values + constant
    from rasterio.crs import CRS
    from rasterio.warp import transform as warp_transform

    lonlat = CRS.from_proj4(f"+proj=longlat +R={SPHERE_M:.0f} +no_defs")
    grid_transform, grid_crs = grid.transform, grid.crs

    def adjust(values: np.ndarray, strip: Window) -> np.ndarray:
        rows, cols = np.mgrid[0:values.shape[0], 0:values.shape[1]]
        xs, ys = window_transform(strip, grid_transform) @ (cols.ravel() + 0.5, rows.ravel() + 0.5)
        _, lats = warp_transform(grid_crs, lonlat, xs, ys)
        radius = body_radius(a, c, np.asarray(lats)).reshape(values.shape)
        return values + (radius - SPHERE_M).astype(np.float32)

    return adjust


def chain_adjustments(adjusts: list[Adjust]) -> Adjust | None:
    """One adjustment applying each of `adjusts` in turn (None when there are none)."""
    if not adjusts:
        return None
    if len(adjusts) == 1:
        return adjusts[0]

    def chained(values: np.ndarray, strip: Window) -> np.ndarray:
        for adjust in adjusts:
            values = adjust(values, strip)
        return values

    return chained
