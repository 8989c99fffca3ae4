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

from ..formats.raster import bounded_windows, streaming_cache_mb
from .product_source import ProductSource
from .stretch import StreamingStretch, Stretch

STRIP_BYTES = 4 * 1024 * 1024  # DNs read at once, whole block rows (a one-line-block .IMG: many lines)
WINDOW_PIXELS = 1 << 20  # pixels a band read at once, at most


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
    with rasterio.open(src.raster_path) as native:  # the file's own blocks (src.open() may be a VRT)
        windows = list(bounded_windows(native, STRIP_BYTES, WINDOW_PIXELS))
        cache_mb = streaming_cache_mb(native)
    with src.open() as ds, rasterio.Env(GDAL_CACHEMAX=cache_mb):
        for window in windows:
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
