"""Encode a lossless JPEG 2000 (JP2) file, every core busy, one row of tiles in memory.

The code stream is laid out for archive readers that decode a region or a
reduced resolution: reversible 5/3 wavelet (lossless), tiles, several
resolution levels, RPCL progression, precincts, PLT (packet lengths) in every
tile-part header and TLM (tile-part lengths) in the main header. Code blocks use
selective arithmetic-coding bypass (BYPASS, a JPEG 2000 Part 1 mode every
decoder handles): lossless files no larger, a fifth to a third less encoding CPU.
`Jp2Settings` holds every one of these choices; the encoder and JP2INFO.TXT
(`describe_jp2`) both read them from there.

Tiles are coded independently in JPEG 2000, so each tile is encoded by its own
single-threaded OpenJPEG encoder, several at once (one per core), while another
thread reads and converts the next row of tiles: no core waits for a tile row to
finish. Each tile's encoder writes a one-tile code stream whose tile-part is
taken as it is (only its tile index changes): tile sizes are powers of two at
least 2^levels, so a tile's wavelet, precinct and code-block partitions are the
same whether it sits at the image origin or inside the whole image. This module writes the JP2
boxes, the main header (SIZ, COD, QCD, TLM) and the tile-parts in order itself,
with the GeoJP2/GMLJP2 boxes in place, so the file is written once.
"""

from __future__ import annotations

import math
import os
import re
import struct
import tempfile
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import numpy as np

from ..bounded import checked_count
from ..errors import InputError, PdsgenError
from ..progress import advance, is_large
from ..storage.staging import InterruptSafeExecutor

TILE_SIZE = 512  # an OpenJPEG tile encoder needs ~17 bytes per tile pixel; 512 keeps memory low
CODE_BLOCK = (64, 64)
PRECINCT = 256  # at every resolution: region decoding needs only nearby packets
OVERVIEW_SIDE = 256  # the lowest resolution level is about this size or smaller
MIN_LOWEST_TILE = 16  # smallest tile side at the lowest resolution level
QUALITY_LAYERS = 1  # one layer holding every coding pass: nothing to truncate in a lossless archive

# Code-block style flags (ISO/IEC 15444-1 Table A.19, SPcod/SPcoc "code-block style").
CODE_BLOCK_STYLES = {
    "BYPASS": 0x01,  # selective arithmetic-coding bypass
    "RESET": 0x02,  # reset context probabilities on coding pass boundaries
    "RESTART": 0x04,  # termination on each coding pass
    "VSC": 0x08,  # vertically causal context
    "ERTERM": 0x10,  # predictable termination
    "SEGMARK": 0x20,  # segmentation symbols
}

MAX_TILES = 65535  # a tile-part header's tile index (Isot) is 16 bits
_TLM_PER_SEGMENT = (65535 - 4) // 6  # Ttlm 16 bits + Ptlm 32 bits per tile-part

# Code-stream markers (ISO/IEC 15444-1 Annex A).
_SOC, _SIZ, _SOT, _TLM, _EOC = b"\xff\x4f", b"\xff\x51", b"\xff\x90", b"\xff\x55", b"\xff\xd9"
_GREY, _SRGB = 17, 16  # colr box enumerated colour spaces

# Reads one row of tiles: (first line, number of lines) -> array (lines, samples[, bands]).
TileRowReader = Callable[[int, int], np.ndarray]


@dataclass(frozen=True)
class Jp2Settings:
    """Every encoding choice of one JP2: what the encoder does and JP2INFO.TXT states."""

    tile_shape: tuple[int, int]  # (rows, columns)
    resolutions: int  # resolution levels = decomposition levels + 1
    code_block: tuple[int, int]  # (rows, columns)
    precincts: tuple[tuple[int, int], ...]  # (rows, columns) per resolution, lowest first
    progression: str = "RPCL"
    code_block_style: tuple[str, ...] = ("BYPASS",)
    reversible: bool = True  # 5/3 wavelet, integer: lossless
    compression_ratio: float = 0  # 0: every coding pass kept; N: each tile cut to 1/N of its size (lossy)
    plt: bool = True
    tlm: bool = True

    @property
    def code_block_flags(self) -> int:
        return sum(CODE_BLOCK_STYLES[name] for name in self.code_block_style)

    def tile_grid(self, lines: int, samples: int) -> tuple[int, int]:
        """(rows, columns) of tiles covering an image."""
        return math.ceil(lines / self.tile_shape[0]), math.ceil(samples / self.tile_shape[1])


