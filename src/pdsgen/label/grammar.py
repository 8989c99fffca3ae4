"""The PDS3 label grammar facts shared by the label writer and the validator.

One copy of each: the identifier pattern, the line limit, the placeholder
values, the special-constant keywords, the ISIS NULL a float DTM stores for
missing data, and the SAMPLE_TYPE table (with its reverse derived from it).
The validator imports these facts but keeps its own computations.
"""

from __future__ import annotations

import re

# An identifier (keyword, unquoted symbol value): a letter, then letters, digits, '_'.
IDENTIFIER_PATTERN = r"[A-Za-z][A-Za-z0-9_]*"
IDENTIFIER_RE = re.compile(IDENTIFIER_PATTERN)

# Label lines: 7-bit ASCII, CR LF, at most 78 characters before the CR LF (80 bytes in all).
MAX_LINE_CHARS = 78
MAX_LINE_BYTES = MAX_LINE_CHARS + len("\r\n")

# Values that stand for "no value" (PDS3 Standards Reference, section 12.6).
PLACEHOLDERS = frozenset({"N/A", "UNK", "NULL", "UNKNOWN"})

# Keywords whose values mark special pixels rather than data.
SPECIAL_CONSTANTS = (
    "MISSING_CONSTANT",
    "NULL",
    "CORE_NULL",
    "INVALID_CONSTANT",
    "CORE_LOW_REPR_SATURATION",
    "CORE_LOW_INSTR_SATURATION",
    "CORE_HIGH_REPR_SATURATION",
    "CORE_HIGH_INSTR_SATURATION",
)

# The ISIS NULL pixel, 16#FF7FFFFB# (-3.4028226550889045e+38), MISSING_CONSTANT of float DTMs.
ISIS_NULL_BITS = 0xFF7FFFFB

# SAMPLE_TYPE -> (byte order, numpy kind): i signed, u unsigned, f IEEE float.
SAMPLE_TYPES = {
    "MSB_INTEGER": (">", "i"),
    "SUN_INTEGER": (">", "i"),
    "MAC_INTEGER": (">", "i"),
    "INTEGER": (">", "i"),
    "LSB_INTEGER": ("<", "i"),
    "PC_INTEGER": ("<", "i"),
    "VAX_INTEGER": ("<", "i"),
    "MSB_UNSIGNED_INTEGER": (">", "u"),
    "UNSIGNED_INTEGER": (">", "u"),
    "SUN_UNSIGNED_INTEGER": (">", "u"),
    "MAC_UNSIGNED_INTEGER": (">", "u"),
    "LSB_UNSIGNED_INTEGER": ("<", "u"),
    "PC_UNSIGNED_INTEGER": ("<", "u"),
    "VAX_UNSIGNED_INTEGER": ("<", "u"),
    "IEEE_REAL": (">", "f"),
    "FLOAT": (">", "f"),
    "REAL": (">", "f"),
    "SUN_REAL": (">", "f"),
    "MAC_REAL": (">", "f"),
    "PC_REAL": ("<", "f"),
}
# The SAMPLE_TYPE pdsgen writes for each (byte order, kind): the first name of the table that has it.
SAMPLE_TYPE_FOR: dict[tuple[str, str], str] = {}
for _name, _order_kind in SAMPLE_TYPES.items():
    SAMPLE_TYPE_FOR.setdefault(_order_kind, _name)
# Every PDS3 data type name (Standards Reference appendix C): the sample types above, which
# can be read as numbers, and the rest, valid types a reader may not decode.
DATA_TYPES = frozenset(SAMPLE_TYPES) | frozenset({
    "VAX_REAL", "VAXG_REAL", "VAX_DOUBLE", "VAX_COMPLEX", "VAXG_COMPLEX", "VAX_BIT_STRING",
    "IEEE_COMPLEX", "PC_COMPLEX", "MAC_COMPLEX", "SUN_COMPLEX", "COMPLEX", "IBM_INTEGER",
    "IBM_UNSIGNED_INTEGER", "IBM_REAL", "IBM_COMPLEX", "MSB_BIT_STRING", "LSB_BIT_STRING", "BIT_STRING",
    "ASCII_REAL", "ASCII_INTEGER", "ASCII_COMPLEX", "CHARACTER", "EBCDIC_CHARACTER", "BOOLEAN",
    "DATE", "TIME", "DOUBLE", "N/A",
})
FLOAT_SAMPLE_TYPES = frozenset(name for name, (_, kind) in SAMPLE_TYPES.items() if kind == "f")


def sample_type(big_endian: bool, kind: str) -> str:
    """The SAMPLE_TYPE name of samples of numpy `kind` ('i', 'u', 'f') in the given byte order."""
    return SAMPLE_TYPE_FOR[(">" if big_endian else "<", kind)]
