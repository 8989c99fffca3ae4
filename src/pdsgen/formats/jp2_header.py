"""What decoding a JPEG 2000 file would cost, read from its header before any decoder sees it.

A JP2 file of a few hundred bytes can declare one tile of 10^6 x 10^6 samples; OpenJPEG
allocates a tile (at the resolution asked for) before it finds the data missing, so opening
such a file drives a process to many gigabytes. The main header says what a decoder will
allocate: the tile size and component count (SIZ) and the number of wavelet levels (COD), the
lowest resolution a reader can ask for. A file whose smallest possible decode - one tile at its
lowest resolution - exceeds a memory bound is refused before GDAL opens it.
"""

from __future__ import annotations

import os
import struct

_JP2_SIGNATURE = b"\x00\x00\x00\x0cjP  \r\n\x87\n"
_SOC_SIZ = b"\xff\x4f\xff\x51"
_COD = b"\xff\x52"
_HEADER_READ = 1 << 16  # a main header (SIZ, COD) comes within the first boxes
# OpenJPEG holds a decoded sample as a 32-bit integer, and a tile's wavelet needs about as
# much again; one tile at the lowest resolution over this is no product a reader of it can hold.
BYTES_PER_SAMPLE = 8
MAX_DECODE_BYTES = 512 << 20


def is_jpeg2000(head: bytes) -> bool:
    """True when `head` (a file's first bytes) starts a JP2 file or a raw J2K code stream."""
    return head.startswith((_JP2_SIGNATURE, _SOC_SIZ))


def smallest_decode_bytes(head: bytes) -> int | None:
    """Bytes a decoder needs for one tile at the lowest resolution the code stream offers
    (SIZ's tile size and components, COD's decomposition levels), or None when `head`
    holds no main header to read."""
    start = head.find(_SOC_SIZ)
    if start < 0 or len(head) < start + 42:
        return None
    xsiz, ysiz, xosiz, yosiz, xtsiz, ytsiz = struct.unpack_from(">6I", head, start + 8)
    (components,) = struct.unpack_from(">H", head, start + 40)
    tile_width = min(xtsiz, max(0, xsiz - xosiz)) or xtsiz
    tile_height = min(ytsiz, max(0, ysiz - yosiz)) or ytsiz
    cod = head.find(_COD, start + 4)
    levels = head[cod + 9] if 0 <= cod and cod + 9 < len(head) else 0
    reduced = 1 << min(levels, 32)
    samples = -(-tile_width // reduced) * -(-tile_height // reduced) * max(1, components)
    return samples * BYTES_PER_SAMPLE


def decode_problem(path: str | os.PathLike[str]) -> str | None:
    """Why the JPEG 2000 file at `path` is not decoded (its smallest decode is over the bound),
    or None (not JPEG 2000, no header found, or within the bound)."""
    if not os.path.isfile(path):
        return None  # (a FIFO would block the read) the reader that opens it next refuses it
    try:
        with open(path, "rb") as stream:
            head = stream.read(_HEADER_READ)
    except OSError:
        return None  # the reader that opens it next says what is wrong
    if not is_jpeg2000(head):
        return None
    needed = smallest_decode_bytes(head)
    if needed is None or needed <= MAX_DECODE_BYTES:
        return None
    return (f"its JPEG 2000 header declares tiles that need {needed / 2**30:.1f} GiB to decode at the "
            f"lowest resolution (at most {MAX_DECODE_BYTES >> 20} MiB are decoded)")