def choose_settings(lines: int, samples: int) -> Jp2Settings:
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
    return Jp2Settings(tile, resolutions, block, tuple((side, side) for _ in range(resolutions)))


choose_layout = choose_settings  # the former name, kept for callers


def _pow2_floor(value: int, minimum: int) -> int:
    return max(minimum, 1 << max(0, int(value).bit_length() - 1))


def encoder_threads(threads: int | None = None) -> int:
    """How many tiles are encoded at once: `threads`, or every core this process may use."""
    if threads is not None:
        if threads < 1:
            raise ValueError(f"threads must be at least 1, not {threads}")
        return threads
    try:
        return len(os.sched_getaffinity(0)) or 1
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


MIN_OPENJPEG = (2, 4, 0)  # the oldest OpenJPEG whose tile-encoding API glymur drives
OPENJPEG_HINT = ("install OpenJPEG 2.4 or newer "
                 "(Debian/Ubuntu: apt-get install libopenjp2-7; macOS: brew install openjpeg)")


def require_openjpeg() -> None:
    """Refuse before any output exists when OpenJPEG cannot be loaded.

    OpenJPEG is a system library that `pip install` cannot provide; without it
    glymur fails deep inside the encoder, after the output directory was made.
    """
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # glymur warns about the missing library on import
        from glymur.lib import openjp2
    if openjp2.OPENJP2 is None:
        raise PdsgenError(None, f"the OpenJPEG library (libopenjp2) was not found: {OPENJPEG_HINT}")
    found = openjp2.version()
    parts = tuple(int(part) for part in re.findall(r"\d+", found)[:3])
    if parts < MIN_OPENJPEG:
        raise PdsgenError(None, f"OpenJPEG {found} is too old (2.4.0 or newer is needed): {OPENJPEG_HINT}")


# -- one tile -> one tile-part ------------------------------------------------------


class _TileEncoder:
    """Encodes single tiles with OpenJPEG into tile-parts of the whole image's code stream.

    OpenJPEG is called through glymur's ctypes bindings (ctypes releases the GIL,
    so encoders in several threads run in parallel). Each tile becomes a one-tile
    J2K code stream in a scratch file, from which the main-header segments (once)
    and the tile-part are taken.
    """

    def __init__(self, settings: Jp2Settings, bands: int, precision: int, scratch: Path) -> None:
        from glymur.lib import openjp2  # lazy: only encoding needs OpenJPEG

        self.opj = openjp2
        self.settings = settings
        self.bands = bands
        self.precision = precision
        self.scratch = scratch
        self.sample_dtype = np.dtype(np.uint8 if precision <= 8 else np.uint16)

    def _parameters(self):
        opj, s = self.opj, self.settings
        cparams = opj.set_default_encoder_parameters()
        cparams.codec_fmt = opj.CODEC_J2K
        cparams.irreversible = 0 if s.reversible else 1
        cparams.tcp_numlayers = QUALITY_LAYERS
        cparams.tcp_rates[0] = s.compression_ratio  # 0: no rate limit, every coding pass is kept
        cparams.cp_disto_alloc = 1
        cparams.numresolution = s.resolutions
        cparams.cblockh_init, cparams.cblockw_init = s.code_block
        cparams.mode = s.code_block_flags
        cparams.prog_order = ("LRCP", "RLCP", "RPCL", "PCRL", "CPRL").index(s.progression)
        cparams.csty |= 0x01  # user-defined precincts
        cparams.res_spec = len(s.precincts)
        for level, (rows, cols) in enumerate(reversed(s.precincts)):  # OpenJPEG lists highest first
            cparams.prch_init[level], cparams.prcw_init[level] = rows, cols
        cparams.tile_size_on = 1
        cparams.cp_tdy, cparams.cp_tdx = s.tile_shape
        cparams.tcp_mct = 1 if self.bands >= 3 else 0
        return cparams

    def encode(self, index: int, tile: np.ndarray) -> bytes:
        """The J2K code stream of `tile` (bands, rows, columns) as a one-tile image."""
        opj = self.opj
        _, rows, cols = tile.shape
        components = (opj.ImageComptParmType * self.bands)()
        for component in components:
            component.dx = component.dy = 1
            component.w, component.h = cols, rows
            component.x0 = component.y0 = 0
            component.prec = component.bpp = self.precision
            component.sgnd = 0
        colour = opj.CLRSPC_SRGB if self.bands >= 3 else opj.CLRSPC_GRAY
        image = opj.image_tile_create(components, colour)
        image.contents.x0 = image.contents.y0 = 0
        image.contents.x1, image.contents.y1 = cols, rows
        codec = opj.create_compress(opj.CODEC_J2K)
        path = self.scratch / f"{index}.j2k"
        stream = None
        try:
            opj.set_error_handler(codec, opj._ERROR_CALLBACK)
            opj.setup_encoder(codec, self._parameters(), image)
            opj.encoder_set_extra_options(codec, plt=self.settings.plt)  # TLM: written by _CodeStreamWriter
            opj.codec_set_threads(codec, 0)  # no worker threads: tiles run in parallel instead
            stream = opj.stream_create_default_file_stream(str(path), False)
            opj.start_compress(codec, image, stream)
            opj.write_tile(codec, 0, np.ascontiguousarray(tile, dtype=self.sample_dtype), stream)
            opj.end_compress(codec, stream)
        finally:
            if stream is not None:
                opj.stream_destroy(stream)
            opj.destroy_codec(codec)
            opj.image_destroy(image)
        try:
            return path.read_bytes()
        finally:
            path.unlink(missing_ok=True)


