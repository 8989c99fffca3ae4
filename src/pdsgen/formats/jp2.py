"""Encode a lossless JPEG 2000 (JP2) file tile by tile, then add metadata boxes.

OpenJPEG (through glymur's tile writers) encodes one tile at a time, so memory
holds one row of tiles, never the image. The code stream is laid out for
viewers that decode a region or a reduced resolution: reversible 5/3 wavelet,
several resolution levels, RPCL progression, precincts and PLT (packet length)
markers. (glymur's tile writer cannot request TLM markers; tile-part headers
still carry each tile's length, so a reader skips tiles without decoding them.)

OpenJPEG writes the JP2 header itself; the GeoJP2/GMLJP2 boxes must sit
between that header and the code stream, so the encoded file is rewritten
once, box by box, streaming the code stream in chunks.
"""

from __future__ import annotations

import math
import os
import shutil
import struct
import tempfile
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import glymur
import numpy as np

TILE_SIZE = 512  # OpenJPEG needs ~17 bytes per tile pixel: 512 keeps it below GDAL's
CODE_BLOCK = (64, 64)
PRECINCT = 256  # at every resolution: region decoding needs only nearby packets
OVERVIEW_SIDE = 256  # the lowest resolution level is about this size or smaller
MIN_LOWEST_TILE = 16  # smallest tile side at the lowest resolution level
_COPY_CHUNK = 8 * 1024 * 1024

# Reads one row of tiles: (first line, number of lines) -> array (lines, samples[, bands]).
TileRowReader = Callable[[int, int], np.ndarray]


@dataclass(frozen=True)
class Jp2Layout:
    """Code-stream parameters chosen from the image size."""

    tile_shape: tuple[int, int]  # (rows, columns)
    resolutions: int
    code_block: tuple[int, int]
    precincts: tuple[tuple[int, int], ...]
    progression: str = "RPCL"


def choose_layout(lines: int, samples: int) -> Jp2Layout:
    """Tiles of TILE_SIZE (or the image, when smaller) and enough levels for an overview.

    The number of decomposition levels brings the whole image to about
    OVERVIEW_SIDE pixels, limited so that a tile keeps at least MIN_LOWEST_TILE
    pixels a side at its lowest level.
    """
    tile = (min(TILE_SIZE, lines), min(TILE_SIZE, samples))
    wanted = max(0, math.ceil(math.log2(max(lines, samples) / OVERVIEW_SIDE))) if max(lines, samples) > 1 else 0
    allowed = max(0, int(math.floor(math.log2(max(1, min(tile) / MIN_LOWEST_TILE)))))
    levels = max(1, min(wanted, allowed)) if min(tile) >= 2 else 0
    resolutions = levels + 1
    block = (min(CODE_BLOCK[0], _pow2_floor(tile[0], 4)), min(CODE_BLOCK[1], _pow2_floor(tile[1], 4)))
    side = max(PRECINCT, 2 * max(block))
    return Jp2Layout(tile, resolutions, block, tuple((side, side) for _ in range(resolutions)))


def _pow2_floor(value: int, minimum: int) -> int:
    return max(minimum, 1 << max(0, int(value).bit_length() - 1))


class _PrecisionJp2k(glymur.Jp2k):
    """A glymur writer that declares `precision` bits per sample (e.g. 10 in uint16).

    glymur only offers 8 (uint8) or 16 (uint16) bits; OpenJPEG itself encodes
    any precision up to 16 from 16-bit samples, so the component parameters are
    adjusted before the encoder is set up.
    """

    def __init__(self, *args, precision: int, **kwargs) -> None:
        self._precision = precision
        super().__init__(*args, **kwargs)

    def _populate_comptparms(self, img_array):  # glymur hook, called once per file
        super()._populate_comptparms(img_array)
        for component in self._comptparms:
            component.prec = self._precision
            component.bpp = self._precision


def set_encoder_threads(threads: int | None = None) -> None:
    """Let OpenJPEG encode code blocks on every core."""
    glymur.set_option("lib.num_threads", threads or os.cpu_count() or 1)


