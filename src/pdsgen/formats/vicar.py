"""A VICAR2 label, written into a PDS3 file between the PDS label and the image (as
DLR's HRSC products carry one), so that VICAR tools and GDAL's VICAR driver read the
image without the PDS label.

VICAR labels are `KEY=VALUE` items separated by spaces, starting with `LBLSIZE`, the
label's length in bytes, a whole number of image records (RECSIZE). The items here
describe an uncompressed band-sequential image: FORMAT (BYTE, HALF, FULL, REAL),
TYPE, ORG, NL/NS/NB (and N1/N2/N3), no binary prefixes (NBB, NLB = 0), no end-of-file
label (EOL = 0), and the byte order of integers (INTFMT HIGH = big-endian, LOW =
little-endian) and reals (REALFMT IEEE = big-endian, RIEEE = little-endian).

`read_vicar_label` reads such a label back, with its property groups (`PROPERTY='MAP'`,
`PROPERTY='DIGITAL_TERRAIN_MODEL'` ...: every item after a PROPERTY item belongs to
that group until the next PROPERTY or TASK item), and where the image's bytes are.
pdsgen reads the map and terrain-model groups itself: GDAL's VICAR reader ignores
some of their keywords (SCALE_FACTOR) and knows few projections. `read_map_group` turns
a MAP group into numbers in the label's own units and counting (`VicarMap`, defined in
geo/label_georef.py beside `vicar_map_georeferencing`, which says what they mean on the
ground: the CRS and grid).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..bounded import checked_count, file_size
from ..errors import InputError
from ..geo.label_georef import VicarMap

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


VicarValue = int | float | str | tuple["int | float | str", ...]
# numpy type of each FORMAT, before the byte order is applied
_NUMPY_KINDS = {"BYTE": "u1", "HALF": "i2", "FULL": "i4", "REAL": "f4", "DOUB": "f8", "WORD": "i2", "LONG": "i4"}
_ITEM_RE = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*=\s*")
_NUMBER_RE = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?")
_HEAD_BYTES = 64


@dataclass(frozen=True)
class VicarLabel:
    """A VICAR image's system items, property groups and the layout of its pixels."""

    path: Path
    system: dict[str, VicarValue]
    properties: dict[str, dict[str, VicarValue]] = field(default_factory=dict)

    def group(self, name: str) -> dict[str, VicarValue] | None:
        return self.properties.get(name.upper())

    @property
    def format(self) -> str:
        return str(self.system.get("FORMAT", "BYTE")).upper()

    @property
    def lines(self) -> int:
        return int(self.system["NL"])  # type: ignore[arg-type]

    @property
    def samples(self) -> int:
        return int(self.system["NS"])  # type: ignore[arg-type]

    @property
    def bands(self) -> int:
        return int(self.system.get("NB", 1))  # type: ignore[arg-type]

    @property
    def dtype(self) -> np.dtype:
        """The samples' numpy type, byte order included (INTFMT for integers, REALFMT for reals)."""
        kind = _NUMPY_KINDS[self.format]
        if kind == "u1":
            return np.dtype(kind)
        if kind.startswith("f"):
            big = self.real_format == "IEEE"  # RIEEE: little-endian (VAX reals are refused on reading)
        else:
            big = str(self.system.get("INTFMT", "HIGH")).upper() == "HIGH"
        return np.dtype((">" if big else "<") + kind)

    @property
    def real_format(self) -> str:
        """REALFMT: IEEE (big-endian), RIEEE (little-endian) or VAX (VICAR's default when absent)."""
        return str(self.system.get("REALFMT", "VAX")).upper()

    @property
    def record_bytes(self) -> int:
        return int(self.system["RECSIZE"])  # type: ignore[arg-type]

    @property
    def image_offset(self) -> int:
        """Byte offset of the first pixel: past the label, the binary header records and the line prefix."""
        label = int(self.system["LBLSIZE"])  # type: ignore[arg-type]
        header_records = int(self.system.get("NLB", 0))  # type: ignore[arg-type]
        return label + header_records * self.record_bytes + self.prefix_bytes

    @property
    def prefix_bytes(self) -> int:
        return int(self.system.get("NBB", 0))  # type: ignore[arg-type]