def _split(codestream: bytes) -> tuple[list[tuple[bytes, bytes]], bytes]:
    """A one-tile code stream's main-header segments (marker, whole segment) and its tile-part."""
    if codestream[:2] != _SOC:
        raise RuntimeError("OpenJPEG did not write a JPEG 2000 code stream")
    segments, position = [], 2
    while codestream[position:position + 2] != _SOT:
        marker = codestream[position:position + 2]
        (length,) = struct.unpack(">H", codestream[position + 2:position + 4])
        segments.append((marker, codestream[position:position + 2 + length]))
        position += 2 + length
    end = len(codestream) - 2 if codestream.endswith(_EOC) else len(codestream)
    part = codestream[position:end]
    _, _, _, length, part_index, parts = struct.unpack(">2sHHIBB", part[:12])
    if length != len(part) or part_index != 0 or parts not in (0, 1):
        raise RuntimeError("OpenJPEG wrote a tile in several tile-parts")
    return segments, part


def _tlm_segments(lengths: Sequence[int]) -> bytes:
    """TLM marker segments: tile index (16 bits) and length (32 bits) of every tile-part."""
    out = bytearray()
    for number, first in enumerate(range(0, len(lengths), _TLM_PER_SEGMENT)):
        chunk = lengths[first:first + _TLM_PER_SEGMENT]
        out += _TLM + struct.pack(">HBB", 4 + 6 * len(chunk), number, 0x60)  # ST=2, SP=1
        for offset, length in enumerate(chunk):
            out += struct.pack(">HI", first + offset, length)
    return bytes(out)


# -- JP2 boxes ----------------------------------------------------------------------


def box(kind: bytes, payload: bytes) -> bytes:
    """One JP2 box: length, four-character type, payload."""
    if len(kind) != 4:
        raise ValueError("box types have four characters")
    if len(payload) + 8 < 2**32:
        return struct.pack(">I4s", len(payload) + 8, kind) + payload
    return struct.pack(">I4sQ", 1, kind, len(payload) + 16) + payload


def _jp2_header(lines: int, samples: int, bands: int, precision: int) -> bytes:
    """Signature, file type and JP2 header (image header + colour specification) boxes."""
    signature = box(b"jP  ", b"\r\n\x87\n")
    file_type = box(b"ftyp", b"jp2 " + struct.pack(">I", 0) + b"jp2 ")
    image_header = box(b"ihdr", struct.pack(">IIHBBBB", lines, samples, bands, precision - 1, 7, 0, 0))
    colour = box(b"colr", struct.pack(">BBBI", 1, 0, 0, _SRGB if bands >= 3 else _GREY))
    return signature + file_type + box(b"jp2h", image_header + colour)


