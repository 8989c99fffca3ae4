"""PDS3 data objects as the PDS4 objects that describe the same bytes.

Each function takes the label as the validator reads it (`FileContext`: the one PDS3 label
reader, its pointers resolved to files and byte offsets) and returns what the PDS4
templates render: a Header, an array or a table, at its byte offset in its file. What
PDS4 cannot state exactly is refused with `Refused`, naming the construct; nothing is
ever described approximately.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError, param
from ..label.beside import find_beside
from ..label.grammar import FLOAT_SAMPLE_TYPES, PLACEHOLDERS
from ..label.parser import LabelFile
from ..label.tree import Block, Pointer, Statement, Value
from ..pds4.model import pds4_data_type
from ..validate.context import FileContext
from .mapping import (
    ASCII_TABLE_TYPES,
    BAND_STORAGE_AXES,
    HEADER_STANDARDS,
    SPECIAL_CONSTANTS,
    SPECIAL_ORDER,
    TABLE_CLASSES,
    TEXT_FIELD_TYPES,
)


class Refused(InputError):
    """A product migration cannot describe exactly: one line, nothing written."""


@dataclass
class DataFile:
    """One file of the product and the PDS4 objects in it, in byte order."""

    path: Path
    objects: list[dict[str, object]] = field(default_factory=list)
    supplemental: bool = False  # the detached PDS3 label itself

    @property
    def name(self) -> str:
        return self.path.name


def describe_objects(ctx: FileContext) -> tuple[list[DataFile], str | None]:
    """The product's files with their objects, and the local identifier of the image the map
    projection describes (None without an image)."""
    _refuse_outside(ctx)
    files: dict[Path, DataFile] = {}
    image_id: str | None = None
    used: set[str] = set()
    for ptr in ctx.data_pointers():
        block = ctx.object_for(ptr)
        kind = _kind(ptr.name)
        if block is None:
            if ptr.form == "file":  # ^MEX_ORIENTATION_DESC = "X.TXT": a document beside the product, no data
                continue
            raise Refused(ctx.path, f"^{ptr.name} points at an object the label does not describe")
        path = _data_path(ctx, ptr)
        offset = ctx.pointer_offset(ptr)
        if offset is None:
            raise Refused(ctx.path, f"^{ptr.name}: its byte offset cannot be known (no RECORD_BYTES)")
        ident = _local_identifier(ptr.name, used)
        if kind == "header":
            described = _header(ctx, block, ident, offset)
        elif kind == "image":
            described = _image(ctx, block, ident, offset)
            if described["kind"] == "array":  # lines with prefixes are table records: no cart: for them
                image_id = image_id or ident
        elif kind == "table":
            described = _table(ctx, block, ident, offset, path)
        else:
            raise Refused(ctx.path, f"OBJECT = {ptr.name}: migrate describes IMAGE, *TABLE, *SERIES and "
                                    "*HEADER objects, not this one")
        files.setdefault(path, DataFile(path)).objects.append(described)
    for data in files.values():
        data.objects.sort(key=lambda o: int(o["offset"]))  # type: ignore[call-overload]
    if ctx.attached:
        _add_attached_label(ctx, files[ctx.path])
    result = list(files.values())
    for encoded in _compressed_files(ctx):  # JPEG 2000 of a HiRISE-style detached label
        result.append(encoded)
        image_id = image_id or str(encoded.objects[0]["local_identifier"])
    if not result:
        raise Refused(ctx.path, "has no data object pointer (^IMAGE, ^TABLE ...) or COMPRESSED_FILE to describe")
    if ctx.path not in files:  # a detached label: a header of its own (the primary file when all else is
        # supplemental: PDS4 takes no JPEG 2000 as primary data)
        primary = any(not data.supplemental for data in result)
        result.append(DataFile(ctx.path, [{"kind": "header", "local_identifier": "pds3_label", "offset": 0,
                                           "length": ctx.size, "parsing_standard_id": "PDS3",
                                           "description": "The detached PDS3 label of this product."}],
                               supplemental=primary))
    for data in result:
        _check_order(ctx, data)
    result.sort(key=lambda data: data.supplemental)  # File_Area_Observational first, as the schema orders them
    return result, image_id


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
            entry["lines"], entry["samples"] = _int(ctx, image, "LINES"), _int(ctx, image, "LINE_SAMPLES")
        found.append(DataFile(path, [entry], supplemental=True))
    return found


def _kind(name: str) -> str:
    if name.endswith("HEADER"):
        return "header"
    if name == "IMAGE" or name.endswith("_IMAGE"):
        return "image"
    if name.endswith(("TABLE", "SERIES")):
        return "table"
    return "other"


def _local_identifier(name: str, used: set[str]) -> str:
    base = name.lower()
    ident, n = base, 1
    while ident in used:
        n += 1
        ident = f"{base}_{n}"
    used.add(ident)
    return ident


def _data_path(ctx: FileContext, ptr: Pointer) -> Path:
    if ptr.form == "files":
        raise Refused(ctx.path, f"^{ptr.name} names several files; migrate describes one file per object")
    path = ctx.target_path(ptr)
    if path is None:
        raise Refused(ctx.path, f"^{ptr.name}: data file {ptr.file_name} is missing")
    return path


def _add_attached_label(ctx: FileContext, data: DataFile) -> None:
    """The attached PDS3 label as a Header: from byte 0 to the first object."""
    first = min(int(o["offset"]) for o in data.objects)  # type: ignore[call-overload]
    if first <= 0 or first < ctx.label.label_end:
        raise Refused(ctx.path, "the first data object starts inside the attached label")
    data.objects.insert(0, {"kind": "header", "local_identifier": "pds3_label", "offset": 0, "length": first,
                            "parsing_standard_id": "PDS3", "description": "The attached PDS3 label of this product."})


def _check_order(ctx: FileContext, data: DataFile) -> None:
    size = data.path.stat().st_size
    end = 0
    for obj in data.objects:
        offset, length = int(obj["offset"]), int(obj["length"])  # type: ignore[call-overload]
        if offset < end:
            raise Refused(ctx.path, f"{obj['local_identifier']} overlaps the object before it in {data.name}")
        end = offset + length
    if end > size:
        raise Refused(ctx.path, f"{data.name} has {size} bytes, fewer than its objects need ({end}); "
                                "the data file is truncated")


# -- headers -----------------------------------------------------------------------------------
def _header(ctx: FileContext, block: Block, ident: str, offset: int) -> dict[str, object]:
    kind = (block.text("TYPE") or block.text("HEADER_TYPE") or "").upper()
    if not kind and (block.text("INTERCHANGE_FORMAT") or "").upper() == "ASCII":
        kind = "ASCII"  # a text header of no named standard (a table's header lines)
    standard = HEADER_STANDARDS.get(kind)
    if standard is None:
        raise Refused(ctx.path, f"OBJECT = {block.name}: header TYPE {kind or 'not given'} has no PDS4 "
                                f"parsing standard (known: {', '.join(sorted(HEADER_STANDARDS))})")
    length = _int(ctx, block, "BYTES")
    records = block.number("RECORDS")
    if isinstance(records, int) and records > 0:
        length *= records
    return {"kind": "header", "local_identifier": ident, "offset": offset, "length": length,
            "parsing_standard_id": standard, "description": f"The {kind} header ({block.name} in the PDS3 label)."}


# -- images ------------------------------------------------------------------------------------
def _image(ctx: FileContext, block: Block, ident: str, offset: int) -> dict[str, object]:
    lines, samples = _int(ctx, block, "LINES"), _int(ctx, block, "LINE_SAMPLES")
    bands = int(block.number("BANDS") or 1)
    sample_type = (block.text("SAMPLE_TYPE") or "").upper()
    bits = _int(ctx, block, "SAMPLE_BITS")
    data_type = pds4_data_type(sample_type, bits)
    if data_type is None:
        raise Refused(ctx.path, f"OBJECT = {block.name}: SAMPLE_TYPE {sample_type or 'not given'} of {bits} bits "
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
            raise Refused(ctx.path, f"OBJECT = {block.name}: BAND_STORAGE_TYPE {storage} is not one PDS4 axes "
                                    "can state")
        element, names = "Array_3D_Image", BAND_STORAGE_AXES[storage]
    sizes = {"Line": lines, "Sample": samples, "Band": bands}
    scaling, value_offset = block.number("SCALING_FACTOR"), block.number("OFFSET")
    identity = (scaling in (None, 1) and value_offset in (None, 0))
    description = block.text("DESCRIPTION") or block.text("NOTE") or f"The {block.name} object of the PDS3 label."
    return {
        "kind": "array", "element": element, "bands": None if bands == 1 else bands,
        "local_identifier": ident, "offset": offset, "length": lines * samples * bands * bits // 8,
        "axes": [(name, sizes[name]) for name in names], "lines": lines, "samples": samples,
        "description": " ".join(description.split()),
        "data_type": data_type, "unit": _unit(block),
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
        raise Refused(ctx.path, f"OBJECT = {block.name}: line prefixes/suffixes with "
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
            "delimiter": None}


def _image_field(ctx: FileContext, block: Block, data_type: str, bits: int, location: int,
                 samples: int) -> dict[str, object]:
    scaling, value_offset = block.number("SCALING_FACTOR"), block.number("OFFSET")
    identity = (scaling in (None, 1) and value_offset in (None, 0))
    return {"name": "SAMPLES", "location": 1, "length": bits // 8, "data_type": data_type, "unit": _unit(block),
            "scaling_factor": None if identity else (scaling if scaling is not None else 1.0),
            "value_offset": None if identity else (value_offset or 0.0), "description": None,
            "special": special_constants(ctx, block, data_type.startswith("IEEE"), bits),
            "group": {"repetitions": samples, "location": location, "length": samples * bits // 8}}


def _byte_group(name: str, location: int, length: int) -> dict[str, object]:
    return {"name": name, "location": 1, "length": 1, "data_type": "UnsignedByte", "unit": None,
            "scaling_factor": None, "value_offset": None, "description": None, "special": [],
            "group": {"repetitions": length, "location": location, "length": length}}


def _unit(block: Block) -> str | None:
    unit = block.text("UNIT")
    return None if unit is None or unit.upper() in PLACEHOLDERS else unit


def special_constants(ctx: FileContext, block: Block, is_float: bool, bits: int) -> list[tuple[str, float | int]]:
    """Special_Constants in the schema's order; a based integer of a float image is its bit
    pattern (16#FF7FFFFB# is the float32 ISIS NULL, -3.4028226550889045e+38)."""
    found: dict[str, tuple[str, float | int]] = {}
    for keyword, element in SPECIAL_CONSTANTS.items():
        value = block.value(keyword)
        if value is None or value.items is not None or not value.is_number:
            continue
        number = _sample_value(value, is_float, bits)
        if element in found and found[element][1] != number:
            raise Refused(ctx.path, f"OBJECT = {block.name}: {found[element][0]} and {keyword} give two "
                                    f"different {element} values, which PDS4 cannot both state")
        found.setdefault(element, (keyword, number))
    return [(name, found[name][1]) for name in SPECIAL_ORDER if name in found]


def _sample_value(value: Value, is_float: bool, bits: int) -> float | int:
    number = value.number
    if value.kind == "based" and is_float and bits in (32, 64):
        packed = int(number).to_bytes(bits // 8, "big", signed=number < 0)
        return struct.unpack(">f" if bits == 32 else ">d", packed)[0]
    return float(number) if is_float else number


def _int(ctx: FileContext, block: Block, key: str) -> int:
    number = block.number(key)
    if not isinstance(number, int) or number <= 0:
        raise Refused(ctx.path, f"OBJECT = {block.name}: {key} is missing or not a positive integer")
    return number


# -- tables ------------------------------------------------------------------------------------
def _table(ctx: FileContext, block: Block, ident: str, offset: int, path: Path) -> dict[str, object]:
    interchange = (block.text("INTERCHANGE_FORMAT") or "").upper()
    element = TABLE_CLASSES.get(interchange)
    if element is None:
        raise Refused(ctx.path, f"OBJECT = {block.name}: INTERCHANGE_FORMAT {interchange or 'not given'} "
                                "is neither ASCII nor BINARY")
    rows, row_bytes = _int(ctx, block, "ROWS"), _int(ctx, block, "ROW_BYTES")
    prefix = int(block.number("ROW_PREFIX_BYTES") or 0)
    suffix = int(block.number("ROW_SUFFIX_BYTES") or 0)
    record_length = prefix + row_bytes + suffix
    columns = _columns(ctx, block, prefix, element == "Table_Character")
    table: dict[str, object] = {
        "kind": "table", "element": element, "local_identifier": ident, "offset": offset,
        "length": rows * record_length, "records": rows, "record_length": record_length,
        "description": " ".join((block.text("DESCRIPTION") or f"The {block.name} object of the PDS3 label.").split()),
        "fields": columns, "delimiter": None,
    }
    if element == "Table_Character":
        table["delimiter"] = _record_delimiter(ctx, block, path, offset, record_length)
    return table


def _record_delimiter(ctx: FileContext, block: Block, path: Path, offset: int, record_length: int) -> str:
    """An ASCII table's records end with CR LF (PDS3's rule) or LF: read the first record's end."""
    with open(path, "rb") as handle:
        handle.seek(offset + record_length - 2)
        end = handle.read(2)
    if end == b"\r\n":
        return "Carriage-Return Line-Feed"
    if end[-1:] == b"\n":
        return "Line-Feed"
    raise Refused(ctx.path, f"OBJECT = {block.name}: its first record does not end with CR LF or LF at "
                            "ROW_BYTES, as a PDS4 character table must")


# Bounds on what ^STRUCTURE files may expand to: no genuine table nests format files more than
# a few deep or has anywhere near this many columns, and a hostile fan-out (files including each
# other four times over) would otherwise expand to 4^19 columns.
_MAX_INCLUDE_DEPTH = 20
_MAX_COLUMNS = 100_000


def _column_blocks(ctx: FileContext, block: Block, expanded: dict[Path, list[Block]] | None = None,
                   chain: tuple[Path, ...] = ()) -> list[Block]:
    """COLUMN and CONTAINER objects in order, a ^STRUCTURE file's in its place: each file
    expanded once (`expanded`), through the files that include it (`chain`)."""
    expanded = {} if expanded is None else expanded
    found: list[Block] = []
    for item in block.items:
        if isinstance(item, Statement) and item.pointer and item.keyword.upper() == "STRUCTURE":
            path, root = _structure(ctx, item, chain)
            if path not in expanded:
                expanded[path] = _column_blocks(ctx, root, expanded, (*chain, path))
            found.extend(expanded[path])
        elif isinstance(item, Block):
            name = item.name.upper()
            if name == "COLUMN":
                found.append(item)
            elif name in ("BIT_COLUMN", "CONTAINER"):
                raise Refused(ctx.path, f"OBJECT = {block.name}: {name} objects are not described by migrate yet")
        if len(found) > _MAX_COLUMNS:
            raise Refused(ctx.path, f"OBJECT = {block.name}: more than {_MAX_COLUMNS} columns")
    return found


def _structure(ctx: FileContext, stmt: Statement, chain: tuple[Path, ...] = ()) -> tuple[Path, Block]:
    """The format file a ^STRUCTURE names, found beside the label (or in a LABEL directory),
    inside the trusted tree either way, and its parsed contents, included through the files of
    `chain`: one that includes itself or lies more than _MAX_INCLUDE_DEPTH files deep is refused."""
    name = stmt.value.text
    exact, other = ctx.resolve(name)
    path = exact or other
    volume_label_dir = ctx.path.parent.parent / "LABEL"  # a volume's format files (PDS3 Standards, 19.3)
    if path is None:
        path = find_beside(volume_label_dir, name, root=ctx.tree)
    if path is None and ctx.tree != ctx.path.parent:  # a volume given as the tree: its top LABEL/ too
        path = find_beside(ctx.tree / "LABEL", name, root=ctx.tree)
    if path is None:
        raise Refused(ctx.path, f"^STRUCTURE file {name} is missing")
    path = path.resolve()
    if path in chain:
        raise Refused(ctx.path, f"^STRUCTURE file {name} includes itself")
    if len(chain) >= _MAX_INCLUDE_DEPTH:
        raise Refused(ctx.path, f"^STRUCTURE files included more than {_MAX_INCLUDE_DEPTH} deep")
    try:
        return path, LabelFile.read(path).root
    except OSError as error:
        raise Refused(ctx.path, f"^STRUCTURE file {name}: {error.strerror or error}") from None


def _columns(ctx: FileContext, block: Block, prefix: int, character: bool) -> list[dict[str, object]]:
    fields: list[dict[str, object]] = []
    for column in _column_blocks(ctx, block):
        fields.append(_field(ctx, block, column, prefix, character))
    if not fields:
        raise Refused(ctx.path, f"OBJECT = {block.name} has no COLUMN objects")
    return fields


def _field(ctx: FileContext, table: Block, column: Block, prefix: int, character: bool) -> dict[str, object]:
    name = column.text("NAME") or "column"
    start, size = _int(ctx, column, "START_BYTE"), _int(ctx, column, "BYTES")
    pds3_type = (column.text("DATA_TYPE") or "").upper()
    items = column.number("ITEMS")
    item_bytes = int(column.number("ITEM_BYTES") or 0) if items else size
    data_type = (ASCII_TABLE_TYPES if character else TEXT_FIELD_TYPES).get(pds3_type)
    if data_type is None and not character:
        data_type = pds4_data_type(pds3_type, item_bytes * 8)
    if data_type is None:
        where = "an ASCII table" if character else "PDS4"
        raise Refused(ctx.path, f"OBJECT = {table.name}: column {name} DATA_TYPE {pds3_type or 'not given'} of "
                                f"{item_bytes} bytes has no data type in {where}")
    scaling, value_offset = column.number("SCALING_FACTOR"), column.number("OFFSET")
    entry: dict[str, object] = {
        "name": name, "location": prefix + start, "length": item_bytes, "data_type": data_type,
        "unit": _unit(column),
        "scaling_factor": scaling, "value_offset": value_offset,
        "description": " ".join((column.text("DESCRIPTION") or "").split()) or None,
        "special": special_constants(ctx, column, pds3_type in FLOAT_SAMPLE_TYPES, item_bytes * 8),
        "group": None,
    }
    if items:
        step = int(column.number("ITEM_OFFSET") or item_bytes)
        if not isinstance(items, int) or items <= 0 or item_bytes <= 0 or step < item_bytes:
            raise Refused(ctx.path, f"OBJECT = {table.name}: column {name} ITEMS/ITEM_BYTES/ITEM_OFFSET "
                                    "do not describe a repeated field")
        entry["group"] = {"repetitions": items, "location": prefix + start, "length": items * step}
        entry["location"] = 1
    return entry
