"""The per-band stretch of a HiRISE RDR from every pixel, by blocks.

The HiRISE release stretches each band of its colour Extras from the lowest 0.1 %
to the highest 0.01 % of the band's values. A preview-sized sample approximates
those points; an RDR is small enough in DNs (10 bits in 16-bit samples) that the
exact points cost one histogram of 65,536 counts a band, filled from the product
one block row at a time (`StreamingStretch.for_whole_numbers`: one pass, no range
pass), so memory stays flat however large the mosaic is. No-data and the label's
special DNs (CORE_* saturation codes) are left out, as in the sampled statistics.
"""

from __future__ import annotations

import numpy as np
import rasterio
from rasterio.windows import Window

from ..formats.raster import MAX_CACHE_MB, MIN_CACHE_MB
from .product_source import ProductSource
from .stretch import StreamingStretch, Stretch


def streams_whole_numbers(src: ProductSource) -> bool:
    """Integer samples of at most 16 bits: the histogram has one bin per possible DN."""
    dtype = np.dtype(src.dtype)
    return bool(np.issubdtype(dtype, np.integer)) and dtype.itemsize <= 2 and src.scale != 0


def full_resolution_stretches(src: ProductSource, bands: list[int], low_percent: float,
                              high_percent: float) -> tuple[Stretch | None, ...]:
    """Each band's stretch in physical units (DN x scale + offset) over every valid pixel."""
    info = np.iinfo(np.dtype(src.dtype))
    stats = [StreamingStretch.for_whole_numbers(int(info.min), int(info.max)) for _ in bands]
    special = np.array(src.special_dns, dtype=np.float64)
    with rasterio.open(src.raster_path) as native:
        block_rows, block_cols = native.block_shapes[0]
    cache_mb = 2 * block_rows * src.width * np.dtype(src.dtype).itemsize * len(bands) / 2**20
    with src.open() as ds, rasterio.Env(
            GDAL_CACHEMAX=int(min(MAX_CACHE_MB, max(MIN_CACHE_MB, cache_mb + 1)))):
        for top in range(0, src.height, block_rows):
            for left in range(0, src.width, block_cols):
                window = Window(left, top, min(block_cols, src.width - left),
                                min(block_rows, src.height - top))
                dn = ds.read(bands, window=window, masked=True)
                mask = np.ma.getmaskarray(dn)
                for i, stat in enumerate(stats):
                    values = np.ma.getdata(dn)[i][~mask[i]]
                    if special.size:
                        values = values[~np.isin(values, special)]
                    stat.count(values)
    return tuple(_physical(s.stretch(low_percent, high_percent), src) for s in stats)


def _physical(stretch: Stretch | None, src: ProductSource) -> Stretch | None:
    if stretch is None:
        return None
    a, b = (stretch.low * src.scale + src.offset, stretch.high * src.scale + src.offset)
    return Stretch(min(a, b), max(a, b))