def jp2_boxes(path: str | os.PathLike[str]) -> list[tuple[bytes, int, int]]:
    """Top-level boxes of a JP2 file: (type, offset, total length)."""
    boxes = []
    size = os.path.getsize(path)
    with open(path, "rb") as handle:
        offset = 0
        while offset < size:
            handle.seek(offset)
            header = handle.read(8)
            if len(header) < 8:
                raise InputError(path, f"a JP2 box at byte {offset} is cut short")
            length, kind = struct.unpack(">I4s", header)
            header_bytes = 8
            if length == 1:
                extended = handle.read(8)
                length, header_bytes = (struct.unpack(">Q", extended)[0] if len(extended) == 8 else 0), 16
            elif length == 0:
                length = size - offset
            if length < header_bytes:
                raise InputError(path, f"the JP2 box at byte {offset} declares {length} bytes, less than its header")
            checked_count(path, f"the JP2 {kind.decode('latin-1')!r} box at byte {offset}", length, 1, size - offset)
            boxes.append((kind, offset, length))
            offset += length
    return boxes


# -- the whole image ----------------------------------------------------------------


def _tiles_of(row: np.ndarray, bands: int, tile_cols: int) -> Iterator[np.ndarray]:
    """(bands, rows, columns) views of each tile in a row of tiles."""
    planes = row[np.newaxis] if bands == 1 else np.moveaxis(row, -1, 0)
    for start in range(0, planes.shape[2], tile_cols):
        yield planes[:, :, start:start + tile_cols]


class _CodeStreamWriter:
    """Writes the code stream into the open JP2 file as tile-parts arrive, in tile order.

    The main header is tile 0's with the whole image's size in SIZ; every other
    tile must have been coded with the same parameters (COD, QCD ...), or the
    tile-parts would not belong to one code stream.
    """

    def __init__(self, handle: BinaryIO, settings: Jp2Settings, lines: int, samples: int, tiles: int) -> None:
        self.handle = handle
        self.settings = settings
        self.lines, self.samples = lines, samples
        self.tiles = tiles
        self.lengths: list[int] = []
        self.coding: list[bytes] = []
        self.tlm_at = -1

    def add(self, index: int, codestream: bytes) -> None:
        segments, part = _split(codestream)
        coding = [segment for marker, segment in segments if marker not in (_SIZ, _TLM)]
        if index == 0:
            self._write_main_header(segments)
            self.coding = coding
        elif coding != self.coding:
            raise RuntimeError(f"JPEG 2000 tile {index} was coded with other parameters than tile 0")
        self.lengths.append(len(part))
        self.handle.write(part[:4] + struct.pack(">H", index) + part[6:])  # Isot: the tile's index

    def _write_main_header(self, segments: list[tuple[bytes, bytes]]) -> None:
        self.handle.write(_SOC)
        for marker, segment in segments:
            if marker == _SIZ:  # Xsiz, Ysiz: the whole image, not the one tile
                segment = segment[:6] + struct.pack(">II", self.samples, self.lines) + segment[14:]
            if marker != _TLM:
                self.handle.write(segment)
        if self.settings.tlm:  # room now, lengths filled in at the end
            self.tlm_at = self.handle.tell()
            self.handle.write(_tlm_segments([0] * self.tiles))

    def finish(self) -> None:
        self.handle.write(_EOC)
        if self.tlm_at >= 0:
            end = self.handle.tell()
            self.handle.seek(self.tlm_at)
            self.handle.write(_tlm_segments(self.lengths))
            self.handle.seek(end)


def check_tiling(settings: Jp2Settings, lines: int, samples: int) -> None:
    """Refuse tilings whose tiles would not code alone as they do in place.

    Along an axis with several tiles, the tile size must be a power of two and at
    least 2^(decomposition levels): then each tile's origin is aligned to the
    wavelet's sample parity at every level and to every (power-of-two) precinct
    and code-block partition.
    """
    levels = settings.resolutions - 1
    for size, extent in zip(settings.tile_shape, (lines, samples), strict=True):
        if size < extent and (size & (size - 1) or size < (1 << levels)):
            raise ValueError(f"tile size {size} must be a power of two of at least {1 << levels} "
                             f"for {levels} decomposition levels")


