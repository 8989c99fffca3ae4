"""`<ID>.QLOOK.JP2`: the full-scale quick look of an orthoimage, as HiRISE Extras carry.

The quick look is the whole product at full resolution, 8 bits per band, each band
stretched exactly as the browse images are (the same `Stretch`, so browse and
quick look look alike), lossy JPEG 2000 (irreversible 9/7 wavelet at a fixed
compression ratio: a small fraction of the lossless product), with a GeoJP2 box
carrying the product's CRS and geotransform so GIS tools place it like the
product. No-data pixels are 0.

The project's JP2 encoder (`formats.jp2.write_jp2`) writes it: the product's
tiling and resolution levels from `choose_settings`, made lossy by the settings
(`reversible=False`, `compression_ratio`), tiles encoded in parallel, the GeoJP2
box written in place. Memory stays flat in the raster's height: the encoder pulls
one row of tiles at a time, and that row is read from the product one tile-sized
window at a time (the stretch's float temporaries are one tile's); GDAL's block
cache holds two block rows of the product, so a strip-organised source is not
decoded again for every tile.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np
import rasterio
from rasterio.windows import Window

from ..formats.geojp2 import geojp2_box
from ..formats.jp2 import choose_settings, write_jp2
from ..formats.raster import streaming_cache_mb
from .product_source import ProductSource
from .stretch import Stretch

# Compression ratio against 8-bit samples (0.4 bits per band sample): small, and
# still sharp enough to judge an image at full scale.
QLOOK_RATIO = 20


def write_qlook(src: ProductSource, stretches: Sequence[Stretch | None],
                path: str | os.PathLike[str]) -> None:
    """Write SRC's quick look at PATH (a temporary name the caller publishes)."""
    bands = [1, 2, 3] if src.band_count >= 3 else [1]
    settings = replace(choose_settings(src.height, src.width), reversible=False,
                       compression_ratio=QLOOK_RATIO)
    tile_cols = settings.tile_shape[1]
    with src.open() as ds, rasterio.Env(GDAL_CACHEMAX=streaming_cache_mb(ds)):
        def tile_row(first: int, count: int) -> np.ndarray:
            return np.concatenate(
                [_stretched(ds, src, bands, stretches,
                            Window(left, first, min(tile_cols, src.width - left), count))
                 for left in range(0, src.width, tile_cols)], axis=1)

        write_jp2(Path(path), src.height, src.width, len(bands), 8, tile_row,
                  [geojp2_box(src.crs, src.transform)], settings=settings)


def _stretched(ds, src: ProductSource, bands: list[int], stretches: Sequence[Stretch | None],
               window: Window) -> np.ndarray:
    """One window of the product as 8-bit stretched bands (rows, cols[, 3]); no data 0."""
    dn = ds.read(bands, window=window, masked=True)
    mask = np.ma.getmaskarray(dn)
    out = np.zeros(dn.shape, dtype=np.uint8)
    for i, stretch in enumerate(stretches):
        if stretch is None:
            continue
        values = dn.data[i].astype(np.float32)
        if src.scale != 1.0 or src.offset != 0.0:
            values = values * np.float32(src.scale) + np.float32(src.offset)
        invalid = mask[i] | ~np.isfinite(values)
        out[i] = np.where(invalid, 0, stretch.apply(np.where(invalid, 0, values)))
    return out[0] if len(bands) == 1 else np.moveaxis(out, 0, -1)
