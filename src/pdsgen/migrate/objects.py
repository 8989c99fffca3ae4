"""PDS3 data objects as the PDS4 objects that describe the same bytes.

Each function takes the label as the validator reads it (`FileContext`: the one PDS3 label
reader, its pointers resolved to files and byte offsets) and returns what the PDS4
templates render: a Header, an array or a table, at its byte offset in its file. What
PDS4 cannot state exactly is refused with `Refused`, naming the construct; nothing is
ever described approximately.
"""

from __future__ import annotations

import csv
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from fnmatch import fnmatchcase
from pathlib import Path

from ..bounded import file_size
from ..errors import param
from ..label.grammar import FLOAT_SAMPLE_TYPES
from ..label.tree import Block, Pointer, Statement, Value, parse_pointer
from ..pds4.model import pds4_data_type
from ..validate.context import FileContext
from .described import (
    MissingFile,
    Refused,
    Target,
    pointer_where,
    positive_int,
    special_constants,
    structure_file,
    unit,
    where,
)
from .mapping import (
    ASCII_TABLE_TYPES,
    BAND_STORAGE_AXES,
    BIT_DATA_TYPES,
    BIT_STRING_TYPES,
    FIELD_DELIMITERS,
    HEADER_STANDARDS,
    OBJECT_CLASSES,
    TABLE_CLASSES,
    TEXT_FIELD_TYPES,
)
from .qube import describe_qube

__all__ = ["DataFile", "Refused", "describe_objects", "special_constants"]


@dataclass
class DataFile:
    """One file of the product and the PDS4 objects in it, in byte order."""

    path: Path
    objects: list[dict[str, object]] = field(default_factory=list)
    supplemental: bool = False  # the detached PDS3 label itself
    warnings: list[str] = field(default_factory=list)  # what was left out or overridden, and why

    @property
    def name(self) -> str:
        return self.path.name


@dataclass(frozen=True)
class Placed:
    """A data pointer with what placing its object needs: the OBJECT it describes and the
    RECORD_BYTES its record numbers count in (the label's, or its OBJECT = FILE block's: a
    combined detached label describes each file in a FILE block of its own)."""

    ptr: Pointer
    block: Block | None
    record_bytes: int | None
    file_block: Block | None = None


def placed_pointers(ctx: FileContext) -> Iterator[Placed]:
    """Every data pointer of the label: the top level's, then each OBJECT = FILE block's."""
    for ptr in ctx.data_pointers():
        block = ctx.object_for(ptr)
        if block is None and ptr.name == "QUBE":  # ^QUBE describing an OBJECT = SPECTRAL_QUBE (Cassini VIMS)
            block = next(ctx.root.find("SPECTRAL_QUBE"), None)
        yield Placed(ptr, block, ctx.record_bytes)
    for file_block in ctx.root.blocks("FILE"):
        record_bytes = file_block.number("RECORD_BYTES")
        for stmt in file_block.statements():
            if not stmt.pointer:
                continue
            ptr = parse_pointer(stmt)
            if ptr.is_reference:
                continue
            block = next((b for b in file_block.walk() if b.kind == "OBJECT" and b.name.upper() == ptr.name), None)
            yield Placed(ptr, block, int(record_bytes) if isinstance(record_bytes, int) else None, file_block)


def _offset(placed: Placed) -> int | None:
    """0-based byte offset of the object in its file (the record number counted in the
    RECORD_BYTES of the label or of the pointer's FILE block)."""
    ptr = placed.ptr
    if ptr.byte is not None:
        return ptr.byte - 1
    if ptr.record == 1:  # the first record starts the file, whatever a record's length
        return 0
    if ptr.record is not None:
        return None if placed.record_bytes is None else (ptr.record - 1) * placed.record_bytes
    return 0 if ptr.form == "file" else None


def describe_objects(ctx: FileContext) -> tuple[list[DataFile], str | None]:
    """The product's files with their objects, and the local identifier of the image the map
    projection describes (None without an image). Every obstacle is gathered before refusing:
    the user learns all that stands in the way at once."""
    _refuse_outside(ctx)
    problems: list[str] = []
    files: dict[Path, DataFile] = {}
    image_id: str | None = None
    used: set[str] = set()
    missing: dict[str, list[str]] = {}  # a missing file named by several pointers: told once
    notes: list[str] = []  # pointers that name nothing, left out
    placements = list(placed_pointers(ctx))
    starts = _object_starts(ctx, placements)
    for placed in placements:
        try:
            found = _describe_pointer(ctx, placed, used, starts, notes)
        except MissingFile as absent:
            missing.setdefault(absent.file_name, []).append(f"^{placed.ptr.name} line {placed.ptr.statement.line}")
            continue
        except Refused as refusal:
            problems.extend(refusal.problems)
            continue
        if found is None:
            continue
        path, described = found
        if described["kind"] == "array" and (described.get("element") in ("Array_2D_Image", "Array_3D_Image")
                                             or "lines" in described):  # an image, or a qube's core of lines
            image_id = image_id or str(described["local_identifier"])  # lines with prefixes: no cart:
        extra = described.pop("extra", [])  # a cube's back planes: arrays of their own after the core
        files.setdefault(path, DataFile(path)).objects.extend([described, *extra])  # type: ignore[misc]
    problems.extend(f"data file {name} is missing ({', '.join(pointers)})" for name, pointers in missing.items())
    if problems:
        raise Refused(ctx.path, problems[0], tuple(problems[1:]))
    for data in files.values():
        data.objects.sort(key=lambda o: int(o["offset"]))  # type: ignore[call-overload]
    if ctx.attached:
        _add_attached_label(ctx, files[ctx.path])
    result = list(files.values())
    for encoded in _compressed_files(ctx):  # JPEG 2000 of a HiRISE-style detached label
        result.append(encoded)
        image_id = image_id or str(encoded.objects[0]["local_identifier"])
    if not result:
        raise Refused(ctx.path, "has no data object pointer (^IMAGE, ^TABLE ..., at the top level or in "
                                "an OBJECT = FILE) or COMPRESSED_FILE to describe")
    if ctx.path not in files:  # a detached label: a header of its own (the primary file when all else is
        # supplemental: PDS4 takes no JPEG 2000 as primary data)
        primary = any(not data.supplemental for data in result)
        result.append(DataFile(ctx.path, [{"kind": "header", "local_identifier": "pds3_label", "offset": 0,
                                           "length": ctx.size, "parsing_standard_id": "PDS3",
                                           "description": "The detached PDS3 label of this product."}],
                               supplemental=primary))
    next(data for data in result if data.path == ctx.path).warnings.extend(notes)
    for data in result:
        problems.extend(_order_problems(data))
    if problems:
        raise Refused(ctx.path, problems[0], tuple(problems[1:]))
    result.sort(key=lambda data: data.supplemental)  # File_Area_Observational first, as the schema orders them
    return result, image_id


# The keywords that make an object of any name an image (PDS3 Standards, IMAGE object).
_IMAGE_KEYWORDS = ("LINES", "LINE_SAMPLES", "SAMPLE_TYPE", "SAMPLE_BITS")

# Pointers to an image's line prefixes or suffixes as a table of their own (Cassini ISS:
# ^LINE_PREFIX_TABLE with no OBJECT, its layout in ^LINE_PREFIX_STRUCTURE of the IMAGE).
_LINE_AFFIX_TABLES = frozenset({"LINE_PREFIX_TABLE", "LINE_SUFFIX_TABLE"})


def _has_line_affixes(ctx: FileContext) -> bool:
    return any(block.number("LINE_PREFIX_BYTES") or block.number("LINE_SUFFIX_BYTES")
               for block in ctx.root.walk() if block.kind == "OBJECT" and _kind(block.name) == "image")


def _object_starts(ctx: FileContext, placements: list[Placed]) -> dict[Path, list[int]]:
    """Each file's object starts, in order, with the file's end last: what bounds an object
    whose label states no length (an ISIS2 HISTORY)."""
    starts: dict[Path, set[int]] = {}
    for placed in placements:
        offset = _offset(placed)
        try:
            path = _data_path(ctx, placed) if placed.block is not None else None
        except Refused:
            continue
        if path is not None and offset is not None and offset >= 0:
            starts.setdefault(path, {path.stat().st_size}).add(offset)
    return {path: sorted(found) for path, found in starts.items()}


def _describe_pointer(ctx: FileContext, placed: Placed, used: set[str], starts: dict[Path, list[int]],
                      notes: list[str]) -> tuple[Path, dict[str, object]] | None:
    """One pointer's object, described at its place (None: a document beside the product)."""
    ptr, block = placed.ptr, placed.block
    if block is None and ptr.form == "record" and ptr.record == 0:  # CRISM's ^TRDR_HK_TABLE = 0: none
        notes.append(f"{pointer_where(ptr)} = 0 names no record and the label describes no object for it: "
                     "left out")
        return None
    if (ptr.record is not None and ptr.record < 1) or (ptr.byte is not None and ptr.byte < 1):
        raise Refused(ctx.path, f"{pointer_where(ptr)}: {ptr.record if ptr.byte is None else ptr.byte} is no "
                                "record or byte number (they count from 1)")
    if block is None:
        if ptr.form == "file":  # ^MEX_ORIENTATION_DESC = "X.TXT": a document beside the product, no data
            return None
        if ptr.name in _LINE_AFFIX_TABLES and _has_line_affixes(ctx):
            return None  # the image's line prefixes/suffixes again: described with the image's lines
        raise Refused(ctx.path, f"{pointer_where(ptr)} points at an object the label does not describe")
    kind = _kind(ptr.name)
    if kind == "other" and all(block.get(key) is not None for key in _IMAGE_KEYWORDS):
        kind = "image"  # an image by its keywords, whatever its name (SELENE's GEOMETRIC_DATA_ALTITUDE)
    if kind == "other":
        raise Refused(ctx.path, f"{where(block)}: migrate describes {DESCRIBED_OBJECTS}, not this object")
    path = _data_path(ctx, placed)
    offset = _offset(placed)
    if offset is None:
        raise Refused(ctx.path, f"{pointer_where(ptr)}: its byte offset cannot be known (no RECORD_BYTES)")
    size = path.stat().st_size
    if offset >= size:
        raise Refused(ctx.path, f"{pointer_where(ptr)}: {where(block)} starts at byte {offset}, past the end of "
                                f"{path.name} ({size} bytes)")
    ident = _local_identifier(ptr.name, used)
    describer = DESCRIBERS[kind]
    following = next((start for start in starts.get(path, ()) if start > offset), None)
    return path, describer(ctx, Target(block, ident, offset, path, placed.record_bytes, following))


