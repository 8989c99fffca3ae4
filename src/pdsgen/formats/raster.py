"""Open input rasters through GDAL and hand them out in row strips.

Every input format GDAL reads (GeoTIFF, ISIS3 cube, PDS3, VICAR, ...) arrives
here; checks that concern the file itself (exists, readable, one band) are made
before any output is created.
"""

from __future__ import annotations

import logging
import math
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import rasterio
from rasterio.errors import RasterioIOError
from rasterio.io import DatasetReader
from rasterio.windows import Window

from ..errors import PdsgenError
from ..storage import display, explain_unreadable, gdal_environment, is_remote, raster_input

STRIP_BYTES = 16 * 1024 * 1024  # working-set size of one strip of input
# GDAL's block cache defaults to 5 % of RAM and would keep every block we stream
# past; we read each block once, so a cache of two block rows keeps memory flat.
# Sizes are in MB: given as a large byte count, GDAL_CACHEMAX was measured to
# leave peak memory higher (e.g. 156 MB against 124 MB on an 8000 x 8000 DTM).
log = logging.getLogger(__name__)  # what was read: shown by `pdsgen ... --verbose`
MIN_CACHE_MB = 4
MAX_CACHE_MB = 64
# GDAL's PDS driver reads a label's objects in time growing with their square (5,000 took 7 s,
# 10,000 27 s, 20,000 two minutes: a 600 kB label); an image label holds tens. A PDS3 label of
# more objects and groups than this is not handed to GDAL (about a second's worth).
MAX_GDAL_LABEL_BLOCKS = 2000


def gdal_label_problem(path: str | os.PathLike[str]) -> str | None:
    """Why GDAL must not be handed PATH, a PDS3 label of more objects and groups than
    MAX_GDAL_LABEL_BLOCKS (read first by pdsgen's own linear reader); None for any other file.
    The one gate before GDAL opens a local file a user or a label named: product inputs
    (open_raster) and the Extras' products."""
    from ..label.parser import LabelFile

    try:
        label = LabelFile.read_pds3(path)
    except (OSError, PdsgenError):
        return None  # GDAL's open, or the caller, says what is wrong with the file
    if label is None:
        return None
    blocks = sum(1 for _ in label.root.walk()) - 1
    if blocks <= MAX_GDAL_LABEL_BLOCKS:
        return None
    return (f"is a PDS3 label of {blocks} objects and groups; more than {MAX_GDAL_LABEL_BLOCKS} are not opened "
            "(GDAL's PDS reader takes time growing with their square)")


@contextmanager
def open_raster(path: str | os.PathLike[str]) -> Iterator[DatasetReader]:
    """Open a raster with GDAL, turning every failure into a one-line PdsgenError.

    An object in a bucket (s3://, /vsis3/) or on the web is read in place by GDAL;
    pdsgen.storage says why one cannot be opened and names it by its URL in messages.
    GDAL's S3 configuration holds while the raster is open (a local VRT's sources may be
    objects too), and only then."""
    with gdal_environment(), _opened_raster(path) as dataset:
        yield dataset


@contextmanager
def _opened_raster(path: str | os.PathLike[str]) -> Iterator[DatasetReader]:
    if is_remote(path):
        path = raster_input(path)
        shown: str | Path = display(path)
    else:
        path = shown = Path(path)
        if not path.exists():
            raise PdsgenError(path, "no such file")
        if path.is_dir():
            raise PdsgenError(path, "is a directory, not a raster file")
        problem = gdal_label_problem(path)
        if problem is not None:
            raise PdsgenError(path, problem)
    try:
        dataset = rasterio.open(path)
    except UnicodeEncodeError:
        raise not_utf8(shown) from None
    except RasterioIOError as exc:
        explain_unreadable(path)  # a missing object or bucket, refused credentials: said as such
        reason = str(exc).splitlines()[0] if str(exc) else "unknown format"
        raise PdsgenError(shown, f"not a raster GDAL can read ({reason})") from None
    log.info("read %s: %d lines x %d samples, %d band(s) of %s, projection %s", path, dataset.height,
             dataset.width, dataset.count, dataset.dtypes[0], _projection_name(dataset))
    with dataset, rasterio.Env(GDAL_CACHEMAX=streaming_cache_mb(dataset)):
        try:
            yield dataset
        except RasterioIOError as exc:
            reason = gdal_reason(exc)
            raise PdsgenError(shown, f"cannot read the raster data; truncated or damaged? (GDAL: {reason})") from None


