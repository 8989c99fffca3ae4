"""`<ID>.QLOOK.JP2`: the full-scale quick look of an orthoimage, as HiRISE Extras carry.

The quick look is the whole product at full resolution, 8 bits per band, each band
stretched exactly as the browse images are (the same `Stretch`, so browse and
quick look look alike), lossy JPEG 2000 (irreversible 9/7 wavelet at a fixed
compression ratio: a small fraction of the lossless product), with a GeoJP2 box
carrying the product's CRS and geotransform so GIS tools place it like the
product. No-data pixels are 0.

Memory stays flat: the code stream is written tile by tile (the project's JP2
layout from `write_jp2.choose_layout`, its `jp2_boxes` reader, and
`geojp2_box`), and each tile is read from the product as one window of that
tile's size; GDAL's block cache holds two block rows of the product, so a
strip-organised source is not decoded again for every tile. The project's JP2
writer encodes losslessly only (it has no compression-ratio setting), so this
thin wrapper sets up the lossy encoding with glymur's tile writers and adds the
GeoJP2 box after the JP2 header while copying the code stream in chunks.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path

import glymur
import numpy as np
import rasterio
from rasterio.windows import Window

from ..formats.geojp2 import geojp2_box
from ..formats.jp2 import choose_layout, jp2_boxes
from ..formats.raster import streaming_cache_mb
from .product_source import ProductSource
from .stretch import Stretch

# Compression ratio against 8-bit samples (0.4 bits per band sample): small, and
# still sharp enough to judge an image at full scale.
QLOOK_RATIO = 20
_COPY_CHUNK = 8 * 1024 * 1024


def write_qlook(src: ProductSource, stretches: Sequence[Stretch | None],
                path: str | os.PathLike[str]) -> None:
    """Write SRC's quick look at PATH (a temporary name the caller publishes)."""
    path = Path(path)
    bands = [1, 2, 3] if src.band_count >= 3 else [1]
    layout = choose_layout(src.height, src.width)
    fd, scratch_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".jp2", dir=path.parent)
    os.close(fd)
    scratch = Path(scratch_name)
    scratch.unlink()  # glymur writes a new file only
    try:
        with src.open() as ds, rasterio.Env(GDAL_CACHEMAX=streaming_cache_mb(ds)):
            def tile(top: int, left: int, rows: int, cols: int) -> np.ndarray:
                return _stretched(ds, src, bands, stretches, Window(left, top, cols, rows))

            _encode(scratch, src.height, src.width, len(bands), layout.tile_shape,
                    layout.resolutions, tile)
        _copy_with_box(scratch, path, geojp2_box(src.crs, src.transform))
    finally:
        scratch.unlink(missing_ok=True)


def _encode(path: Path, lines: int, samples: int, bands: int, tile_shape: tuple[int, int],
            resolutions: int, tile) -> None:
    """Lossy JP2, one tile at a time in row-major order (glymur's tile writers)."""
    glymur.set_option("lib.num_threads", os.cpu_count() or 1)
    options = dict(numres=resolutions, cratios=(QLOOK_RATIO,), irreversible=True, plt=True,
                   prog="RPCL", colorspace="gray" if bands == 1 else "rgb", mct=bands == 3)
    rows, cols = tile_shape
    if (rows, cols) == (lines, samples):  # glymur refuses tile writers for a single tile
        glymur.Jp2k(str(path), data=tile(0, 0, lines, samples), **options)
        return
    shape = (lines, samples) if bands == 1 else (lines, samples, bands)
    writer = glymur.Jp2k(str(path), shape=shape, tilesize=tile_shape, **options)
    columns = math.ceil(samples / cols)
    for index, tile_writer in enumerate(writer.get_tilewriters()):
        row, col = divmod(index, columns)
        top, left = row * rows, col * cols
        tile_writer[:] = tile(top, left, min(rows, lines - top), min(cols, samples - left))


def _copy_with_box(encoded: Path, final: Path, extra: bytes) -> None:
    """Copy ENCODED to FINAL with EXTRA (a whole box) right after the JP2 header box."""
    boxes = jp2_boxes(encoded)
    kinds = [kind for kind, _, _ in boxes]
    if b"jp2h" not in kinds:
        raise RuntimeError(f"{encoded} is not a JP2 file with a header box")
    with open(encoded, "rb") as source, open(final, "wb") as target:
        for kind, offset, length in boxes:
            source.seek(offset)
            while length:
                chunk = source.read(min(_COPY_CHUNK, length))
                if not chunk:
                    raise RuntimeError(f"{encoded} ends inside a box")
                target.write(chunk)
                length -= len(chunk)
            if kind == b"jp2h":
                target.write(extra)


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