def _refuse_outside(ctx: FileContext) -> None:
    """Refuse a label naming a file outside the trusted tree (its directory, or the root given; ../x,
    /etc/x, a link leading out): its content must not travel into the PDS4 product."""
    for keyword, name, _ in ctx.outside_names():
        raise Refused(ctx.path, f"{keyword} names {name}, which lies outside {ctx.tree}; not migrated "
                                f"({param('root')} widens the tree)")


def _compressed_files(ctx: FileContext) -> list[DataFile]:
    """COMPRESSED_FILE objects (ENCODING_TYPE JP2) as Encoded_Image in a supplemental area, with
    the size of the image their UNCOMPRESSED_FILE describes (for cart:)."""
    found: list[DataFile] = []
    for block in ctx.root.blocks("COMPRESSED_FILE"):
        encoding = (block.text("ENCODING_TYPE") or "").upper()
        name = block.text("FILE_NAME")
        if not encoding.startswith("JP2") or not name:
            raise Refused(ctx.path, f"OBJECT = COMPRESSED_FILE: ENCODING_TYPE {encoding or 'not given'} is not "
                                    "JP2, the only encoding a PDS4 Encoded_Image of PDS3 products takes here")
        exact, other = ctx.resolve(name)
        path = exact or other
        if path is None:
            raise Refused(ctx.path, f"COMPRESSED_FILE {name} is missing")
        image = next((b for u in ctx.root.blocks("UNCOMPRESSED_FILE") for b in u.blocks("IMAGE")), None)
        entry: dict[str, object] = {"kind": "encoded", "local_identifier": "jp2_image", "offset": 0,
                                    "length": path.stat().st_size, "encoding_standard_id": "JP2",
                                    "description": "The JPEG 2000 file of the PDS3 product, unchanged."}
        if image is not None:
            entry["lines"] = positive_int(ctx, image, "LINES")
            entry["samples"] = positive_int(ctx, image, "LINE_SAMPLES")
        found.append(DataFile(path, [entry], supplemental=True))
    return found


def _kind(name: str) -> str:
    """The describer of an object class (mapping.OBJECT_CLASSES), or "other"."""
    return next((kind for pattern, kind, _ in OBJECT_CLASSES if fnmatchcase(name.upper(), pattern)), "other")


def _local_identifier(name: str, used: set[str]) -> str:
    base = name.lower()
    ident, n = base, 1
    while ident in used:
        n += 1
        ident = f"{base}_{n}"
    used.add(ident)
    return ident


def _data_path(ctx: FileContext, placed: Placed) -> Path:
    ptr = placed.ptr
    if ptr.form == "files":
        raise Refused(ctx.path, f"{pointer_where(ptr)} names several files; migrate describes one file per object")
    if ptr.attached and placed.file_block is not None:  # ^IMAGE = 3 in a FILE block: the block's FILE_NAME
        name = placed.file_block.text("FILE_NAME")
        if name is None:
            raise Refused(ctx.path, f"{pointer_where(ptr)} in {where(placed.file_block)} names no file and the "
                                    "FILE block gives no FILE_NAME")
        exact, other = ctx.resolve(name)
        path = exact or other
        file_name = name
    else:
        path, file_name = ctx.target_path(ptr), ptr.file_name or ctx.path.name
    if path is None:
        beside = ctx.path.parent / file_name  # inside the tree: _refuse_outside has run
        if beside.exists() and not beside.is_file():
            raise Refused(ctx.path, f"{pointer_where(ptr)}: data file {file_name} is not a regular file")
        raise MissingFile(ctx.path, file_name)
    if not path.is_file():
        raise Refused(ctx.path, f"{pointer_where(ptr)}: data file {file_name} is not a regular file")
    return path


def _add_attached_label(ctx: FileContext, data: DataFile) -> None:
    """The attached PDS3 label as a Header: from byte 0 to the first object."""
    first_object = min(data.objects, key=lambda o: int(o["offset"]))  # type: ignore[call-overload]
    first = int(first_object["offset"])  # type: ignore[call-overload]
    if first <= 0 or first < ctx.label.label_end:
        raise Refused(ctx.path, f"{first_object.get('pds3') or first_object['local_identifier']} starts at byte "
                                f"{first}, inside the attached label (which ends at byte {ctx.label.label_end})")
    data.objects.insert(0, {"kind": "header", "local_identifier": "pds3_label", "offset": 0, "length": first,
                            "parsing_standard_id": "PDS3", "description": "The attached PDS3 label of this product."})


def _order_problems(data: DataFile) -> list[str]:
    """Objects of one file that overlap, and objects that run past its end (each named)."""
    size = data.path.stat().st_size
    problems: list[str] = []
    end, before = 0, None
    for obj in data.objects:
        offset, length = int(obj["offset"]), int(obj["length"])  # type: ignore[call-overload]
        name = obj.get("pds3") or obj["local_identifier"]
        if offset < end and before is not None:
            problems.append(f"{name} starts at byte {offset} of {data.name}, inside "
                            f"{before.get('pds3') or before['local_identifier']} (bytes {before['offset']} to {end})")
        if offset + length > size:
            problems.append(f"{name} needs bytes {offset} to {offset + length} of {data.name}, which has "
                            f"{size} bytes; the data file is truncated")
        end, before = max(end, offset + length), obj
    return problems


# -- headers -----------------------------------------------------------------------------------
def _header(ctx: FileContext, target: Target) -> dict[str, object]:
    """A header or history object as a Header: its length from BYTES (the object's size: with
    RECORDS too, BYTES still counts the object's bytes), else RECORDS x RECORD_BYTES; its parsing
    standard from TYPE/HEADER_TYPE, or, for text of no named standard (SPREADSHEET and SFDU headers,
    a table's header line, a HISTORY), from its bytes: 7-bit ASCII or UTF-8 text."""
    block = target.block
    length = _header_length(ctx, target)
    kind = (block.text("TYPE") or block.text("HEADER_TYPE") or "").upper()
    standard = HEADER_STANDARDS.get(kind)
    if standard == "7-Bit ASCII Text":  # TYPE = ASCII/TEXT: the bytes say whether 7-bit or UTF-8
        standard = _text_standard(ctx, target, length)
    if standard is None and (block.text("INTERCHANGE_FORMAT") or "").upper() == "BINARY":
        return _binary_header(ctx, target, length, kind)
    if standard is None:
        if kind not in TEXT_HEADER_TYPES:
            raise Refused(ctx.path, f"{where(block)}: header TYPE {kind} has no PDS4 parsing standard (known: "
                                    f"{', '.join(sorted(HEADER_STANDARDS))}; text headers of "
                                    f"{', '.join(sorted(t for t in TEXT_HEADER_TYPES if t))} or no TYPE)")
        standard = _text_standard(ctx, target, length)
        is_cube = any(_kind(ptr.name) == "qube" for ptr in ctx.data_pointers())  # ^QUBE, ^SPECTRAL_QUBE
        if block.name.upper().endswith("HISTORY") and standard == "7-Bit ASCII Text" and is_cube:
            standard = "ISIS2 History Label"  # the history object of an ISIS2 cube
    what = f"{kind} header" if kind else ("history" if "HISTORY" in block.name.upper() else "header")
    stated = block.get("BYTES") is not None or block.get("RECORDS") is not None
    extent = "" if stated else " Its length, which the label does not state, runs to the next object or the file's end."
    return {"kind": "header", "local_identifier": target.ident, "offset": target.offset, "length": length,
            "parsing_standard_id": standard, "pds3": where(block),
            "description": f"The {what} ({block.name} in the PDS3 label).{extent}"}


def _binary_header(ctx: FileContext, target: Target, length: int, kind: str) -> dict[str, object]:
    """A binary header of no standard PDS4 parses (a Galileo SSI BAD_DATA_VALUES_HEADER,
    HEADER_TYPE BDV, INTERCHANGE_FORMAT BINARY): PDS4's Header takes text and named standards
    only, so its bytes are stated as a Table_Binary - RECORDS records (one when it states none),
    each record its bytes as an UnsignedByte group - exact, every byte accounted for, their
    meaning left to the document the PDS3 label names (^DESCRIPTION)."""
    block = target.block
    records = block.number("RECORDS")
    count = records if isinstance(records, int) and records > 0 else 1
    if length % count:
        raise Refused(ctx.path, f"{where(block)}: BYTES {length} are not RECORDS {count} records of one length")
    size = length // count
    document = block.text("DESCRIPTION")
    named = block.value("^DESCRIPTION")
    about = f" Their layout is documented in {named.text}." if named is not None else ""
    description = (f"The binary {kind or block.name} header ({block.name} in the PDS3 label): {count} record(s) of "
                   f"{size} bytes, stated as bytes - PDS4 parses no binary header of this kind.{about}")
    if document:
        description += " " + " ".join(document.split())
    return {"kind": "table", "element": "Table_Binary", "local_identifier": target.ident, "offset": target.offset,
            "length": length, "records": count, "record_length": size, "description": description,
            "fields": [_byte_group(block.name.upper(), 1, size)], "delimiter": None, "pds3": where(block),
            "warnings": [f"{where(block)}: a binary {kind or 'untyped'} header PDS4 has no parsing standard for: "
                         f"described as a Table_Binary of {count} record(s) of {size} bytes"]}