def encode_jp2(
    path: str | os.PathLike[str],
    lines: int,
    samples: int,
    bands: int,
    precision: int,
    read_tile_row: TileRowReader,
    layout: Jp2Layout | None = None,
) -> Jp2Layout:
    """Write a lossless JP2 at `path`, pulling one row of tiles at a time."""
    layout = layout or choose_layout(lines, samples)
    set_encoder_threads()
    shape = (lines, samples) if bands == 1 else (lines, samples, bands)
    options: dict[str, Any] = dict(
        numres=layout.resolutions,
        cbsize=layout.code_block,
        psizes=list(layout.precincts),
        prog=layout.progression,
        irreversible=False,
        plt=True,
        precision=precision,
        colorspace="gray" if bands < 3 else "rgb",
        mct=bands >= 3,
    )
    tile_rows, tile_cols = layout.tile_shape
    if (tile_rows, tile_cols) == (lines, samples):
        # glymur refuses tile writers for a single tile: the image is one tile's size anyway.
        _PrecisionJp2k(str(path), data=read_tile_row(0, lines), **options)
        return layout
    writer = _PrecisionJp2k(str(path), shape=shape, tilesize=layout.tile_shape, **options)
    columns = math.ceil(samples / tile_cols)
    starts = list(range(0, lines, tile_rows))

    def read_row(row: int) -> np.ndarray:
        return read_tile_row(starts[row], min(tile_rows, lines - starts[row]))

    # The next row of tiles is read (GDAL, numpy: GIL released) while OpenJPEG
    # encodes this one, so reading does not leave the encoder's cores idle.
    # Two rows at most are in memory.
    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="pdsgen-read") as reader:
        pending = reader.submit(read_row, 0)
        row_data: np.ndarray | None = None
        current = -1
        for index, tile_writer in enumerate(writer.get_tilewriters()):
            row, col = divmod(index, columns)
            if row != current:
                row_data = pending.result()
                current = row
                if row + 1 < len(starts):
                    pending = reader.submit(read_row, row + 1)
            assert row_data is not None
            tile_writer[:] = row_data[:, col * tile_cols:(col + 1) * tile_cols]
    return layout


def jp2_boxes(path: str | os.PathLike[str]) -> list[tuple[bytes, int, int]]:
    """Top-level boxes of a JP2 file: (type, offset, total length)."""
    boxes = []
    size = os.path.getsize(path)
    with open(path, "rb") as handle:
        offset = 0
        while offset < size:
            handle.seek(offset)
            length, kind = struct.unpack(">I4s", handle.read(8))
            if length == 1:
                (length,) = struct.unpack(">Q", handle.read(8))
            elif length == 0:
                length = size - offset
            boxes.append((kind, offset, length))
            offset += length
    return boxes


def box(kind: bytes, payload: bytes) -> bytes:
    """One JP2 box: length, four-character type, payload."""
    if len(kind) != 4:
        raise ValueError("box types have four characters")
    if len(payload) + 8 < 2**32:
        return struct.pack(">I4s", len(payload) + 8, kind) + payload
    return struct.pack(">I4sQ", 1, kind, len(payload) + 16) + payload


def insert_boxes(encoded: Path, final: Path, extra: Sequence[bytes]) -> None:
    """Copy `encoded` to `final` with `extra` boxes right after the JP2 header box."""
    boxes = jp2_boxes(encoded)
    kinds = [kind for kind, _, _ in boxes]
    if b"jp2h" not in kinds or b"jp2c" not in kinds:
        raise RuntimeError(f"{encoded} is not a JP2 file with header and code stream")
    after = kinds.index(b"jp2h")
    with open(encoded, "rb") as source, open(final, "wb") as target:
        for position, (_, offset, length) in enumerate(boxes):
            source.seek(offset)
            _copy(source, target, length)
            if position == after:
                for payload in extra:
                    target.write(payload)


def _copy(source, target, length: int) -> None:
    remaining = length
    while remaining:
        chunk = source.read(min(_COPY_CHUNK, remaining))
        if not chunk:
            raise RuntimeError("JP2 file ended inside a box")
        target.write(chunk)
        remaining -= len(chunk)


def write_jp2(
    path: str | os.PathLike[str],
    lines: int,
    samples: int,
    bands: int,
    precision: int,
    read_tile_row: TileRowReader,
    extra_boxes: Sequence[bytes] = (),
) -> Jp2Layout:
    """Encode tile by tile into a scratch file beside `path`, then add `extra_boxes`."""
    path = Path(path)
    fd, scratch = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".jp2", dir=path.parent)
    os.close(fd)
    scratch_path = Path(scratch)
    scratch_path.unlink()  # glymur reads an existing file instead of writing one
    try:
        layout = encode_jp2(scratch_path, lines, samples, bands, precision, read_tile_row)
        if extra_boxes:
            insert_boxes(scratch_path, path, extra_boxes)
        else:
            shutil.move(scratch_path, path)
    finally:
        scratch_path.unlink(missing_ok=True)
    return layout
