"""A JPEG's size from its frame header, read with a marker walk of its own (the Extras write their
previews with Pillow; the check that they are the size of their product - archive/extras_check,
DLV-027 and deliver's refusal of stale Extras - reads them without it): bounded - at most 256
segments, each skipped by its stated length, never a read past the file."""

from __future__ import annotations

import struct
from pathlib import Path

from ..bounded import open_regular

# Start-of-frame markers (baseline, progressive, lossless ...); C4, C8 and CC are other segments.
_FRAMES = frozenset(range(0xC0, 0xD0)) - {0xC4, 0xC8, 0xCC}
_MAX_SEGMENTS = 256


def jpeg_size(path: Path) -> tuple[int, int] | None:
    """(width, height) a JPEG's frame header states, or None for a file that is no JPEG."""
    try:
        with open_regular(path) as stream:  # the one open of a file a tree holds (no FIFO waited on)
            if stream.read(2) != b"\xff\xd8":
                return None
            for _ in range(_MAX_SEGMENTS):
                marker = stream.read(4)
                if len(marker) < 4 or marker[0] != 0xFF:
                    return None
                kind, length = marker[1], struct.unpack(">H", marker[2:])[0]
                if kind in _FRAMES:
                    frame = stream.read(5)
                    if len(frame) < 5:
                        return None
                    height, width = struct.unpack(">HH", frame[1:])
                    return width, height
                if kind == 0xDA or length < 2:  # the scan begins: no frame header before it
                    return None
                stream.seek(length - 2, 1)
    except OSError:
        return None
    return None
