"""Read a product at preview size without ever holding the full raster.

Previews come from GDAL decimated reads (`out_shape` with averaging): GDAL walks the
source in chunks, or picks a JPEG 2000 reduced resolution level, and hands back only
the small array, so memory follows the preview size. Averaging (not nearest) keeps
the browse free of aliasing; GDAL leaves no-data pixels out of each average and
marks an output pixel missing only when all of its sources are.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from rasterio.enums import Resampling
from rasterio.windows import Window

from ..formats.preview_size import browse_size
from .product_source import ProductSource

MIN_SAMPLE_VALUES = 1_000_000
MAX_SAMPLE_PIXELS = 16_000_000   # per band: caps memory when valid data is sparse


@dataclass(frozen=True)
class PreviewGrid:
    """A decimated grid over the product: its size and its pixel size in source pixels."""

    width: int
    height: int
    source_width: int
    source_height: int

    @property
    def step_x(self) -> float:
        return self.source_width / self.width

    @property
    def step_y(self) -> float:
        return self.source_height / self.height


def preview_grid(src: ProductSource, max_width: int) -> PreviewGrid:
    """The browse grid: `max_width` wide (never wider than the data), aspect kept."""
    width, height = browse_size(src.width, src.height, max_width)  # the one home of the arithmetic
    return PreviewGrid(width, height, src.width, src.height)


def read_physical(src: ProductSource, grid: PreviewGrid, bands: list[int],
                  resampling: Resampling = Resampling.average) -> np.ma.MaskedArray:
    """Bands at grid size in physical units (DN * scale + offset), no-data masked.

    Special DNs (saturation codes) are masked as well: they are flags, not data.
    """
    with src.open((grid.height, grid.width)) as ds:
        dn = ds.read(bands, out_shape=(len(bands), grid.height, grid.width),
                     resampling=resampling, masked=True)
    mask = np.ma.getmaskarray(dn).copy()
    if resampling == Resampling.nearest:
        for special in src.special_dns:
            mask |= dn.data == special
    values = dn.data.astype(np.float32)
    if src.scale != 1.0 or src.offset != 0.0:
        values = values * np.float32(src.scale) + np.float32(src.offset)
    mask |= ~np.isfinite(values)
    values[mask] = 0.0  # keep the no-data value's huge magnitude out of all arithmetic
    return np.ma.MaskedArray(values, mask=mask)


def statistics_sample(src: ProductSource, browse: np.ma.MaskedArray,
                      bands: list[int]) -> np.ma.MaskedArray:
    """At least 10**6 valid values per band (or the whole raster when it is smaller).

    Pixels next to no-data are left out: averaging (and JPEG 2000 reduced levels,
    which are wavelet approximations) blends them with the no-data value, and
    along a long image edge they are numerous enough to move the 0.1 % point.
    The browse itself is used when it already holds enough; otherwise a denser
    nearest-neighbour sample is read (nearest keeps the tails of the distribution,
    which the percentile stretch depends on), sized by the valid fraction seen in
    the browse and capped at MAX_SAMPLE_PIXELS per band.
    """
    total = src.width * src.height
    valid = int(np.count_nonzero(~np.ma.getmaskarray(browse[0])))
    if valid >= MIN_SAMPLE_VALUES or browse.shape[1] * browse.shape[2] >= total:
        return _interior(browse)
    fraction = max(valid / (browse.shape[1] * browse.shape[2]), 1e-6)
    pixels = min(total, MAX_SAMPLE_PIXELS, math.ceil(1.1 * MIN_SAMPLE_VALUES / fraction))
    factor = math.sqrt(total / pixels)
    width = max(1, min(src.width, math.ceil(src.width / factor)))
    height = max(1, min(src.height, math.ceil(src.height / factor)))
    grid = PreviewGrid(width, height, src.width, src.height)
    return _interior(read_physical(src, grid, bands, Resampling.nearest))


def _interior(data: np.ma.MaskedArray) -> np.ma.MaskedArray:
    """The same data with every pixel that touches a masked pixel masked too."""
    mask = np.ma.getmaskarray(data)
    if not mask.any():
        return data
    grown = mask.copy()
    grown[..., 1:, :] |= mask[..., :-1, :]
    grown[..., :-1, :] |= mask[..., 1:, :]
    grown[..., :, 1:] |= mask[..., :, :-1]
    grown[..., :, :-1] |= mask[..., :, 1:]
    if grown.all():  # tiny or speckled data: keep what there is
        return data
    return np.ma.MaskedArray(np.ma.getdata(data), mask=grown)


def valid_range(src: ProductSource, band: int = 1) -> tuple[float, float] | None:
    """Exact min and max of the valid data in physical units, streamed in strips.

    Used only when the label carries no VALID_MINIMUM/MAXIMUM; memory is one strip
    of about 4 MB whatever the raster size.
    """
    rows = max(1, (4 * 1024 * 1024) // max(1, src.width * 4))
    low, high = math.inf, -math.inf
    with src.open() as ds:
        for top in range(0, src.height, rows):
            window = Window(0, top, src.width, min(rows, src.height - top))
            strip = ds.read(band, window=window, masked=True)
            data = strip.compressed()
            if src.special_dns:
                data = data[~np.isin(data, src.special_dns)]
            if data.size:
                low, high = min(low, float(data.min())), max(high, float(data.max()))
    if low > high:
        return None
    a, b = low * src.scale + src.offset, high * src.scale + src.offset
    return (min(a, b), max(a, b))