def not_utf8(path: str | os.PathLike[str]) -> PdsgenError:
    """The refusal of a file whose name holds bytes that are not UTF-8 (a Latin-1 name): rasterio
    hands GDAL names as UTF-8, so such a file cannot be opened - said in one line, not a traceback."""
    return PdsgenError(path, "its name is not UTF-8, which GDAL cannot open; rename it")


@contextmanager
def temporary_vrt(text: str, name: str, shown: str, prefix: str = "pdsgen-") -> Iterator[Path]:
    """The VRT XML `text` as a file `name`.vrt in a private temporary directory, removed afterwards.

    A writer reading it reports problems (no valid pixels, unreadable data) naming the VRT; they
    are the problems of the user's files, so they are reported naming `shown`, never the
    temporary file.
    """
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
        path = Path(tmp) / f"{name}.vrt"
        path.write_text(text, encoding="utf-8")
        try:
            yield path
        except PdsgenError as exc:
            if exc.path is None or Path(exc.path) != path:
                raise
            raise type(exc)(shown, exc.problem) from None


def gdal_reason(exc: BaseException) -> str:
    """GDAL's own words for a failure, without rasterio's "See previous exception" wrapper.

    rasterio chains the GDAL error (e.g. "IReadBlock failed ... TIFFReadEncodedStrip()
    failed": a truncated file) as the cause; that is the part a person can act on.
    """
    cause = exc.__cause__ or exc.__context__ or exc
    text = str(cause.args[-1] if cause.args else cause)
    return text.splitlines()[0] if text else "read failed"


def _projection_name(dataset: DatasetReader) -> str:
    """The PROJ short name (eqc, stere, sinu ...), short enough for a log line."""
    if dataset.crs is None:
        return "none"
    return str(dataset.crs.to_dict().get("proj", "not a PROJ projection"))


def streaming_cache_mb(dataset: DatasetReader) -> int:
    """GDAL block cache (MB) for reading `dataset` once, row of blocks after row of blocks."""
    block_rows = dataset.block_shapes[0][0]
    row_bytes = dataset.width * block_rows * _itemsize(dataset)
    return int(min(MAX_CACHE_MB, max(MIN_CACHE_MB, math.ceil(2 * row_bytes / 2**20))))


def require_single_band(dataset: DatasetReader, what: str = "a DTM") -> None:
    if dataset.count != 1:
        raise PdsgenError(dataset.name, f"has {dataset.count} bands; {what} must have exactly one")


def row_strips(dataset: DatasetReader, strip_bytes: int = STRIP_BYTES) -> Iterator[Window]:
    """Full-width windows of whole block rows, each about `strip_bytes` of input.

    Strips follow the file's own block height so GDAL never decodes a block
    twice, and their size is fixed, so memory does not grow with the raster.
    """
    block_rows = max(1, dataset.block_shapes[0][0])
    itemsize = _itemsize(dataset)
    rows = max(1, strip_bytes // max(1, dataset.width * itemsize))
    rows = max(block_rows, rows - rows % block_rows)
    for row in range(0, dataset.height, rows):
        yield Window(0, row, dataset.width, min(rows, dataset.height - row))


def bounded_windows(dataset: DatasetReader, strip_bytes: int, window_pixels: int) -> Iterator[Window]:
    """row_strips of `strip_bytes`, each cut across into windows of at most `window_pixels`
    that keep to the file's block columns: a wide mosaic is read in bounded pieces, every
    pixel once, and a file of one-line blocks many lines at a time."""
    block_cols = max(1, dataset.block_shapes[0][1])
    for strip in row_strips(dataset, strip_bytes):
        cols = max(1, window_pixels // strip.height)
        cols = max(block_cols, cols - cols % block_cols)
        for left in range(0, dataset.width, cols):
            yield Window(left, strip.row_off, min(cols, dataset.width - left), strip.height)


def _itemsize(dataset: DatasetReader) -> int:
    return max(np.dtype(dt).itemsize for dt in dataset.dtypes) * dataset.count