def _header_length(ctx: FileContext, target: Target) -> int:
    block = target.block
    size = block.number("BYTES")
    if isinstance(size, int) and size > 0:
        return size
    records = block.number("RECORDS")
    if isinstance(records, int) and records > 0:
        if target.record_bytes is None:
            raise Refused(ctx.path, f"{where(block)}: RECORDS without BYTES, and no RECORD_BYTES to count them in")
        return records * target.record_bytes
    if block.name.upper().endswith("HISTORY") and target.next_start is not None:
        return target.next_start - target.offset  # ISIS2: the history runs to the next object (or the file's end)
    raise Refused(ctx.path, f"{where(block)}: neither BYTES nor RECORDS gives its length")


def _text_standard(ctx: FileContext, target: Target, length: int) -> str:
    """7-Bit ASCII Text or UTF-8 Text, as the header's bytes are (read, never assumed)."""
    if target.offset + length > file_size(target.path):  # said before LENGTH bytes are asked for
        raise Refused(ctx.path, f"{where(target.block)}: its {length} bytes run past the end of {target.path.name}")
    with open(target.path, "rb") as handle:
        handle.seek(target.offset)
        data = handle.read(length)
    if len(data) < length:
        raise Refused(ctx.path, f"{where(target.block)}: its {length} bytes run past the end of {target.path.name}")
    if all(byte < 0x80 for byte in data) and not any(byte < 0x20 and byte not in _TEXT_CONTROLS for byte in data):
        return "7-Bit ASCII Text"
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = None
    if text is not None and not any(ord(c) < 0x20 and ord(c) not in _TEXT_CONTROLS for c in text):
        return "UTF-8 Text"
    raise Refused(ctx.path, f"{where(target.block)}: its bytes are not text (7-bit ASCII or UTF-8) and it names "
                            "no standard PDS4 parses")


# Text bytes below 0x20 a text header holds: TAB, LF, FF, CR (and NUL padding to a record's end).
_TEXT_CONTROLS = frozenset({0x00, 0x09, 0x0A, 0x0C, 0x0D})
# HEADER_TYPEs that name no parsing standard but a text (a spreadsheet's column-name line, an SFDU label).
TEXT_HEADER_TYPES = frozenset({"", "SPREADSHEET", "SFDU", "TEXT", "ASCII", "HISTORY"})


# -- images ------------------------------------------------------------------------------------
def _image(ctx: FileContext, target: Target) -> dict[str, object]:
    block, ident, offset = target.block, target.ident, target.offset
    lines, samples = positive_int(ctx, block, "LINES"), positive_int(ctx, block, "LINE_SAMPLES")
    bands = int(block.number("BANDS") or 1)
    sample_type = (block.text("SAMPLE_TYPE") or "").upper()
    bits = positive_int(ctx, block, "SAMPLE_BITS")
    data_type = pds4_data_type(sample_type, bits)
    if data_type is None:
        raise Refused(ctx.path, f"{where(block)}: SAMPLE_TYPE {sample_type or 'not given'} of {bits} bits "
                                "has no PDS4 data type")
    prefix, suffix = (int(block.number(key) or 0) for key in ("LINE_PREFIX_BYTES", "LINE_SUFFIX_BYTES"))
    if prefix or suffix:
        return _lines_as_records(ctx, block, ident, offset, (lines, samples, bands), data_type, bits,
                                 (prefix, suffix))
    names: tuple[str, ...]
    if bands == 1:
        element, names = "Array_2D_Image", ("Line", "Sample")
    else:
        storage = (block.text("BAND_STORAGE_TYPE") or "BAND_SEQUENTIAL").upper().replace(" ", "_")
        if storage not in BAND_STORAGE_AXES:
            raise Refused(ctx.path, f"{where(block)}: BAND_STORAGE_TYPE {storage} is not one PDS4 axes "
                                    "can state")
        element, names = "Array_3D_Image", BAND_STORAGE_AXES[storage]
    sizes = {"Line": lines, "Sample": samples, "Band": bands}
    scaling, value_offset = block.number("SCALING_FACTOR"), block.number("OFFSET")
    identity = (scaling in (None, 1) and value_offset in (None, 0))
    description = block.text("DESCRIPTION") or block.text("NOTE") or f"The {block.name} object of the PDS3 label."
    return {
        "kind": "array", "element": element, "bands": None if bands == 1 else bands, "pds3": where(block),
        "local_identifier": ident, "offset": offset, "length": lines * samples * bands * bits // 8,
        "axes": [(name, sizes[name]) for name in names], "lines": lines, "samples": samples,
        "description": " ".join(description.split()),
        "data_type": data_type, "unit": unit(block),
        "scaling_factor": None if identity else (scaling if scaling is not None else 1.0),
        "value_offset": value_offset if value_offset is not None else 0.0,
        "special": special_constants(ctx, block, sample_type in FLOAT_SAMPLE_TYPES, bits),
    }


def _lines_as_records(ctx: FileContext, block: Block, ident: str, offset: int, size: tuple[int, int, int],
                      data_type: str, bits: int, prefix_suffix: tuple[int, int]) -> dict[str, object]:
    """An image whose lines carry prefix/suffix bytes: PDS4 arrays have no stride, so each line
    with its prefix and suffix is one record of a binary table (the prefix and suffix as byte
    groups, the samples as a group of LINE_SAMPLES fields) - exact, never an approximate array."""
    lines, samples, bands = size
    prefix, suffix = prefix_suffix
    if bands > 1 and (block.text("BAND_STORAGE_TYPE") or "BAND_SEQUENTIAL").upper() != "BAND_SEQUENTIAL":
        raise Refused(ctx.path, f"{where(block)}: line prefixes/suffixes with "
                                f"{block.text('BAND_STORAGE_TYPE')} bands are not described by migrate")
    width = samples * bits // 8
    sample_field = _image_field(ctx, block, data_type, bits, 1 + prefix, samples)
    fields = [sample_field]
    if prefix:
        fields.insert(0, _byte_group("LINE_PREFIX", 1, prefix))
    if suffix:
        fields.append(_byte_group("LINE_SUFFIX", 1 + prefix + width, suffix))
    description = (f"The {block.name} object's lines ({lines * bands} = LINES x BANDS, band after band), "
                   f"each a record with its LINE_PREFIX_BYTES ({prefix}) and LINE_SUFFIX_BYTES ({suffix}): "
                   "a PDS4 array cannot skip bytes between lines.")
    return {"kind": "table", "element": "Table_Binary", "local_identifier": ident, "offset": offset,
            "length": lines * bands * (prefix + width + suffix), "records": lines * bands,
            "record_length": prefix + width + suffix, "description": description, "fields": fields,
            "delimiter": None, "pds3": where(block)}