def read_vicar_label(path: str | os.PathLike[str]) -> VicarLabel:
    """Parse a VICAR file's label (and its end-of-file label, when EOL = 1).

    Refuses, in one line naming the file, what is not an uncompressed band-sequential
    VICAR image whose pixels pdsgen can locate.
    """
    path = Path(path)
    try:
        with open(path, "rb") as handle:
            head = handle.read(_HEAD_BYTES)
            size = _label_size(head, path)
            handle.seek(0)
            text = handle.read(size)
            items = parse_items(text.decode("latin-1"), path)
            system, properties = _group(items)
            label = VicarLabel(path, system, properties)
            _check_layout(label)
            if int(system.get("EOL", 0)) == 1:  # type: ignore[arg-type]
                end = label.image_offset - label.prefix_bytes + label.lines * label.bands * label.record_bytes
                handle.seek(end)
                more_size = _label_size(handle.read(_HEAD_BYTES), path)
                handle.seek(end)
                more_system, more_properties = _group(
                    parse_items(handle.read(more_size).decode("latin-1"), path))
                for name, group in more_properties.items():
                    properties.setdefault(name, {}).update(group)
                for key, value in more_system.items():
                    system.setdefault(key, value)
    except OSError as exc:
        raise InputError(path, f"cannot read ({exc.strerror or exc})") from None
    return label


def _label_size(head: bytes, path: Path) -> int:
    match = re.match(rb"LBLSIZE\s*=\s*(\d{1,18})\b", head)
    if match is None or int(match.group(1)) <= 0:
        raise InputError(path, "is not a VICAR file (it does not start with LBLSIZE=)")
    return checked_count(path, "LBLSIZE", int(match.group(1)), 1, file_size(path))


def _check_layout(label: VicarLabel) -> None:
    system, path = label.system, label.path
    for key in ("NL", "NS", "RECSIZE"):
        if not isinstance(system.get(key), int) or int(system[key]) <= 0:  # type: ignore[arg-type]
            raise InputError(path, f"VICAR label has no usable {key}")
    for key in ("NB", "NLB", "NBB", "EOL"):  # optional counts: when present, whole numbers
        if key in system and (not isinstance(system[key], int) or int(system[key]) < 0):  # type: ignore[arg-type]
            raise InputError(path, f"VICAR label has an unusable {key} ({system[key]!r})")
    if label.format not in _NUMPY_KINDS:
        raise InputError(path, f"VICAR FORMAT {label.format} is not one pdsgen reads "
                               f"({', '.join(_NUMPY_KINDS)})")
    if label.format in ("REAL", "DOUB") and label.real_format not in ("IEEE", "RIEEE"):
        raise InputError(path, f"VICAR REALFMT {label.real_format} reals are not read (IEEE or RIEEE are)")
    organisation = str(system.get("ORG", "BSQ")).upper()
    if organisation != "BSQ" and label.bands > 1:
        raise InputError(path, f"VICAR ORG {organisation} is not read; pdsgen reads band-sequential (BSQ) images")
    if str(system.get("COMPRESS", "NONE")).upper() not in ("NONE", ""):
        raise InputError(path, "compressed VICAR images are not read")
    needed = label.prefix_bytes + label.samples * label.dtype.itemsize
    if label.record_bytes < needed:
        raise InputError(path, f"VICAR RECSIZE {label.record_bytes} is shorter than a line "
                               f"({label.samples} samples of {label.format} after {label.prefix_bytes} prefix bytes)")
    data_end = label.image_offset - label.prefix_bytes + label.lines * label.bands * label.record_bytes
    actual = path.stat().st_size
    if actual < data_end:
        raise InputError(path, f"is truncated: the VICAR label describes {data_end} bytes, the file has {actual}")


def parse_items(text: str, path: str | os.PathLike[str] = "input") -> list[tuple[str, VicarValue]]:
    """The KEY=VALUE items of a VICAR label in order (strings unquoted, numbers as numbers)."""
    items: list[tuple[str, VicarValue]] = []
    position = 0
    text = text.rstrip("\x00 \r\n\t")
    while position < len(text):
        match = _ITEM_RE.match(text, position)
        if match is None:
            if text[position:].strip(" \x00\r\n\t") == "":
                break
            raise InputError(path, f"VICAR label cannot be read near {text[position:position + 30]!r}")
        value, position = _value(text, match.end(), path)
        items.append((match.group(1).upper(), value))
    return items


