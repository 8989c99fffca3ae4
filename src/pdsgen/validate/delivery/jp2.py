"""JPEG 2000 facts the delivery checks compare: JP2INFO.TXT's entries and a JP2's header."""

from __future__ import annotations

import re
from pathlib import Path

from ...bounded import text_lines
from ...errors import InputError

# --- JP2INFO.TXT and the quick look against the JPEG 2000 files they describe (DLV-025, DLV-026) ---
# JP2INFO.TXT (written by `pdsgen ortho` beside its JP2s, formats/jp2.describe_jp2) states each
# JP2's size, bands and bit depth; an Extras quick look (<ID>.QLOOK.JP2) is its orthoimage at full
# scale. A product remade at another size with its old JP2INFO.TXT or its old quick look kept
# ships parts that describe another image. Both are read against the JP2 header (ihdr) through
# the validator's own box walk (validate/geojp2.read_jp2), never a general JP2 reader.

_JP2INFO_IMAGE = re.compile(r"^\s+Image:\s+(\d+) samples x (\d+) lines, (\d+) band\(s\), (\d+) bits")


def jp2info_entries(path: Path) -> dict[str, tuple[int, int, int, int, int]]:
    """JP2INFO.TXT's entries as pdsgen writes them: file name (upper case) -> (samples, lines,
    bands, bits, line of the Image: line). A JP2INFO.TXT of another writer (HiRISE's is a general
    text) has none, and nothing is compared."""
    try:
        lines = text_lines(path, "JP2INFO.TXT")
    except InputError:
        return {}
    entries: dict[str, tuple[int, int, int, int, int]] = {}
    name = ""
    for number, line in enumerate(lines, 1):
        if line and not line[0].isspace() and " " not in line.strip() and line.strip().upper().endswith(".JP2"):
            name = line.strip().upper()
        elif name and (match := _JP2INFO_IMAGE.match(line)) is not None:
            samples, rows, bands, bits = (int(group) for group in match.groups())
            entries[name] = (samples, rows, bands, bits, number)
    return entries


def jp2_header(path: Path) -> tuple[int, int, int, int] | None:
    """(samples, lines, bands, bits) of a JP2's header, or None for a file that is none (the
    image rules say why)."""
    from ..geojp2 import Jp2Error, read_jp2

    try:
        info = read_jp2(path)
    except Jp2Error:
        return None
    return info.width, info.height, info.bands, info.bits


def shape(values: tuple[int, int, int, int]) -> str:
    samples, lines, bands, bits = values
    return f"{samples} samples x {lines} lines, {bands} band(s), {bits} bits"