def _image_field(ctx: FileContext, block: Block, data_type: str, bits: int, location: int,
                 samples: int) -> dict[str, object]:
    scaling, value_offset = block.number("SCALING_FACTOR"), block.number("OFFSET")
    identity = (scaling in (None, 1) and value_offset in (None, 0))
    return {"name": "SAMPLES", "location": 1, "length": bits // 8, "data_type": data_type, "unit": unit(block),
            "scaling_factor": None if identity else (scaling if scaling is not None else 1.0),
            "value_offset": None if identity else (value_offset or 0.0), "description": None,
            "special": special_constants(ctx, block, data_type.startswith("IEEE"), bits),
            "group": {"repetitions": samples, "location": location, "length": samples * bits // 8}}


def _byte_group(name: str, location: int, length: int) -> dict[str, object]:
    return {"name": name, "location": 1, "length": 1, "data_type": "UnsignedByte", "unit": None,
            "scaling_factor": None, "value_offset": None, "description": None, "special": [],
            "group": {"repetitions": length, "location": location, "length": length}}


# -- tables ------------------------------------------------------------------------------------
def _table(ctx: FileContext, target: Target) -> dict[str, object]:
    block, ident, offset, path = target.block, target.ident, target.offset, target.path
    interchange = (block.text("INTERCHANGE_FORMAT") or "").upper()
    element = TABLE_CLASSES.get(interchange)
    if element is None:
        raise Refused(ctx.path, f"{where(block)}: INTERCHANGE_FORMAT {interchange or 'not given'} "
                                "is neither ASCII nor BINARY")
    rows, row_bytes = positive_int(ctx, block, "ROWS"), positive_int(ctx, block, "ROW_BYTES")
    prefix = int(block.number("ROW_PREFIX_BYTES") or 0)
    suffix = int(block.number("ROW_SUFFIX_BYTES") or 0)
    record_length = prefix + row_bytes + suffix
    columns = _columns(ctx, block, prefix, element == "Table_Character")
    table: dict[str, object] = {
        "kind": "table", "element": element, "local_identifier": ident, "offset": offset,
        "length": rows * record_length, "records": rows, "record_length": record_length,
        "description": " ".join((block.text("DESCRIPTION") or f"The {block.name} object of the PDS3 label.").split()),
        "fields": columns, "delimiter": None, "pds3": where(block),
    }
    warnings = [str(f.pop("warning")) for f in columns if f.get("warning")]
    table["warnings"] = warnings
    reach = _fields_end(columns)
    if element == "Table_Binary" and reach > record_length:
        raise Refused(ctx.path, f"{where(block)}: its columns reach byte {reach} of a row, past its {record_length} "
                                "bytes (ROW_BYTES with any prefix and suffix)")
    record_bytes = _rows_in_records(target, rows, record_length)
    if element == "Table_Binary" and record_bytes is not None:
        table["record_length"], table["length"] = record_bytes, rows * record_bytes
        stated = "ROW_BYTES with its prefix and suffix" if prefix or suffix else "ROW_BYTES"
        warnings.append(f"{where(block)}: rows of {record_length} bytes ({stated}), but its file ends {rows} "
                        f"records of RECORD_BYTES {record_bytes} after the table's start: each row described as "
                        f"one {record_bytes}-byte record, the bytes after its columns unnamed")
    if element == "Table_Character":
        try:
            table["delimiter"] = _record_delimiter(ctx, block, path, offset, record_length)
        except Refused:
            measured = _measured_records(path, offset, rows, _fields_end(columns))
            if measured is None:
                raise
            table["delimiter"], table["record_length"] = measured
            table["length"] = rows * measured[1]
            warnings.append(f"{where(block)}: ROW_BYTES {row_bytes} overridden by the bytes: each of its {rows} "
                            f"records ends with {_ENDINGS[measured[0]]} at byte {measured[1]}, and every column "
                            "lies before it")
        _check_records(ctx, target, rows, table)
    return table


def _check_records(ctx: FileContext, target: Target, rows: int, table: dict[str, object]) -> None:
    """Read a character table as a PDS4 reader will: every one of ROWS records ends with its line
    end at its length (the first that does not - a short or long line amid fixed-length ones -
    refuses the table, named: records of unequal length have no PDS4 Table_Character), and
    every numeric field's values are numbers of its type (`_NumberCheck`)."""
    length = int(table["record_length"])  # type: ignore[call-overload]
    ending = b"\r\n" if table["delimiter"] == "Carriage-Return Line-Feed" else b"\n"
    checks = [_NumberCheck(f, spans) for f, spans in _field_spans(table["fields"], 0, {}).values()  # type: ignore[arg-type]
              if f["data_type"] in _NUMERIC_TEXT]
    per_block = max(1, (1 << 20) // length)  # a block of records at a time: a large table is not read whole
    with open(target.path, "rb") as handle:
        handle.seek(target.offset)
        for first in range(0, rows, per_block):
            count = min(per_block, rows - first)
            block = handle.read(count * length)
            for n in range(count):
                end = (n + 1) * length
                if len(block) < end:
                    return  # the file ends first: told as a truncated table by _order_problems
                if block[end - len(ending):end] != ending:
                    raise Refused(ctx.path, _misfit(target, rows, first + n + 1, length, ending, block[n * length:]))
                for check in checks:
                    check.read(block[n * length:end], first + n + 1)
    warnings = table.setdefault("warnings", [])
    for check in checks:
        warning = check.verdict(ctx, target.block)
        if warning:
            warnings.append(warning)  # type: ignore[attr-defined]


_NUMERIC_TEXT = frozenset({"ASCII_Integer", "ASCII_NonNegative_Integer", "ASCII_Real"})


def _field_spans(fields: list[dict[str, object]], base: int,
                 into: dict[int, tuple[dict[str, object], list[slice]]]) -> dict[int, tuple[dict[str, object],
                                                                                    list[slice]]]:
    """Each field of a record with the byte ranges it takes in the record: once, or in every
    repetition of its group (an ITEMS column; a CONTAINER's members, nested), `base` the
    0-based byte its fields' locations count from."""
    for entry in fields:
        group = entry.get("group")
        length = int(entry["length"])  # type: ignore[call-overload]
        if not isinstance(group, dict):
            start = base + int(entry["location"]) - 1  # type: ignore[call-overload]
            into.setdefault(id(entry), (entry, []))[1].append(slice(start, start + length))
            continue
        repetitions, location = int(group["repetitions"]), base + int(group["location"]) - 1
        step = int(group["length"]) // repetitions
        for n in range(repetitions):
            if group.get("members"):
                _field_spans(group["members"], location + n * step, into)
            else:  # an ITEMS column: the field itself in each repetition
                start = location + n * step + int(entry["location"]) - 1  # type: ignore[call-overload]
                into.setdefault(id(entry), (entry, []))[1].append(slice(start, start + length))
    return into


class _NumberCheck:
    """One numeric field of a character table read in every record, as a PDS4 reader converts it:
    an integer field whose values are reals (a Galileo Probe DESCENT.TAB ALTITUDE of DATA_TYPE
    ASCII_INTEGER, FORMAT F9.4) is described as ASCII_Real; a field holding a value that is no
    number at all (blank, N/A: pds4_tools cannot convert it, and the label would not open) as
    ASCII_String - the text the bytes hold. Either way a warning names DATA_TYPE and the value."""

    def __init__(self, field: dict[str, object], spans: list[slice]) -> None:
        self.field, self.spans = field, spans
        self.not_integer: tuple[int, str] | None = None
        self.not_number: tuple[int, str] | None = None

    def read(self, record: bytes, number: int) -> None:
        for span in self.spans:
            if self.not_number is not None:
                return
            self._read(record[span].strip(), number)

    def _read(self, text: bytes, number: int) -> None:
        if not text:
            self.not_number = (number, "")
            return
        if self.field["data_type"] != "ASCII_Real" and self.not_integer is None and \
                not text.lstrip(b"+-" if self.field["data_type"] == "ASCII_Integer" else b"+").isdigit():
            self.not_integer = (number, text.decode("latin-1"))
        try:
            float(text)
        except ValueError:
            self.not_number = (number, text.decode("latin-1"))

    def verdict(self, ctx: FileContext, block: Block) -> str | None:
        name, stated = self.field["name"], self.field["data_type"]
        if self.not_number is not None:
            record, text = self.not_number
            self.field.update(data_type="ASCII_String", scaling_factor=None, value_offset=None, special=[])
            return (f"{where(block)}: column {name} DATA_TYPE overridden by the bytes: {text!r} in record {record} "
                    f"is no number, which a PDS4 reader of {stated} cannot convert: described as ASCII_String")
        if self.not_integer is None:
            return None
        record, text = self.not_integer
        self.field["data_type"] = "ASCII_Real"
        return (f"{where(block)}: column {name} DATA_TYPE overridden by the bytes: {text!r} in record {record} is "
                f"no {stated}, and every value of the column is a number: described as ASCII_Real")


def _misfit(target: Target, rows: int, record: int, length: int, ending: bytes, rest: bytes) -> str:
    """How a record that does not end where the label says is told: where its line end is."""
    found = rest.find(b"\n")
    where_end = (f"its line end is at byte {found + 1} of it" if 0 <= found < 1 << 16
                 else "no line end follows it")
    return (f"{where(target.block)}: ROWS {rows} records of {length} bytes ending with {_ENDINGS_BY_BYTES[ending]}, "
            f"but record {record} of {target.path.name} does not end so ({where_end}): records of unequal "
            "length are no PDS4 Table_Character, and describing fewer would leave table rows undescribed")


def _rows_in_records(target: Target, rows: int, record_length: int) -> int | None:
    """RECORD_BYTES when a binary table's rows are its file's fixed-length records, not packed at
    ROW_BYTES: the table is the file's last object and the file ends exactly ROWS records of
    RECORD_BYTES after its start (and not ROWS rows of ROW_BYTES). None otherwise."""
    record_bytes, end = target.record_bytes, target.next_start
    if record_bytes is None or end is None or record_bytes <= record_length:
        return None
    if end != target.path.stat().st_size or end - target.offset != rows * record_bytes:
        return None
    return record_bytes


_ENDINGS = {"Carriage-Return Line-Feed": "CR LF", "Line-Feed": "LF"}
_ENDINGS_BY_BYTES = {b"\r\n": "CR LF", b"\n": "LF"}


def _fields_end(fields: list[dict[str, object]]) -> int:
    """The last byte (1-based) any field or group of a record reaches."""
    ends = [int(f["group"]["location"]) + int(f["group"]["length"]) - 1  # type: ignore[index]
            if f.get("group") else int(f["location"]) + int(f["length"]) - 1  # type: ignore[call-overload]
            for f in fields]
    return max(ends, default=0)


def _measured_records(path: Path, offset: int, rows: int, fields_end: int) -> tuple[str, int] | None:
    """(record_delimiter, record length) of an ASCII table whose ROW_BYTES its bytes contradict,
    when the bytes leave no doubt: every one of ROWS records ends with the same line end at
    the same length, and every column lies before it. None otherwise (then it is refused)."""
    with open(path, "rb") as handle:
        handle.seek(offset)
        first = handle.readline(1 << 20)
        ending = b"\r\n" if first.endswith(b"\r\n") else b"\n"
        length = len(first)
        if not first.endswith(b"\n") or fields_end > length - len(ending):
            return None
        for _ in range(rows - 1):  # a record at a time: a large table is not read whole
            record = handle.readline(length)
            if len(record) != length or not record.endswith(ending):
                return None
    return ("Carriage-Return Line-Feed" if ending == b"\r\n" else "Line-Feed"), length


def _record_delimiter(ctx: FileContext, block: Block, path: Path, offset: int, record_length: int) -> str:
    """An ASCII table's records end with CR LF (PDS3's rule) or LF: read the first record's end,
    once the label's ROW_BYTES is known to end it inside the file (10^12 could not be sought)."""
    if record_length < 2 or offset + record_length > file_size(path):
        raise Refused(ctx.path, f"{where(block)}: its first record of ROW_BYTES = {record_length} from byte "
                                f"{offset + 1} does not lie in {path.name} ({file_size(path)} bytes)")
    with open(path, "rb") as handle:
        handle.seek(offset + record_length - 2)
        end = handle.read(2)
    if end == b"\r\n":
        return "Carriage-Return Line-Feed"
    if end[-1:] == b"\n":
        return "Line-Feed"
    raise Refused(ctx.path, f"{where(block)}: its first record does not end with CR LF or LF at "
                            "ROW_BYTES, as a PDS4 character table must")


# Bounds on what ^STRUCTURE files may expand to (label/includes.MAX_INCLUDE_DEPTH bounds their
# nesting): no genuine table has anywhere near this many columns, and a hostile fan-out (files
# including each other four times over) would otherwise expand to 4^19 columns.
_MAX_COLUMNS = 100_000


def _column_blocks(ctx: FileContext, block: Block, expanded: dict[Path, list[Block]] | None = None,
                   chain: tuple[Path, ...] = ()) -> list[Block]:
    """COLUMN and CONTAINER objects in order, a ^STRUCTURE file's in its place: each file
    expanded once (`expanded`), through the files that include it (`chain`)."""
    expanded = {} if expanded is None else expanded
    found: list[Block] = []
    for item in block.items:
        if isinstance(item, Statement) and item.pointer and item.keyword.upper() == "STRUCTURE":
            path, root = structure_file(ctx, item, chain)
            if path not in expanded:
                expanded[path] = _column_blocks(ctx, _unwrapped(root), expanded, (*chain, path))
            found.extend(expanded[path])
        elif isinstance(item, Block):
            name = item.name.upper()
            if name in ("COLUMN", "CONTAINER"):
                found.append(item)
            elif name == "BIT_COLUMN":
                raise Refused(ctx.path, f"{where(item)} in {where(block)}: a BIT_COLUMN outside a COLUMN has no "
                                        "bytes of its own")
        if len(found) > _MAX_COLUMNS:
            raise Refused(ctx.path, f"{where(block)}: more than {_MAX_COLUMNS} columns")
    return found


def _unwrapped(root: Block, names: frozenset[str] | None = None) -> Block:
    """A format file's columns: its top level, or (a quirk of real volumes) the one OBJECT that
    wraps them (OBJECT = TABLE ... COLUMNs ... END_OBJECT in the .FMT file)."""
    while not any(b.name.upper() in (names or _COLUMN_OBJECTS) for b in root.blocks()):
        children = [b for b in root.blocks() if b.kind == "OBJECT"]
        if len(children) != 1:
            break
        root = children[0]
    return root


_COLUMN_OBJECTS = frozenset({"COLUMN", "CONTAINER", "BIT_COLUMN"})
# The bit fields of a COLUMN (tables) or of an ELEMENT (arrays and collections): the same keywords.
_BIT_OBJECTS = ("BIT_COLUMN", "BIT_ELEMENT")


def _columns(ctx: FileContext, block: Block, prefix: int, character: bool,
             budget: list[int] | None = None) -> list[dict[str, object]]:
    """The fields of a table (or of a CONTAINER: then locations are the container's own, as PDS3
    counts them); every column PDS4 cannot state is named (all of them, not the first).
    `budget`: fields left for the whole table (a hostile fan-out of containers stays bounded)."""
    budget = [_MAX_COLUMNS] if budget is None else budget
    row_bytes = int(block.number("ROW_BYTES") or block.number("BYTES") or 0)

    def described(column: Block) -> dict[str, object]:
        if column.name.upper() == "CONTAINER":
            return _container(ctx, column, prefix, character, budget)
        return _field(ctx, column, prefix, character, row_bytes)

    return _gathered(ctx, block, _column_blocks(ctx, block), described, budget,
                     "has no COLUMN objects (nor a ^STRUCTURE file holding them)")


def _gathered(ctx: FileContext, block: Block, parts: list[Block], describe: Callable[[Block], dict[str, object]],
              budget: list[int], empty: str) -> list[dict[str, object]]:
    """Each part of a table, container or collection described as a field or group; every part
    PDS4 cannot state is named (all of them, not the first), and `budget` (fields left for the
    whole object) keeps a hostile fan-out of nested parts bounded."""
    fields: list[dict[str, object]] = []
    problems: list[str] = []
    for part in parts:
        budget[0] -= 1
        if budget[0] < 0:
            raise Refused(ctx.path, f"{where(block)}: more than {_MAX_COLUMNS} columns")
        try:
            fields.append(describe(part))
        except Refused as refusal:
            problems.extend(refusal.problems)
    if problems:
        raise Refused(ctx.path, problems[0], tuple(problems[1:]))
    if not fields:
        raise Refused(ctx.path, f"{where(block)} {empty}")
    return fields


def _container(ctx: FileContext, container: Block, prefix: int, character: bool,
               budget: list[int]) -> dict[str, object]:
    """A CONTAINER as a Group_Field_*: REPETITIONS of BYTES from START_BYTE, its COLUMNs and
    CONTAINERs at their START_BYTEs within it (PDS3 counts them from the container's start, as
    PDS4 counts a group's fields from the group's)."""
    start, size = positive_int(ctx, container, "START_BYTE"), positive_int(ctx, container, "BYTES")
    repetitions = container.number("REPETITIONS")
    repetitions = 1 if repetitions is None else repetitions
    if not isinstance(repetitions, int) or repetitions <= 0:
        raise Refused(ctx.path, f"{where(container)}: REPETITIONS {repetitions} is not a positive integer")
    members = _columns(ctx, container, 0, character, budget)
    for member in members:
        group = member.get("group")
        end = (int(group["location"]) + int(group["length"]) - 1 if isinstance(group, dict)
               else int(member["location"]) + int(member["length"]) - 1)  # type: ignore[call-overload]
        if end > size:
            raise Refused(ctx.path, f"{where(container)}: {member['name']} ends at byte {end}, past the "
                                    f"container's BYTES {size}")
    return {"name": container.text("NAME") or "container", "location": 1, "length": size, "group": {
        "repetitions": repetitions, "location": prefix + start, "length": repetitions * size,
        "name": container.text("NAME"), "members": members,
        "description": " ".join((container.text("DESCRIPTION") or "").split()) or None}}


def _column_type(ctx: FileContext, column: Block, character: bool, item_bytes: int) -> str:
    name = column.text("NAME") or "column"
    pds3_type = " ".join((column.text("DATA_TYPE") or "").upper().split()).replace(" ", "_")  # MSB BIT STRING
    data_type = (ASCII_TABLE_TYPES if character else TEXT_FIELD_TYPES).get(pds3_type)
    if data_type is None and not character:
        data_type = pds4_data_type(pds3_type, item_bytes * 8) or BIT_STRING_TYPES.get(pds3_type)
    if data_type is None:
        where_ = "an ASCII table" if character else "PDS4"
        raise Refused(ctx.path, f"{where(column)}: column {name} DATA_TYPE {pds3_type or 'not given'} of "
                                f"{item_bytes} bytes has no data type in {where_}")
    return data_type


def _item_bytes(column: Block, items: int, size: int, row_bytes: int, character: bool) -> tuple[int, bool]:
    """The bytes of one item of an ITEMS column, and whether BYTES was taken per item. ITEM_BYTES
    when given; else BYTES is the whole column's (the PDS3 Standards) - unless it cannot be
    (BYTES not ITEMS items of a size its binary DATA_TYPE has) while BYTES per item fits the
    row: real ^STRUCTURE files give BYTES per item so, and pdr reads them so."""
    given = column.number("ITEM_BYTES")
    if isinstance(given, int) and given > 0:
        return given, False
    start = int(column.number("START_BYTE") or 1)
    pds3_type = " ".join((column.text("DATA_TYPE") or "").upper().split()).replace(" ", "_")
    whole_fits = size % items == 0 and (character or pds3_type in TEXT_FIELD_TYPES
                                        or pds4_data_type(pds3_type, size // items * 8) is not None)
    per_item_fits = row_bytes > 0 and start - 1 + size * items <= row_bytes
    if per_item_fits and not whole_fits:
        return size, True
    return (size // items if size % items == 0 else size), False


def _field(ctx: FileContext, column: Block, prefix: int, character: bool, row_bytes: int) -> dict[str, object]:
    name = column.text("NAME") or "column"
    start, size = positive_int(ctx, column, "START_BYTE"), positive_int(ctx, column, "BYTES")
    items = column.number("ITEMS")
    if items is not None and (not isinstance(items, int) or items <= 0):
        raise Refused(ctx.path, f"{where(column)}: column {name} ITEMS {items} is not a positive integer")
    count = int(items or 0)
    item_bytes, per_item = _item_bytes(column, count, size, row_bytes, character) if count else (size, False)
    try:
        data_type = _column_type(ctx, column, character, item_bytes)
    except Refused:
        if character or not _is_spare(name):
            raise
        return _spare_bytes(column, name, prefix + start, size * count if per_item else size)
    pds3_type = (column.text("DATA_TYPE") or "").upper()
    scaling, value_offset = column.number("SCALING_FACTOR"), column.number("OFFSET")
    entry: dict[str, object] = {
        "name": name, "location": prefix + start, "length": item_bytes, "data_type": data_type,
        "unit": unit(column),
        "scaling_factor": scaling, "value_offset": value_offset,
        "description": " ".join((column.text("DESCRIPTION") or "").split()) or None,
        "special": special_constants(ctx, column, pds3_type in FLOAT_SAMPLE_TYPES, item_bytes * 8),
        "group": None, "bits": None,
    }
    if per_item:
        entry["warning"] = (f"{where(column)}: column {name} BYTES {size} taken per item: {items} items of {size} "
                            f"bytes fill {size * count} bytes of the row, while {size} bytes cannot hold {items} "
                            f"{pds3_type} items")
    if any(True for name in _BIT_OBJECTS for _ in column.blocks(name)):
        entry.update(data_type="UnsignedBitString", scaling_factor=None, value_offset=None, special=[],
                     bits=_bit_fields(ctx, column, pds3_type, item_bytes))
    if items:
        step = int(column.number("ITEM_OFFSET") or item_bytes)
        if item_bytes <= 0 or step < item_bytes:
            raise Refused(ctx.path, f"{where(column)}: column {name} ITEMS/ITEM_BYTES/ITEM_OFFSET "
                                    "do not describe a repeated field")
        entry["group"] = {"repetitions": items, "location": prefix + start, "length": items * step}
        entry["location"] = 1
    return entry


# Words that name a column holding no value (PDS3 labels' spare and filler columns).
_SPARE_WORDS = frozenset({"SPARE", "SPARES", "FILL", "FILLER", "PAD", "PADDING", "UNUSED", "RESERVED"})


def _is_spare(name: str) -> bool:
    return bool(_SPARE_WORDS & set(re.split(r"[^A-Z]+", name.upper())))


def _spare_bytes(column: Block, name: str, location: int, size: int) -> dict[str, object]:
    """A spare column whose DATA_TYPE PDS4 has no type for (a Pioneer Venus SPARE of IBM_REAL):
    it holds no value, so its bytes are stated as they are, an UnsignedByte group under its name,
    rather than left undescribed - every byte of the record stays accounted for and readable,
    and nothing is claimed about a number format PDS4 cannot state."""
    entry = _byte_group(name, location, size)
    stated = " ".join((column.text("DATA_TYPE") or "").split())
    entry["warning"] = (f"{where(column)}: column {name} DATA_TYPE {stated} has no PDS4 data type; a spare column, "
                        f"stated as its {size} bytes (UnsignedByte)")
    return entry


def _bit_fields(ctx: FileContext, column: Block, pds3_type: str, item_bytes: int) -> list[dict[str, object]]:
    """A column's BIT_COLUMNs as Packed_Data_Fields' Field_Bit (the column an UnsignedBitString,
    as PDS4 requires): bits counted from the most significant bit of the column's first byte,
    as PDS3 counts them in MSB columns; in an LSB column the bit order is not stated: refused."""
    pds3_type = " ".join(pds3_type.split()).replace(" ", "_")
    if pds3_type.startswith(("LSB_", "PC_", "VAX_")) and item_bytes > 1:
        raise Refused(ctx.path, f"{where(column)}: BIT_COLUMNs in a {pds3_type} column: PDS4 counts bits from the "
                                "first byte's most significant bit, and this column's bytes run the other way")
    bits: list[dict[str, object]] = []
    for bit_column in (b for b in column.blocks() if b.name.upper() in _BIT_OBJECTS):
        name = bit_column.text("NAME") or "bit_column"
        start, count = positive_int(ctx, bit_column, "START_BIT"), positive_int(ctx, bit_column, "BITS")
        kind = " ".join((bit_column.text("BIT_DATA_TYPE") or "").upper().split()).replace(" ", "_")
        data_type = BIT_DATA_TYPES.get(kind)
        if data_type is None:
            raise Refused(ctx.path, f"{where(bit_column)}: BIT_DATA_TYPE {kind or 'not given'} is none of "
                                    f"{', '.join(sorted(BIT_DATA_TYPES))}")
        items = bit_column.number("ITEMS")
        repeats = int(items) if isinstance(items, int) and items > 0 else 1
        width = int(bit_column.number("ITEM_BITS") or count) if repeats > 1 else count
        step = int(bit_column.number("ITEM_OFFSET") or width) if repeats > 1 else width
        last = start + (repeats - 1) * step + width - 1
        if last > item_bytes * 8 or len(bits) + repeats > _MAX_COLUMNS:
            raise Refused(ctx.path, f"{where(bit_column)}: its bits (to bit {last}) lie outside the column's "
                                    f"{item_bytes * 8} bits")
        for n in range(repeats):
            first = start + n * step
            if first + width - 1 > item_bytes * 8:
                raise Refused(ctx.path, f"{where(bit_column)}: bits {first} to {first + width - 1} lie outside "
                                        f"the column's {item_bytes * 8} bits")
            bits.append({"name": name if repeats == 1 else f"{name}_{n + 1}", "start": first,
                         "stop": first + width - 1, "data_type": data_type, "unit": unit(bit_column),
                         "description": " ".join((bit_column.text("DESCRIPTION") or "").split()) or None})
    return bits


# -- spreadsheets and histograms ------------------------------------------------------------------
def _spreadsheet(ctx: FileContext, target: Target) -> dict[str, object]:
    """SPREADSHEET (delimited text, FIELD objects) as a Table_Delimited: its records end as the
    first record's bytes show, its FIELD_DELIMITER one of PDS4's four."""
    block = target.block
    rows = positive_int(ctx, block, "ROWS")
    delimiter_name = (block.text("FIELD_DELIMITER") or "").upper().replace(" ", "_")
    delimiter = FIELD_DELIMITERS.get(delimiter_name)
    if delimiter is None:
        raise Refused(ctx.path, f"{where(block)}: FIELD_DELIMITER {delimiter_name or 'not given'} is none of "
                                f"PDS4's ({', '.join(sorted(FIELD_DELIMITERS))})")
    fields: list[dict[str, object]] = []
    for item in _field_blocks(ctx, block):
        pds3_type = (item.text("DATA_TYPE") or "").upper()
        data_type = ASCII_TABLE_TYPES.get(pds3_type)
        if data_type is None:
            raise Refused(ctx.path, f"{where(item)}: field {item.text('NAME')} DATA_TYPE {pds3_type or 'not given'} "
                                    "has no data type in a delimited table")
        items = item.number("ITEMS")
        count = int(items) if isinstance(items, int) and items > 0 else 1
        name = item.text("NAME") or f"field_{len(fields) + 1}"
        for n in range(count):  # ITEMS values, each a field of its own (a delimited record has no groups here)
            fields.append({"name": name if count == 1 else f"{name}_{n + 1}", "number": len(fields) + 1,
                           "data_type": data_type, "length": item.number("ITEM_BYTES") or item.number("BYTES"),
                           "unit": unit(item),
                           "description": " ".join((item.text("DESCRIPTION") or "").split()) or None})
        if len(fields) > _MAX_COLUMNS:
            raise Refused(ctx.path, f"{where(block)}: more than {_MAX_COLUMNS} fields")
    if not fields:
        raise Refused(ctx.path, f"{where(block)} has no FIELD objects (nor a ^STRUCTURE file holding them)")
    length, record_delimiter = _delimited_extent(ctx, target, rows, (_DELIMITER_CHARACTERS[delimiter_name],
                                                                     len(fields)))
    return {"kind": "delimited", "local_identifier": target.ident, "offset": target.offset, "length": length,
            "records": rows, "record_delimiter": record_delimiter, "field_delimiter": delimiter,
            "description": " ".join((block.text("DESCRIPTION") or f"The {block.name} object of the PDS3 label.")
                                    .split()),
            "fields": fields, "pds3": where(block)}


_DELIMITER_CHARACTERS = {"COMMA": ",", "TAB": "\t", "SEMICOLON": ";", "VERTICAL_BAR": "|"}


def _field_blocks(ctx: FileContext, block: Block) -> list[Block]:
    """A spreadsheet's FIELD objects in order, a ^STRUCTURE file's in its place (one level: the
    format files of spreadsheets name no further files)."""
    found: list[Block] = []
    for item in block.items:
        if isinstance(item, Statement) and item.pointer and item.keyword.upper() == "STRUCTURE":
            _, root = structure_file(ctx, item)
            found.extend(_unwrapped(root, frozenset({"FIELD"})).blocks("FIELD"))
        elif isinstance(item, Block) and item.name.upper() == "FIELD":
            found.append(item)
    return found


def _delimited_extent(ctx: FileContext, target: Target, rows: int, layout: tuple[str, int]) -> tuple[int, str]:
    """Bytes of ROWS delimited records from the object's offset, and how they end (read, a
    record at a time: a large file is not read whole); every record holds as many values as the
    label has fields (`layout`: delimiter, number of fields), read as a CSV reader splits it,
    quotes respected - a record of more or fewer would shift every value after it."""
    delimiter, expected = layout
    length, endings = 0, set()
    with open(target.path, "rb") as handle:
        handle.seek(target.offset)
        for n in range(rows):
            record = handle.readline(1 << 20)
            if not record.endswith(b"\n"):
                raise Refused(ctx.path, f"{where(target.block)}: ROWS {rows}, but record {n + 1} of "
                                        f"{target.path.name} after byte {target.offset} ends without a line end")
            endings.add(record.endswith(b"\r\n"))
            length += len(record)
            values = next(csv.reader([record.decode("latin-1").rstrip("\r\n")], delimiter=delimiter), [])
            if len(values) != expected:
                raise Refused(ctx.path, f"{where(target.block)}: record {n + 1} of {target.path.name} holds "
                                        f"{len(values)} values, the label {expected} fields (ITEMS counted)")
    if len(endings) > 1:
        raise Refused(ctx.path, f"{where(target.block)}: its records end with CR LF and with LF alike")
    return length, "Carriage-Return Line-Feed" if endings == {True} else "Line-Feed"


def _histogram(ctx: FileContext, target: Target) -> dict[str, object]:
    """A histogram: a table when it has COLUMNs, else ITEMS counts of one type as an Array_1D."""
    block = target.block
    if block.get("ROWS") is not None or any(True for _ in block.blocks("COLUMN")):
        return _table(ctx, target)
    items = positive_int(ctx, block, "ITEMS")
    item_bytes = block.number("ITEM_BYTES") or block.number("BYTES")
    if not isinstance(item_bytes, int) or item_bytes <= 0:
        raise Refused(ctx.path, f"{where(block)}: ITEM_BYTES (or BYTES) is missing or not a positive integer")
    pds3_type = (block.text("DATA_TYPE") or block.text("ITEM_TYPE") or "").upper()
    data_type = pds4_data_type(pds3_type, item_bytes * 8)
    if data_type is None:
        raise Refused(ctx.path, f"{where(block)}: DATA_TYPE {pds3_type or 'not given'} of {item_bytes} bytes has "
                                "no PDS4 data type")
    description = block.text("DESCRIPTION") or f"The {block.name} object of the PDS3 label: {items} bins."
    return {"kind": "array", "element": "Array_1D", "local_identifier": target.ident, "offset": target.offset,
            "length": items * item_bytes, "axes": [("Bin", items)], "description": " ".join(description.split()),
            "data_type": data_type, "unit": unit(block), "scaling_factor": None, "value_offset": 0.0,
            "special": [], "pds3": where(block)}


# -- arrays: ARRAY, COLLECTION, ELEMENT (PDS3 Standards, appendix A) ---------------------------------
# The subobjects an ARRAY holds (exactly one) and a COLLECTION holds (any number).
_ARRAY_PARTS = frozenset({"ELEMENT", "COLLECTION", "ARRAY"})
# PDS4's array classes by number of axes; more axes: the generic Array (up to 16).
_ARRAY_ELEMENTS = {1: "Array_1D", 2: "Array_2D", 3: "Array_3D"}
_MAX_AXES = 16


def _array(ctx: FileContext, target: Target) -> dict[str, object]:
    """An ARRAY (or a top-level COLLECTION). An array whose leaf is one number (its own DATA_TYPE,
    or an ELEMENT, nested ARRAYs adding their axes) is a PDS4 array of as many axes, in the same
    order: PDS3 and PDS4 both store the last axis fastest. An array of COLLECTIONs, or of an
    ELEMENT with BIT_ELEMENTs, is a Table_Binary of one record per leaf (the axes flattened in
    that order), the collection's ELEMENTs, COLLECTIONs and ARRAYs its fields and groups."""
    block = target.block
    interchange = (block.text("INTERCHANGE_FORMAT") or "BINARY").upper()
    if interchange not in ("BINARY", "ASCII"):
        raise Refused(ctx.path, f"{where(block)}: INTERCHANGE_FORMAT {interchange} is neither ASCII nor BINARY")
    start = block.number("START_BYTE")
    if start not in (None, 1):
        raise Refused(ctx.path, f"{where(block)}: START_BYTE {start} of an object its pointer places")
    axes: list[tuple[str, int]] = []
    if block.name.upper() == "COLLECTION":
        leaf = block
    else:
        axes, leaf = _array_shape(ctx, block)
    description = " ".join((block.text("DESCRIPTION") or f"The {block.name} object of the PDS3 label.").split())
    shape = " x ".join(f"{name} {items}" for name, items in axes)
    if interchange == "ASCII":
        return _ascii_array(ctx, target, axes, leaf, description, shape)
    if leaf.name.upper() == "COLLECTION" or any(True for name in _BIT_OBJECTS for _ in leaf.blocks(name)):
        return _array_as_table(ctx, target, axes, leaf, description, shape)
    return _array_of_numbers(ctx, target, axes, leaf, description)


def _array_shape(ctx: FileContext, block: Block, depth: int = 0) -> tuple[list[tuple[str, int]], Block]:
    """The axes (name, items), slowest first, of an ARRAY and of the ARRAYs nested in it, and the
    leaf they repeat: an ELEMENT, a COLLECTION, or the innermost ARRAY itself (DATA_TYPE and BYTES
    its own). A nested ARRAY must start its parent's element (START_BYTE 1): else it is no axis."""
    count = positive_int(ctx, block, "AXES")
    items = _axis_values(ctx, block, "AXIS_ITEMS", count)
    names = _axis_values(ctx, block, "AXIS_NAME", count, required=False)
    sizes = [n for n in items if isinstance(n, int) and n > 0]
    if len(sizes) != count:
        raise Refused(ctx.path, f"{where(block)}: AXIS_ITEMS {items} are not positive integers")
    axes = [(str(names[n]) if names else f"{block.text('NAME') or block.name}_axis_{n + 1}", sizes[n])
            for n in range(count)]
    parts = [b for b in block.blocks() if b.name.upper() in _ARRAY_PARTS]
    if len(parts) > 1:
        raise Refused(ctx.path, f"{where(block)}: an ARRAY holds one ELEMENT, COLLECTION or ARRAY, this one "
                                f"{len(parts)}")
    if not parts:
        return axes, block
    part = parts[0]
    if part.name.upper() == "ARRAY" and part.number("START_BYTE") in (None, 1):
        if depth >= MAX_NESTING:
            raise Refused(ctx.path, f"{where(part)}: ARRAYs nested more than {MAX_NESTING} deep")
        inner, leaf = _array_shape(ctx, part, depth + 1)
        return axes + inner, leaf
    if part.name.upper() == "ARRAY":
        raise Refused(ctx.path, f"{where(part)}: an ARRAY of an ARRAY that starts at byte "
                                f"{part.number('START_BYTE')} of each element, with no bytes before it described")
    return axes, part


MAX_NESTING = 8  # ARRAYs and COLLECTIONs in one another; genuine labels nest two or three


def _axis_values(ctx: FileContext, block: Block, key: str, count: int, required: bool = True) -> list[object]:
    value = block.value(key)
    if value is None:
        if required:
            raise Refused(ctx.path, f"{where(block)}: {key} is missing")
        return []
    values = [item.py for item in value.items] if value.items is not None else [value.py]
    text = str(values[0]).strip() if len(values) == 1 else ""
    if count > 1 and text.startswith("(") and text.endswith(")"):  # AXIS_NAME = "(ELEVATION, AZIMUTH)"
        values = [part.strip() for part in text[1:-1].split(",")]
    if len(values) != count:
        raise Refused(ctx.path, f"{where(block)}: {key} gives {len(values)} values for AXES = {count}")
    return values


def _array_of_numbers(ctx: FileContext, target: Target, axes: list[tuple[str, int]], leaf: Block,
                      description: str) -> dict[str, object]:
    """An array of one number per element as Array_ND: the leaf's DATA_TYPE and BYTES, its scaling,
    unit and special constants; an ELEMENT must fill the element (START_BYTE 1, no ITEMS)."""
    if len(axes) > _MAX_AXES:
        raise Refused(ctx.path, f"{where(target.block)}: {len(axes)} axes, more than PDS4's {_MAX_AXES}")
    size = positive_int(ctx, leaf, "BYTES")
    if leaf.number("START_BYTE") not in (None, 1) or leaf.get("ITEMS") is not None:
        raise Refused(ctx.path, f"{where(leaf)}: an ELEMENT that does not fill its array's element (START_BYTE "
                                f"{leaf.number('START_BYTE')}, ITEMS {leaf.number('ITEMS')})")
    pds3_type = " ".join((leaf.text("DATA_TYPE") or "").upper().split()).replace(" ", "_")
    data_type = pds4_data_type(pds3_type, size * 8)
    if data_type is None:
        raise Refused(ctx.path, f"{where(leaf)}: DATA_TYPE {pds3_type or 'not given'} of {size} bytes has no "
                                "PDS4 data type")
    elements = 1
    for _, items in axes:
        elements *= items
    scaling, value_offset = leaf.number("SCALING_FACTOR"), leaf.number("OFFSET")
    identity = scaling in (None, 1) and value_offset in (None, 0)
    return {"kind": "array", "element": _ARRAY_ELEMENTS.get(len(axes), "Array"), "pds3": where(target.block),
            "local_identifier": target.ident, "offset": target.offset, "length": elements * size, "axes": axes,
            "description": description, "data_type": data_type, "unit": unit(leaf),
            "scaling_factor": None if identity else (scaling if scaling is not None else 1.0),
            "value_offset": value_offset if value_offset is not None else 0.0,
            "special": special_constants(ctx, leaf, pds3_type in FLOAT_SAMPLE_TYPES, size * 8)}


def _array_as_table(ctx: FileContext, target: Target, axes: list[tuple[str, int]], leaf: Block,
                    description: str, shape: str) -> dict[str, object]:
    """An array of records (COLLECTIONs, or ELEMENTs with bit fields) as a Table_Binary: one
    record per leaf, axes flattened slowest first - the bytes' own order."""
    records = 1
    for _, items in axes:
        records *= items
    size = positive_int(ctx, leaf, "BYTES")
    if leaf.name.upper() == "COLLECTION":
        fields = _collection_fields(ctx, leaf, 0, [_MAX_COLUMNS], 0)
    else:
        fields = [_field(ctx, _starting_at_one(leaf), 0, False, size)]
    reach = _fields_end(fields)
    if reach > size:
        raise Refused(ctx.path, f"{where(leaf)}: its parts reach byte {reach}, past its BYTES {size}")
    if shape:
        description += f" PDS3 array of {shape}, each element a record here (the last axis fastest)."
    return {"kind": "table", "element": "Table_Binary", "local_identifier": target.ident, "offset": target.offset,
            "length": records * size, "records": records, "record_length": size, "description": description,
            "fields": fields, "delimiter": None, "pds3": where(target.block),
            "warnings": [str(f.pop("warning")) for f in fields if f.get("warning")]}


def _ascii_array(ctx: FileContext, target: Target, axes: list[tuple[str, int]], leaf: Block, description: str,
                 shape: str) -> dict[str, object]:
    """An ASCII array (the Galileo Probe NFR calibration arrays): PDS4 arrays are binary, and PDS3
    states no byte layout of an ASCII array, so the layout is read from the bytes. Each line holds
    the last axis' values, the lines run through the other axes (last fastest); when every line
    has the same length and its values lie at the same columns, evenly spaced, the array is a
    Table_Character of a record per line, the values a repeated field (the separators between
    them unnamed). Any other layout is refused, naming what does not repeat."""
    if not axes or leaf.name.upper() == "COLLECTION":
        raise Refused(ctx.path, f"{where(target.block)}: an ASCII array of COLLECTIONs has no byte layout PDS4 "
                                "can state")
    per_line = axes[-1][1]
    lines = 1
    for _, items in axes[:-1]:
        lines *= items
    layout = _ascii_layout(ctx, target, lines, per_line)
    length, ending, first, width, step = layout
    values = _ascii_values(ctx, target, lines, length, (first, width, step, per_line))
    pds3_type = " ".join((leaf.text("DATA_TYPE") or "").upper().split()).replace(" ", "_")
    data_type = ASCII_TABLE_TYPES.get(pds3_type) if pds3_type else values
    if data_type is None:
        raise Refused(ctx.path, f"{where(leaf)}: DATA_TYPE {pds3_type} has no data type in an ASCII table")
    name = leaf.text("NAME") or target.block.text("NAME") or target.block.name
    field = {"name": name, "location": 1, "length": width, "data_type": data_type, "unit": unit(leaf),
             "scaling_factor": None, "value_offset": None, "description": None, "special": [], "bits": None,
             "group": {"repetitions": per_line, "location": first, "length": per_line * step}}
    description += (f" PDS3 ASCII array of {shape}: a record per line of {per_line} values "
                    f"({axes[-1][0]}), each in {width} bytes every {step} bytes from byte {first}, the last axis "
                    "fastest.")
    return {"kind": "table", "element": "Table_Character", "local_identifier": target.ident,
            "offset": target.offset, "length": lines * length, "records": lines, "record_length": length,
            "description": description, "fields": [field], "delimiter": ending, "pds3": where(target.block),
            "warnings": []}


_VALUE = re.compile(rb"[^\s,;]+")


def _ascii_layout(ctx: FileContext, target: Target, lines: int, per_line: int) -> tuple[int, str, int, int, int]:
    """(record length, record delimiter, first slot's byte (1-based), slot width, step) of an
    ASCII array's first line: its values end evenly spaced (numbers right-aligned in fixed
    slots, as Fortran writes them: a sign or a longer number grows to the left), each slot
    the bytes between one separator and the next; the step repeated must fit before the line end."""
    with open(target.path, "rb") as handle:
        handle.seek(target.offset)
        line = handle.readline(1 << 20)
    ending = b"\r\n" if line.endswith(b"\r\n") else b"\n"
    ends = [b for _, b in (m.span() for m in _VALUE.finditer(line))]
    steps = {b - a for a, b in zip(ends, ends[1:], strict=False)}
    problem = None
    if not line.endswith(b"\n"):
        problem = "its first line has no line end"
    elif len(ends) != per_line:
        problem = f"its first line holds {len(ends)} values, not the last axis' {per_line}"
    elif len(steps) > 1:
        problem = "the values of its first line do not end evenly spaced"
    if problem is not None:
        raise Refused(ctx.path, f"{where(target.block)}: ASCII array: {problem}, so no table of fixed fields "
                                "can state it")
    step = steps.pop() if steps else ends[0]
    separator = 1 if line[ends[0]:ends[0] + 1] in (b",", b";") else 0
    width = min(step - separator, ends[0])
    first = ends[0] - width
    if first + per_line * step > len(line) - len(ending):
        raise Refused(ctx.path, f"{where(target.block)}: ASCII array: its values repeated every {step} bytes would "
                                "reach the line end, which a repeated PDS4 field may not")
    return len(line), _DELIMITERS[ending], first + 1, width, step


_DELIMITERS = {b"\r\n": "Carriage-Return Line-Feed", b"\n": "Line-Feed"}


def _ascii_values(ctx: FileContext, target: Target, lines: int, length: int,
                  layout: tuple[int, int, int, int]) -> str:
    """Every line of an ASCII array read against the first line's layout (same length, each
    value inside its slot); the values' type from the bytes: ASCII_Integer when all are integers,
    else ASCII_Real when all are numbers. Refused, naming the line, otherwise."""
    first, width, step, per_line = layout
    slots = [(first - 1 + n * step, first - 1 + n * step + width) for n in range(per_line)]
    integers = True
    with open(target.path, "rb") as handle:
        handle.seek(target.offset)
        for number in range(1, lines + 1):
            line = handle.readline(length)
            spans = [m.span() for m in _VALUE.finditer(line)]
            if len(line) != length or not line.endswith(b"\n") or len(spans) != per_line or \
                    any(not (lo <= a and b <= hi) for (a, b), (lo, hi) in zip(spans, slots, strict=True)):
                raise Refused(ctx.path, f"{where(target.block)}: ASCII array: line {number} of {target.path.name} "
                                        f"does not hold its {per_line} values in the first line's {width}-byte "
                                        "slots (or is of another length)")
            for start, end in slots:
                text = line[start:end].strip()
                try:
                    float(text)
                except ValueError:
                    raise Refused(ctx.path, f"{where(target.block)}: ASCII array: {text.decode('latin-1')!r} "
                                            f"on line {number} is no number") from None
                integers = integers and text.lstrip(b"+-").isdigit()
    return "ASCII_Integer" if integers else "ASCII_Real"


def _starting_at_one(element: Block) -> Block:
    """An array's ELEMENT, which may leave out START_BYTE (it starts its element): START_BYTE 1."""
    if element.get("START_BYTE") is not None:
        return element
    start = Statement("START_BYTE", Value("int", "1", 1, element.line), element.line)
    return Block(element.kind, element.name, element.line, element.end_line, [start, *element.items])


def _collection_fields(ctx: FileContext, collection: Block, prefix: int, budget: list[int],
                       depth: int) -> list[dict[str, object]]:
    """A COLLECTION's parts as fields (ELEMENT), groups of repetition 1 (COLLECTION) and repeated
    groups (ARRAY: its axes' product of its leaf), each at its START_BYTE in the collection."""
    if depth > MAX_NESTING:
        raise Refused(ctx.path, f"{where(collection)}: COLLECTIONs and ARRAYs nested more than {MAX_NESTING} deep")
    size = positive_int(ctx, collection, "BYTES")

    def described(part: Block) -> dict[str, object]:
        if part.name.upper() == "ELEMENT":
            return _field(ctx, part, prefix, False, size)
        return _nested_group(ctx, part, prefix, budget, depth + 1)

    parts = [part for part in collection.blocks() if part.name.upper() in _ARRAY_PARTS]
    return _gathered(ctx, collection, parts, described, budget, "has no ELEMENT, COLLECTION or ARRAY objects")


def _nested_group(ctx: FileContext, part: Block, prefix: int, budget: list[int], depth: int) -> dict[str, object]:
    """A COLLECTION or ARRAY inside a COLLECTION as a Group_Field_Binary at its START_BYTE: the
    array's elements its repetitions (axes flattened, last fastest), its leaf the group's fields."""
    start = positive_int(ctx, part, "START_BYTE")
    if part.name.upper() == "COLLECTION":
        repetitions, leaf = 1, part
    else:
        axes, leaf = _array_shape(ctx, part, depth)
        repetitions = 1
        for _, items in axes:
            repetitions *= items
    size = positive_int(ctx, leaf, "BYTES")
    if leaf.name.upper() == "COLLECTION":
        members = _collection_fields(ctx, leaf, 0, budget, depth)
    else:
        members = [_field(ctx, _starting_at_one(leaf), 0, False, size)]
    reach = _fields_end(members)
    if reach > size:
        raise Refused(ctx.path, f"{where(leaf)}: its parts reach byte {reach}, past its BYTES {size}")
    name = part.text("NAME") or part.name.lower()
    return {"name": name, "location": 1, "length": size, "group": {
        "repetitions": repetitions, "location": prefix + start, "length": repetitions * size, "name": name,
        "members": members, "description": " ".join((part.text("DESCRIPTION") or "").split()) or None}}


DESCRIBERS: dict[str, Callable[[FileContext, Target], dict[str, object]]] = {
    "header": _header, "image": _image, "table": _table, "spreadsheet": _spreadsheet,
    "histogram": _histogram, "qube": describe_qube, "array": _array,
}
# What a refusal of an object of another class says migrate describes.
DESCRIBED_OBJECTS = ", ".join(pattern for pattern, _, _ in OBJECT_CLASSES) + " objects"