def _value(text: str, position: int, path) -> tuple[VicarValue, int]:
    if text.startswith("(", position):
        values: list[int | float | str] = []
        position += 1
        while True:
            while text.startswith((" ", ","), position):
                position += 1
            if text.startswith(")", position):
                return tuple(values), position + 1
            if position >= len(text):
                raise InputError(path, "VICAR label has an unclosed '(' list")
            one, position = _value(text, position, path)
            if isinstance(one, tuple):
                raise InputError(path, "VICAR label has a list inside a list")
            values.append(one)
    if text.startswith("'", position):
        chars: list[str] = []
        position += 1
        while True:
            end = text.find("'", position)
            if end < 0:
                raise InputError(path, "VICAR label has an unclosed quoted string")
            chars.append(text[position:end])
            if text.startswith("''", end):  # a doubled quote stands for one quote
                chars.append("'")
                position = end + 2
                continue
            return "".join(chars), end + 1
    number = _NUMBER_RE.match(text, position)
    end = position
    while end < len(text) and text[end] not in " ,)":
        end += 1
    word = text[position:end]
    if number is not None and number.end() == end:
        if re.fullmatch(r"[-+]?\d+", word):
            return int(word), end
        return float(word.replace("D", "E").replace("d", "e")), end
    return word, end


def _group(items: list[tuple[str, VicarValue]]) -> tuple[dict[str, VicarValue], dict[str, dict[str, VicarValue]]]:
    """System items (before the first PROPERTY or TASK) and property groups by name."""
    system: dict[str, VicarValue] = {}
    properties: dict[str, dict[str, VicarValue]] = {}
    current: dict[str, VicarValue] | None = system
    for key, value in items:
        if key == "PROPERTY":
            current = properties.setdefault(str(value).upper(), {})
        elif key == "TASK":
            current = None  # history items: who processed the file, not what it holds
        elif current is not None:
            current.setdefault(key, value)
    return system, properties


# -- the MAP property group ------------------------------------------------------------------
_REQUIRED_MAP = ("A_AXIS_RADIUS", "C_AXIS_RADIUS", "CENTER_LATITUDE", "CENTER_LONGITUDE",
                 "LINE_PROJECTION_OFFSET", "SAMPLE_PROJECTION_OFFSET", "MAP_PROJECTION_TYPE", "MAP_SCALE")


def group_number(group: Mapping[str, VicarValue], key: str, path: str | os.PathLike[str],
                 default: float | None = None) -> float:
    """A property group's keyword as a number (`default` when absent); one line naming the file if not."""
    value = group.get(key)
    if value is None and default is not None:
        return default
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(path, f"MAP/DIGITAL_TERRAIN_MODEL keyword {key} = {value!r} is not a number") from None


def read_map_group(group: Mapping[str, VicarValue], path: str | os.PathLike[str], missing_hint: str = "") -> VicarMap:
    """The map projection of a MAP group; refuses a group without the keywords a grid needs.

    `missing_hint` ends the message about a missing keyword (where else the reader may find it).
    """
    missing = [key for key in _REQUIRED_MAP if key not in group]
    if missing:
        raise InputError(path, f"has no MAP group keyword {missing[0]}{missing_hint}")
    a_km = group_number(group, "A_AXIS_RADIUS", path)
    c_km = group_number(group, "C_AXIS_RADIUS", path)
    if not (a_km > 0 and c_km > 0):
        raise InputError(path, "MAP group radii must be positive")
    scale_factor = group_number(group, "SCALE_FACTOR", path, 1.0)
    center_latitude = group_number(group, "CENTER_LATITUDE", path)
    center_longitude = group_number(group, "CENTER_LONGITUDE", path)
    map_scale_km = group_number(group, "MAP_SCALE", path)
    if not map_scale_km > 0:
        raise InputError(path, "MAP_SCALE must be positive")
    line_offset = group_number(group, "LINE_PROJECTION_OFFSET", path)
    sample_offset = group_number(group, "SAMPLE_PROJECTION_OFFSET", path)
    false_easting = false_northing = None
    if "FALSE_EASTING" in group or "FALSE_NORTHING" in group:
        false_easting = group_number(group, "FALSE_EASTING", path, 0.0)
        false_northing = group_number(group, "FALSE_NORTHING", path, 0.0)
    return VicarMap(
        projection_type=str(group["MAP_PROJECTION_TYPE"]).upper().replace(" ", "_"),
        a_axis_km=a_km, c_axis_km=c_km,
        center_latitude=center_latitude, center_longitude=center_longitude,
        latitude_type=str(group.get("COORDINATE_SYSTEM_NAME", "PLANETOGRAPHIC")).upper(),
        positive_longitude_direction=str(group.get("POSITIVE_LONGITUDE_DIRECTION", "EAST")).upper(),
        map_scale_km=map_scale_km,
        line_projection_offset=line_offset, sample_projection_offset=sample_offset,
        scale_factor=scale_factor, false_easting_m=false_easting, false_northing_m=false_northing,
    )