def encode_jp2(
    handle: BinaryIO,
    lines: int,
    samples: int,
    bands: int,
    precision: int,
    read_tile_row: TileRowReader,
    settings: Jp2Settings,
    scratch: Path,
    threads: int | None = None,
) -> None:
    """Write the code stream of the whole image into `handle`, pulling one row of tiles at a time.

    One thread reads and converts the next row of tiles while `threads` encoders
    work through the tiles queued so far; tile-parts are written in tile order as
    they complete. The next row is read once half of the current row's tiles are
    encoded, and its tiles are queued when no more than one tile per encoder is
    left: reading a row takes a few per cent of the time its tiles take to encode,
    so encoders never wait. A row's tiles are views of it, so it lives until its last
    tile is encoded: at most two rows are held, and for images narrower than two tiles
    per encoder, the rows of the (at most `threads`) tiles still queued besides.
    """
    tile_rows, tile_cols = settings.tile_shape
    grid_rows, grid_cols = settings.tile_grid(lines, samples)
    if grid_rows * grid_cols > MAX_TILES:
        raise ValueError(f"{lines} x {samples} needs {grid_rows * grid_cols} tiles; JPEG 2000 allows {MAX_TILES}")
    encoder = _TileEncoder(settings, bands, precision, scratch)
    writer = _CodeStreamWriter(handle, settings, lines, samples, grid_rows * grid_cols)
    large = is_large(lines * samples)

    def add(index: int, codestream: bytes) -> None:
        writer.add(index, codestream)
        if large:
            advance(index + 1, grid_rows * grid_cols, "tiles")

    def read_row(row: int) -> np.ndarray:
        first = row * tile_rows
        return read_tile_row(first, min(tile_rows, lines - first))

    pending: deque[tuple[int, Future[bytes]]] = deque()

    def write_until(left: int) -> None:
        """Write finished tile-parts, in tile order, until `left` tiles are still queued."""
        while len(pending) > left:
            index, future = pending.popleft()
            add(index, future.result())

    workers = encoder_threads(threads)
    with InterruptSafeExecutor(1, "pdsgen-read") as reader, \
            InterruptSafeExecutor(workers, "pdsgen-jp2") as encoders:
        next_row = reader.submit(read_row, 0)
        read_ahead = max(workers, grid_cols // 2)  # tiles left when the next row is read
        try:
            for row in range(grid_rows):
                data = next_row.result()
                for col, tile in enumerate(_tiles_of(data, bands, tile_cols)):
                    index = row * grid_cols + col
                    pending.append((index, encoders.submit(encoder.encode, index, tile)))
                del data
                write_until(read_ahead)
                if row + 1 < grid_rows:
                    next_row = reader.submit(read_row, row + 1)
                write_until(workers)  # queue the next row while every encoder is still busy
            write_until(0)
        except BaseException:
            for _, future in pending:
                future.cancel()
            next_row.cancel()
            raise
    writer.finish()


def write_jp2(
    path: str | os.PathLike[str],
    lines: int,
    samples: int,
    bands: int,
    precision: int,
    read_tile_row: TileRowReader,
    extra_boxes: Sequence[bytes] = (),
    *,
    settings: Jp2Settings | None = None,
    threads: int | None = None,
) -> Jp2Settings:
    """Write a JP2 at `path`: header boxes, `extra_boxes` (GeoJP2 ...), code stream.

    Lossless unless `settings` say otherwise (`reversible=False`, `compression_ratio`).

    `threads` limits how many tiles are encoded at once (default: every core).
    """
    if bands not in (1, 3):
        raise ValueError(f"a JP2 orthoimage has 1 or 3 bands, not {bands}")
    if not 1 <= precision <= 16:
        raise ValueError(f"precision must be 1 to 16 bits, not {precision}")
    settings = settings or choose_settings(lines, samples)
    check_tiling(settings, lines, samples)  # arguments are checked before any file is created
    threads = encoder_threads(threads)
    path = Path(path)
    # Tiles' one-tile code streams pass through local scratch files (one per encoder at a
    # time), not the output directory, which may be a slow network file system.
    with tempfile.TemporaryDirectory(prefix="pdsgen-jp2-") as scratch, \
            open(path, "wb") as handle:
        handle.write(_jp2_header(lines, samples, bands, precision))
        for payload in extra_boxes:
            handle.write(payload)
        code_box = handle.tell()
        handle.write(struct.pack(">I4s", 0, b"jp2c"))  # length 0: to the end of the file, set below
        encode_jp2(handle, lines, samples, bands, precision, read_tile_row, settings, Path(scratch), threads)
        length = handle.tell() - code_box
        if length < 2**32:
            handle.seek(code_box)
            handle.write(struct.pack(">I", length))
    return settings


# -- JP2INFO.TXT: the encoding facts, for readers of the archive ----------------------

JP2INFO_NAME = "JP2INFO.TXT"
_PROGRESSIONS = {
    "LRCP": "layer, resolution, component, position",
    "RLCP": "resolution, layer, component, position",
    "RPCL": "resolution, position, component, layer",
    "PCRL": "position, component, resolution, layer",
    "CPRL": "component, position, resolution, layer",
}
_STYLE_MEANINGS = {
    "BYPASS": "selective arithmetic-coding bypass",
    "RESET": "context reset on each coding pass",
    "RESTART": "termination on each coding pass",
    "VSC": "vertically causal context",
    "ERTERM": "predictable termination",
    "SEGMARK": "segmentation symbols",
}
_JP2INFO_HEAD = (
    "JP2INFO.TXT - how the JPEG 2000 files in this directory are encoded",
    "",
    "Each .JP2 file below is a JP2 file (ISO/IEC 15444-1:2004, JPEG 2000 Part 1)",
    "written by pdsgen; its detached PDS3 label (.LBL) points here with",
    "^DESCRIPTION in its COMPRESSED_FILE object. Every feature used belongs to",
    "Part 1, so any JPEG 2000 decoder reads the files (OpenJPEG, Kakadu, GDAL,",
    "glymur, Pillow). Lossless files decode to exactly the DNs the label describes.",
    "",
)


def describe_jp2(
    name: str, settings: Jp2Settings, lines: int, samples: int, bands: int, precision: int,
    geo_boxes: Sequence[str] = (),
) -> list[str]:
    """JP2INFO.TXT's entry for one file: every encoding fact a reader may need, from `settings`."""
    grid_rows, grid_cols = settings.tile_grid(lines, samples)
    cb_rows, cb_cols = settings.code_block
    styles = ", ".join(f"{style} ({_STYLE_MEANINGS[style]})" for style in settings.code_block_style)
    precincts = sorted(set(settings.precincts))
    entry = [
        name,
        f"  Image:              {samples} samples x {lines} lines, {bands} band(s), "
        f"{precision} bits unsigned",
        "  Compression:        " + ("lossless, reversible 5/3 integer wavelet" if settings.reversible
                                    else "lossy, irreversible 9/7 wavelet")
        + (f", compression ratio {settings.compression_ratio:g}:1" if settings.compression_ratio else ""),
        f"  Quality layers:     {QUALITY_LAYERS}",
        f"  Progression order:  {settings.progression} ({_PROGRESSIONS[settings.progression]})",
        f"  Tiles:              {settings.tile_shape[1]} x {settings.tile_shape[0]} samples, "
        f"{grid_cols} x {grid_rows} tiles, one tile-part each",
        f"  Resolution levels:  {settings.resolutions} ({settings.resolutions - 1} wavelet decomposition levels)",
        f"  Code blocks:        {cb_cols} x {cb_rows}",
        f"  Code-block style:   {styles or 'none (all passes arithmetic-coded)'}",
        "  Precincts:          " + ", ".join(f"{c} x {r}" for r, c in precincts)
        + (" at every resolution level" if len(precincts) == 1 else ""),
        "  PLT markers:        " + ("yes (packet lengths in each tile-part header)" if settings.plt else "no"),
        "  TLM markers:        " + ("yes (tile-part lengths in the main header)" if settings.tlm else "no"),
        "  Colour transform:   " + ("none" if bands < 3 else "reversible (RCT) across the 3 bands"
                                    if settings.reversible else "irreversible (ICT) across the 3 bands"),
        "  Georeferencing:     " + (" and ".join(f"{kind} box" for kind in geo_boxes) or "none"),
    ]
    return entry


def jp2info_text(previous: str | None, entry: Sequence[str], keep: Callable[[str], bool]) -> bytes:
    """JP2INFO.TXT with `entry` added to (or replacing) the entries of `previous` that `keep` accepts.

    Entries are separated by blank lines and start with the file name; one text
    file serves every product written into the same directory.
    """
    entries = {entry[0]: list(entry)}
    for block in (previous or "").replace("\r\n", "\n").split("\n\n"):
        found = [line for line in block.split("\n") if line]
        if found and _is_entry_name(found[0]) and found[0] not in entries and keep(found[0]):
            entries[found[0]] = found
    lines = list(_JP2INFO_HEAD)
    for name in sorted(entries):
        lines += entries[name] + [""]
    return "\r\n".join(lines).encode("ascii")


def _is_entry_name(line: str) -> bool:
    return not line[:1].isspace() and " " not in line and line.upper().endswith(".JP2")
