"""A VICAR2 label, written into a PDS3 file between the PDS label and the image (as
DLR's HRSC products carry one), so that VICAR tools and GDAL's VICAR driver read the
image without the PDS label.

VICAR labels are `KEY=VALUE` items separated by spaces, starting with `LBLSIZE`, the
label's length in bytes, a whole number of image records (RECSIZE). The items here
describe an uncompressed band-sequential image: FORMAT (BYTE, HALF, FULL, REAL),
TYPE, ORG, NL/NS/NB (and N1/N2/N3), no binary prefixes (NBB, NLB = 0), no end-of-file
label (EOL = 0), and the byte order of integers (INTFMT HIGH = big-endian, LOW =
little-endian) and reals (REALFMT IEEE = big-endian, RIEEE = little-endian).
"""

from __future__ import annotations

import math

import numpy as np

# numpy sample kind and size -> VICAR FORMAT
_FORMATS = {("u", 1): "BYTE", ("i", 2): "HALF", ("i", 4): "FULL", ("f", 4): "REAL", ("f", 8): "DOUB"}


def vicar_label(dtype: np.dtype, lines: int, samples: int, bands: int, record_bytes: int,
                big_endian: bool) -> bytes:
    """The VICAR label of a band-sequential image, padded with spaces to whole records."""
    dtype = np.dtype(dtype)
    try:
        vicar_format = _FORMATS[(dtype.kind, dtype.itemsize)]
    except KeyError:
        raise ValueError(f"VICAR has no FORMAT for {dtype}") from None
    if record_bytes != samples * dtype.itemsize:
        raise ValueError("a VICAR record is one image line of one band")
    items = [
        ("FORMAT", f"'{vicar_format}'"), ("TYPE", "'IMAGE'"), ("BUFSIZ", str(record_bytes)),
        ("DIM", "3"), ("EOL", "0"), ("RECSIZE", str(record_bytes)), ("ORG", "'BSQ'"),
        ("NL", str(lines)), ("NS", str(samples)), ("NB", str(bands)),
        ("N1", str(samples)), ("N2", str(lines)), ("N3", str(bands)), ("N4", "0"),
        ("NBB", "0"), ("NLB", "0"), ("HOST", "'JAVA'" if big_endian else "'X86-LINUX'"),
        ("INTFMT", "'HIGH'" if big_endian else "'LOW'"),
        ("REALFMT", "'IEEE'" if big_endian else "'RIEEE'"),
        ("BHOST", "'JAVA'" if big_endian else "'X86-LINUX'"),
        ("BINTFMT", "'HIGH'" if big_endian else "'LOW'"),
        ("BREALFMT", "'IEEE'" if big_endian else "'RIEEE'"),
        ("BLTYPE", "''"),
    ]
    body = "  ".join(f"{key}={value}" for key, value in items)
    # LBLSIZE's own digits are part of the label: grow until the record count is stable.
    size = record_bytes
    while True:
        text = f"LBLSIZE={size:<10d}{body}"
        needed = math.ceil(len(text) / record_bytes) * record_bytes
        if needed == size:
            return text.encode("ascii").ljust(size, b" ")
        size = needed
