"""DLV family: a delivery (a PDS3 volume, a PDS4 bundle, its MD5 manifest) checked as a whole.

`pdsgen validate DIR` recognises a delivery by the files `pdsgen deliver` writes at its
root (archive/layout.py: MD5SUMS.TXT, INDEX/INDEX.LBL), or by a PDS4 bundle label at its root -
a label whose root element is Product_Bundle, whatever its file name. These checks
compare files with each other - the index table with its label and with every product
label, inventories with the labels present, references with their targets, the manifest
with the files - so they run once per delivery (the runner hook `DeliveryChecks`), and
their findings are reported beside each file's own.

They read everything with their own code: the index through the columns INDEX.LBL
declares (never the writer's layout), PDS3 labels with the label reader (pdsgen.label),
PDS4 labels with lxml, CSV inventories with the csv module, and MD5s streamed by
formats/checksum.py (hashlib's MD5, read in blocks). Only names come from layout.
"""

from __future__ import annotations

import csv
import io
import os
import re
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ...archive import layout
from ...label.beside import outside_tree
from ...label.parser import is_pds3_head
from ...label.tree import Block, Statement, first_statement
from ...pds4.detect import LABEL_SUFFIXES as PDS4_LABEL_SUFFIXES
from .. import facts
from ..model import Finding, Hit
from ..registry import Rule, register

if TYPE_CHECKING:
    from ...label.read import LabelCache
    from ..context import FileContext

PDS_NS = "{http://pds.nasa.gov/pds4/pds/v1}"
_FORMAT = re.compile(r"([AFIE])(\d+)(?:\.(\d+))?", re.IGNORECASE)
_TEXT_FILES = (layout.VOLDESC, layout.AAREADME)


def is_delivery(directory: Path) -> bool:
    """A directory `pdsgen deliver` made (or one laid out the same way), or any PDS4 bundle: a
    Product_Bundle label at its root, named bundle.xml, bundle_*.xml or anything else."""
    from ...archive.scan import bundle_labels

    return directory.is_dir() and ((directory / layout.MANIFEST).is_file()
                                   or (directory / layout.INDEX_DIR / layout.INDEX_LABEL).is_file()
                                   or bool(bundle_labels(directory)))


@dataclass
class _Found:
    rule: str
    file: Path
    message: str
    line: int | None = None
    keyword: str | None = None


def _read_pds3(path: Path, labels: LabelCache | None) -> Block | None:
    """A PDS3 label's tree, reading no further than its END line; None when it is no PDS3 label."""
    from ...label.read import read_pds3_label  # start-up: loaded only when a delivery is checked

    label = read_pds3_label(path, labels)
    return label.root if label is not None else None


def _first(root: Block, keyword: str) -> tuple[str | None, int | None]:
    stmt = first_statement(root, keyword)
    return (stmt.value.text, stmt.line) if stmt is not None else (None, None)


def _all_files(root: Path) -> Iterator[Path]:
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames.sort()
        for name in sorted(filenames):
            yield Path(dirpath) / name


# --- PDS3: the index table --------------------------------------------------------------------

@dataclass
class _Column:
    name: str
    data_type: str
    start: int
    size: int
    format: str | None
    line: int


def _index_columns(label: Block, found: list[_Found], path: Path) -> tuple[Block | None, list[_Column]]:
    table = next((b for b in label.walk() if b.kind == "OBJECT" and b.name.upper().endswith("TABLE")), None)
    if table is None:
        found.append(_Found("DLV-001", path, "no INDEX_TABLE object"))
        return None, []
    columns: list[_Column] = []
    for block in table.blocks("COLUMN"):
        start, size = block.number("START_BYTE"), block.number("BYTES")
        if not isinstance(start, int) or not isinstance(size, int):
            found.append(_Found("DLV-001", path, "a COLUMN without integer START_BYTE and BYTES", block.line))
            continue
        columns.append(_Column((block.text("NAME") or "").upper(), (block.text("DATA_TYPE") or "").upper(),
                               start, size, block.text("FORMAT"), block.line))
    return table, columns


def _table_file(label: Block, label_path: Path) -> Path | None:
    """The file the label's table pointer (^INDEX_TABLE = "INDEX.TAB") names, beside the label."""
    for stmt in label.statements():
        if stmt.pointer and stmt.keyword.upper().endswith("TABLE"):
            for value in stmt.value.scalars():
                if value.kind in ("string", "ident"):  # one outside the label's directory is not read
                    return label_path.parent / value.text if not outside_tree(label_path.parent, value.text) else None
    return None


def _field(row: bytes, column: _Column, number: int, path: Path, found: list[_Found]) -> str | None:
    """One field's text as the column states it, or None after a DLV-001 finding."""
    begin, end = column.start - 1, column.start - 1 + column.size
    text = row[begin:end].decode("ascii", errors="replace")
    where = f"row {number}, column {column.name}"
    if column.data_type == "CHARACTER":
        if row[begin - 1:begin] != b'"' or row[end:end + 1] != b'"':
            found.append(_Found("DLV-001", path, f"{where}: the value is not between the double quotes "
                                                 f"START_BYTE {column.start} and BYTES {column.size} place",
                                number))
            return None
        return text.strip()
    value = text.strip()
    try:
        float(value) if column.data_type == "ASCII_REAL" else int(value)
    except ValueError:
        found.append(_Found("DLV-001", path, f"{where}: {text!r} is not {column.data_type}", number))
        return None
    match = _FORMAT.fullmatch(column.format or "")
    if match and match.group(3) is not None and match.group(1).upper() == "F":
        decimals = len(value.split(".", 1)[1]) if "." in value else 0
        if decimals != int(match.group(3)):
            found.append(_Found("DLV-001", path, f"{where}: {value} has {decimals} decimals, FORMAT "
                                                 f"{column.format} states {match.group(3)}", number))
    return value


def _same(row_value: str, label_value: str | None, data_type: str, column_format: str | None) -> bool:
    """Whether a row holds its label's value. A keyword the label does not have cannot be compared
    (archives' indexes carry derived columns); it passes."""
    if label_value is None:
        return True
    if data_type == "CHARACTER":
        return row_value.strip().upper() == label_value.strip().upper()
    match = _FORMAT.fullmatch(column_format or "")
    decimals = int(match.group(3)) if match and match.group(3) else 0
    return _number_equal(row_value, label_value, decimals)


def _number_equal(a: str, b: str, decimals: int) -> bool:
    try:
        return abs(float(a) - float(b)) <= 0.5 * 10.0 ** -decimals + 1e-12 * max(1.0, abs(float(b)))
    except ValueError:
        return False


def _check_index(root: Path, found: list[_Found], labels: LabelCache | None) -> None:
    label_path = root / layout.INDEX_DIR / layout.INDEX_LABEL
    table_path = root / layout.INDEX_DIR / layout.INDEX_TABLE
    # one string per product (not a Path): memory stays small for 10,000 products
    products = {name.upper(): name for name in (p.relative_to(root).as_posix() for p in _pds3_products(root))}
    if not label_path.is_file():  # a PDS4 bundle alone has no index; a PDS3 volume (VOLDESC.CAT) must
        if products and (root / layout.VOLDESC).is_file():
            found.append(_Found("DLV-002", root / layout.VOLDESC,
                                f"a PDS3 volume without {layout.INDEX_DIR}/{layout.INDEX_LABEL}"))
        return
    label = _read_pds3(label_path, labels)
    if label is None:
        found.append(_Found("DLV-001", label_path, "not a PDS3 label"))
        return
    table, columns = _index_columns(label, found, label_path)
    if table is None:
        return
    table_path = _table_file(label, label_path) or table_path
    row_bytes, rows = table.number("ROW_BYTES"), table.number("ROWS")
    volume_ids = {label.text("VOLUME_ID")} | {_text_value(root / layout.VOLDESC, "VOLUME_ID", labels)}
    declared = {name.upper() for name in _set_of(label, "DATA_SET_ID")}
    seen: dict[str, int] = {}
    count = 0
    try:
        with open(table_path, "rb") as stream:  # row by row: memory does not grow with the table
            for count, line in enumerate(stream, 1):
                if not line.endswith(b"\r\n"):
                    found.append(_Found("DLV-001", table_path, f"row {count} does not end with CR LF", count))
                    continue
                raw = line[:-2]
                if row_bytes is not None and len(line) != row_bytes:
                    found.append(_Found("DLV-001", table_path, f"row {count} has {len(line)} bytes with its "
                                                               f"CR LF, ROW_BYTES = {row_bytes}", count))
                    continue
                values = {c.name: _field(raw, c, count, table_path, found) for c in columns}
                _check_row(root, table_path, count, values, columns, seen, volume_ids, found, labels)
                _check_row_data_set(table_path, count, values.get("DATA_SET_ID"), declared, found)
    except OSError as exc:
        found.append(_Found("DLV-001", table_path, f"cannot read the index table: {exc.strerror or exc}"))
        return
    if rows is not None and rows != count:
        found.append(_Found("DLV-001", table_path, f"ROWS = {rows} in {layout.INDEX_LABEL}, but the table has "
                                                   f"{count} rows"))
    for key, name in products.items():
        if key not in seen:
            found.append(_Found("DLV-002", root / name, f"this data product is not in {layout.INDEX_DIR}/"
                                                 f"{layout.INDEX_TABLE}"))
    _check_data_sets(root, label, table_path, found, labels)


def _check_row(root: Path, table_path: Path, number: int, values: dict[str, str | None], columns: list[_Column],
               seen: dict[str, int], volume_ids: set[str | None],
               found: list[_Found], labels: LabelCache | None) -> None:
    spec = values.get("FILE_SPECIFICATION_NAME")
    if spec is None:
        return
    volume_id = values.get("VOLUME_ID")
    if volume_id is not None and len({v for v in volume_ids if v} | {volume_id}) > 1:
        found.append(_Found("DLV-005", table_path, f"row {number}: VOLUME_ID {volume_id} differs from the volume's "
                                                   f"({', '.join(sorted(v for v in volume_ids if v))})", number))
    key = spec.upper()
    named, problem = _named_inside(root, spec)
    if named is None:
        found.append(_Found("DLV-003", table_path, f"row {number} names {spec!r}, which is not a file inside the "
                                                   f"delivery ({problem})", number))
        return
    if not named.is_file():
        found.append(_Found("DLV-003", table_path, f"row {number} names {spec}, which does not exist", number))
        return
    if key in seen:
        found.append(_Found("DLV-002", table_path, f"row {number} indexes {spec} again (first in row "
                                                   f"{seen[key]})", number))
        return
    seen[key] = number
    product = _read_pds3(named, labels)
    if product is None:
        found.append(_Found("DLV-003", table_path, f"row {number} names {spec}, which is not a PDS3 label", number))
        return
    for column in columns:
        if column.name in ("VOLUME_ID", "FILE_SPECIFICATION_NAME"):
            continue
        row_value = values.get(column.name)
        if row_value is None:
            continue
        label_value, line = _first(product, column.name)
        if not _same(row_value, label_value, column.data_type, column.format):
            found.append(_Found("DLV-004", table_path, f"row {number} ({spec}): {column.name} = {row_value}, "
                                                       f"but its label has {label_value or 'none'}"
                                                       + (f" (line {line})" if line else ""), number, column.name))


def _check_row_data_set(table_path: Path, number: int, data_set: str | None, declared: set[str],
                        found: list[_Found]) -> None:
    """DLV-005: a row's DATA_SET_ID (its label's, DLV-004) is one INDEX.LBL declares (and so, by
    _check_data_sets, VOLDESC.CAT)."""
    if data_set and declared and data_set.strip().upper() not in declared:
        found.append(_Found("DLV-005", table_path, f"row {number}: DATA_SET_ID {data_set.strip()} is not declared in "
                                                   f"{layout.INDEX_LABEL} ({', '.join(sorted(declared))}) nor "
                                                   f"{layout.VOLDESC}", number, "DATA_SET_ID"))


def _check_data_sets(root: Path, index_label: Block, table_path: Path, found: list[_Found],
                     labels: LabelCache | None) -> None:
    """DATA_SET_ID of INDEX.LBL and VOLDESC.CAT name the same data sets."""
    index_sets = _set_of(index_label, "DATA_SET_ID")
    voldesc = _read_pds3(root / layout.VOLDESC, labels)
    if voldesc is None:
        return
    volume = next(voldesc.find("VOLUME"), voldesc)
    volume_sets = _set_of(volume, "DATA_SET_ID")
    if index_sets != volume_sets:
        found.append(_Found("DLV-005", root / layout.VOLDESC, f"DATA_SET_ID {', '.join(sorted(volume_sets))} "
                            f"differs from {layout.INDEX_LABEL}'s {', '.join(sorted(index_sets))}"))


def _set_of(block: Block, keyword: str) -> set[str]:
    value = block.value(keyword)
    return {v.text for v in value.scalars()} if value is not None else set()


def _text_value(path: Path, keyword: str, labels: LabelCache | None) -> str | None:
    label = _read_pds3(path, labels)
    if label is None:
        return None
    return _first(label, keyword)[0]


def _pds3_products(root: Path) -> Iterator[Path]:
    """PDS3 product labels of the volume's DATA directory."""
    data = root / layout.DATA_DIR
    if not data.is_dir():
        return
    for path in _all_files(data):
        if path.suffix.lower() in (*PDS4_LABEL_SUFFIXES, ".txt", ".csv", ".jp2", ".jpg"):
            continue
        if path.suffix.lower() == ".lbl" or is_pds3_head(_read_head(path)):
            yield path


def _read_head(path: Path) -> bytes:
    try:
        with open(path, "rb") as stream:
            return stream.read(32)
    except OSError:
        return b""


# --- placeholders -------------------------------------------------------------------------------

def _check_placeholders(root: Path, found: list[_Found]) -> None:
    from ...archive.scan import bundle_labels

    files = [root / name for name in _TEXT_FILES] + bundle_labels(root)
    files += [root / directory / layout.collection_label_name(c) for c, (_, _, directory) in
              layout.COLLECTIONS.items()]
    for path in files:
        try:
            text = path.read_text(encoding="latin-1")
        except OSError:
            continue
        for match in layout.PLACEHOLDER_PATTERN.finditer(text):
            number = text.count("\n", 0, match.start()) + 1
            found.append(_Found("DLV-006", path, "text still to be written: " + " ".join(match.group(0).split()),
                                number))


# --- identification keywords that say nothing (DLV-007, DLV-008) ---------------------------------
# A product made without a params file carries "UNK" in DATA_SET_ID, PRODUCER_*, INSTRUMENT_* ...: a
# label a reader can open, but one that does not say whose data it is or where they come from. While
# a product is being made that is a step on the way (`pdsgen dtm` and `pdsgen ortho` warn about it
# then); in a delivery, and in any product validated alone, it is text still to be written, like a
# [TO BE WRITTEN: ...] placeholder (DLV-006). So the check runs on every product label, whatever
# holds it (a file alone, a product directory, a PDS3 volume, a PDS4 bundle): DLV-007 on a PDS3
# product label, DLV-008 on a PDS4 label (a rule takes one kind of file, registry.Rule.target).
# Genuine archives hold such values too, so a warning, not an error; --strict fails on it, and the
# validation summary counts both (report.PLACEHOLDER_RULES).

_UNSTATED = frozenset({"UNK", "N/A", "UNKNOWN", "NULL"})


def unstated_identification(root: Block) -> Iterator[Statement]:
    """Each top-level identification keyword (params.IDENTIFICATION_KEYWORDS) of a product label
    whose value is "UNK" or "N/A" (every value, for a list)."""
    from ...params import IDENTIFICATION_KEYWORDS  # loaded when a delivery is checked, not by every validation

    for stmt in root.statements():
        if stmt.pointer or stmt.keyword.upper() not in IDENTIFICATION_KEYWORDS:
            continue
        values = [str(value.py).strip().upper() for value in stmt.value.scalars()]
        if values and all(value in _UNSTATED for value in values):
            yield stmt


def _unstated_message(stmt: Statement) -> str:
    return (f"{stmt.value.raw.strip()}: not stated (write it in a params file, `pdsgen params --template PROFILE` "
            "lists every keyword, and make the product again)")


_PRODUCT_OBJECTS = frozenset({"IMAGE", "IMAGE_MAP_PROJECTION", "SPECTRAL_QUBE", "QUBE", "TABLE", "ARRAY"})


def _is_product_label(root: Block) -> bool:
    """A PDS3 label of a product (PRODUCT_ID, or a data object), not a catalog file or an index."""
    if root.get("PRODUCT_ID") is not None:
        return True
    return any(block.kind == "OBJECT" and block.name.upper() in _PRODUCT_OBJECTS for block in root.blocks())


def check_pds4_unstated(label: object) -> list[Hit]:
    """DLV-008: a PDS4 label names its investigation, observing system and targets (identity_rules
    reads them; imported here when run, so that the IDN family registers after this one)."""
    from .identity_rules import pds4_unstated_check

    return pds4_unstated_check(label)


def check_unstated(ctx: FileContext) -> Iterator[Hit]:
    """DLV-007: a PDS3 product label's identification keywords are stated, not UNK or N/A."""
    if _is_product_label(ctx.root):
        for stmt in unstated_identification(ctx.root):
            yield Hit(_unstated_message(stmt), stmt.line, stmt.keyword)


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
        lines = path.read_text(encoding="latin-1").splitlines()
    except OSError:
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


def _jp2_header(path: Path) -> tuple[int, int, int, int] | None:
    """(samples, lines, bands, bits) of a JP2's header, or None for a file that is none (the
    image rules say why)."""
    from ..geojp2 import Jp2Error, read_jp2

    try:
        info = read_jp2(path)
    except Jp2Error:
        return None
    return info.width, info.height, info.bands, info.bits


def check_jp2info(ctx: FileContext) -> Iterator[Hit]:
    """DLV-025: the JP2INFO.TXT a COMPRESSED_FILE's ^DESCRIPTION names describes the JP2 beside it."""
    for block in ctx.root.walk():
        if block.kind != "OBJECT" or block.name.upper() != "COMPRESSED_FILE":
            continue
        jp2_name, info_name = block.text("FILE_NAME"), block.text("^DESCRIPTION")
        if not jp2_name or not info_name or ctx.outside(jp2_name) or ctx.outside(info_name):
            continue
        jp2, info = ctx.resolve(jp2_name)[0], ctx.resolve(info_name)[0]
        if jp2 is None or info is None or not jp2.is_file() or not info.is_file():
            continue  # a missing file is the pointer rules'
        entry = jp2info_entries(info).get(jp2_name.upper())
        header = _jp2_header(jp2) if entry is not None else None
        if entry is not None and header is not None and entry[:4] != header:
            yield Hit(f"describes {jp2_name} as {_shape(entry[:4])}, but the JP2 is {_shape(header)}: "
                      f"{info.name} was written for another version of the JP2 (make the product again, or "
                      "deliver the JP2INFO.TXT made with it)", entry[4], file=str(info))


def _shape(values: tuple[int, int, int, int]) -> str:
    samples, lines, bands, bits = values
    return f"{samples} samples x {lines} lines, {bands} band(s), {bits} bits"


def _check_quick_looks(root: Path, found: list[_Found], labels: LabelCache | None) -> None:
    """DLV-026: each quick-look JP2 README.TXT lists is its product at full scale: the size of the
    image its delivered label describes (archive/extras_check finds the product of each entry)."""
    from ...archive.extras_check import product_of, read_entries, readmes

    for readme in readmes(root):
        for entry in read_entries(readme):
            product = product_of(root, readme, entry)
            label = _read_pds3(product, labels) if product is not None else None
            image = next(label.find("IMAGE"), None) if label is not None else None
            if product is None or image is None:
                continue
            samples, lines = image.number("LINE_SAMPLES"), image.number("LINES")
            for name, _ in entry.files:
                path = readme.parent / name
                header = _jp2_header(path) if name.upper().endswith(".QLOOK.JP2") and path.is_file() else None
                if header is not None and (header[0], header[1]) != (samples, lines):
                    found.append(_Found("DLV-026", path, f"{header[0]} samples x {header[1]} lines, but the "
                                                         f"quick look of {product.name} is the product at full "
                                                         f"scale ({samples} samples x {lines} lines): a quick look "
                                                         f"of another version of the product (pdsgen extras "
                                                         f"{product.name} -o {readme.parent.name} --overwrite)"))


# --- PDS4: bundle, collections, inventories, references -----------------------------------------

@dataclass
class _Pds4Label:
    path: Path
    product_class: str
    lid: str
    version: str
    references: list[tuple[str, int]] = field(default_factory=list)  # (lid or lidvid, line), not members
    members: list[tuple[str, str, int]] = field(default_factory=list)  # a bundle's (lidvid, status, line)
    inventory: Path | None = None
    described: list[Path] = field(default_factory=list)  # the files its File and Document_File areas name
    times: tuple[str | None, str | None] = (None, None)  # Time_Coordinates start and stop, as written
    corner: tuple[float, float, float] | None = None  # cart: upper-left corner x, y and pixel_resolution_x, metres

    @property
    def lidvid(self) -> str:
        return f"{self.lid}::{self.version}"


@facts.fact("pds4")
def _read_pds4(path: Path) -> _Pds4Label | None:
    from lxml import etree

    try:
        tree = etree.parse(str(path), etree.XMLParser(no_network=True, resolve_entities=False))
    except (OSError, etree.XMLSyntaxError):
        return None  # PDS4-001 reports it
    root = tree.getroot()
    if not isinstance(root.tag, str) or not root.tag.startswith(PDS_NS + "Product_"):
        return None
    area = root.find(f"{PDS_NS}Identification_Area")
    lid = (area.findtext(f"{PDS_NS}logical_identifier") or "").strip() if area is not None else ""
    version = (area.findtext(f"{PDS_NS}version_id") or "").strip() if area is not None else ""
    label = _Pds4Label(path, root.tag[len(PDS_NS):], lid, version)
    member_entries = set(root.iter(f"{PDS_NS}Bundle_Member_Entry"))
    for tag in ("lidvid_reference", "lid_reference"):
        for element in root.iter(f"{PDS_NS}{tag}"):
            reference = ((element.text or "").strip(), element.sourceline or 0)
            entry = element.getparent()
            if entry in member_entries:
                status = (entry.findtext(f"{PDS_NS}member_status") or "").strip()
                label.members.append((reference[0], status, reference[1]))
            else:
                label.references.append(reference)
    name = root.findtext(f"{PDS_NS}File_Area_Inventory/{PDS_NS}File/{PDS_NS}file_name")
    if name and not outside_tree(path.parent, name.strip()):  # one outside the label's directory is not read
        label.inventory = path.parent / name.strip()
    label.described = described_files(root, path)
    coordinates = root.find(f"{PDS_NS}Observation_Area/{PDS_NS}Time_Coordinates")
    if coordinates is not None:
        label.times = (coordinates.findtext(f"{PDS_NS}start_date_time"),
                       coordinates.findtext(f"{PDS_NS}stop_date_time"))
    label.corner = _cart_corner(root)
    return label


_CART_NS = "{http://pds.nasa.gov/pds4/cart/v1}"
_METRES = {"m": 1.0, "km": 1000.0, "m/pixel": 1.0, "km/pixel": 1000.0}


def _cart_corner(root: object) -> tuple[float, float, float] | None:
    """cart:Geo_Transformation's upper-left corner and cart:pixel_resolution_x, in metres."""
    values = []
    for tag in ("upperleft_corner_x", "upperleft_corner_y", "pixel_resolution_x"):
        element = next(root.iter(f"{_CART_NS}{tag}"), None)  # type: ignore[attr-defined]
        if element is None:
            return None
        try:
            values.append(float((element.text or "").strip()) * _METRES.get(element.get("unit", "m"), 1.0))
        except ValueError:
            return None
    return values[0], values[1], values[2]


def described_files(root: object, path: Path) -> list[Path]:
    """The files a PDS4 label describes, read from its parsed tree (comments are no elements,
    CDATA is text): each file_name of a File or Document_File, the latter under its
    directory_path_name (relative to the label's directory)."""
    files = []
    for element in root.iter(f"{PDS_NS}file_name"):  # type: ignore[attr-defined]
        name = (element.text or "").strip()
        parent = element.getparent()
        directory = (parent.findtext(f"{PDS_NS}directory_path_name") or "").strip() if parent is not None else ""
        if name:
            files.append(Path(os.path.normpath(path.parent / directory / name)))
    return files


def _check_bundle(root: Path, found: list[_Found], cache: LabelCache | None = None) -> None:
    named = (path for path in _all_files(root) if path.suffix.lower() in PDS4_LABEL_SUFFIXES)
    labels = [label for label in (facts.of(_read_pds4, path) for path in named) if label is not None]
    bundles = [label for label in labels if label.product_class == "Product_Bundle"]
    if not bundles:
        return
    by_lidvid: dict[str, _Pds4Label] = {}
    by_lid: dict[str, list[_Pds4Label]] = {}
    for label in labels:
        other = by_lidvid.get(label.lidvid)
        if other is not None:
            found.append(_Found("DLV-012", label.path, f"LIDVID {label.lidvid} is also that of "
                                                       f"{other.path.relative_to(root)}"))
        by_lidvid.setdefault(label.lidvid, label)
        by_lid.setdefault(label.lid, []).append(label)
    versions = _versions([b for b in bundles if b.lid == bundles[0].lid])  # a bundle may keep its release history
    bundle = versions[-1]
    collections = [label for label in labels if label.product_class == "Product_Collection"]
    listed = {ref for version in versions for ref, _, _ in version.members}
    for collection in collections:  # a collection version belongs to the bundle versions that list it
        if collection.lidvid not in listed and collection.lid not in listed:
            found.append(_Found("DLV-015", bundle.path, f"{_which_bundle(versions)} collection {collection.lidvid} "
                                                        f"({collection.path.relative_to(root)})"))
    for version in versions:  # each version against its own members
        for ref, status, line in version.members:  # a secondary member is another bundle's: not looked for
            if status.lower() == "primary" and ref not in by_lidvid and ref not in by_lid:
                found.append(_Found("DLV-015", version.path, f"primary member {ref} is no collection of this "
                                                             "delivery", line))
    owned = bundle.lid + ":"
    for label in labels:
        for ref, line in label.references:
            if ref.startswith(owned) and ref not in by_lidvid and ref not in by_lid:
                found.append(_Found("DLV-014", label.path, f"{ref} is no product of this delivery (one "
                                                           "delivered apart, or a mistyped LID)", line))
    members: dict[str, Path] = {}
    listed_by_lid: dict[str, set[str] | None] = {}
    for collection in collections:
        inventoried = _check_inventory(root, collection, by_lidvid, members, found)
        known = listed_by_lid.get(collection.lid, set())
        listed_by_lid[collection.lid] = None if inventoried is None or known is None else known | inventoried
    for lid, listed_in_any in listed_by_lid.items():
        if listed_in_any is not None:
            _check_unlisted(_versions([c for c in collections if c.lid == lid]), listed_in_any, labels, found)
    _check_unlabelled(root, labels, found)
    if (root / layout.VOLDESC).is_file():
        _check_both_dialects(root, labels, found, cache)


def _check_both_dialects(root: Path, labels: list[_Pds4Label], found: list[_Found],
                         cache: LabelCache | None) -> None:
    """A delivery that is a PDS3 volume and a PDS4 bundle holds one product set, each product
    told alike in both: DLV-024 a product of one dialect only; DLV-022 PDS3 START_TIME/STOP_TIME
    against PDS4 Time_Coordinates; DLV-023 the PDS3 map grid against cart: (the ground
    position of the upper-left pixel corner, to half a pixel). A PDS3 product and a PDS4 label
    are one product when the label describes a file of the PDS3 product's name (X.IMG, X.JP2)."""
    observational: dict[tuple[str, str], _Pds4Label] = {}
    data = root / layout.DATA_DIR
    for label in labels:  # the data products: those of DATA/, where the volume's are (_pds3_products)
        if label.product_class == "Product_Observational" and data in label.path.parents:
            for path in label.described:
                observational.setdefault(_product_key(Path(path)), label)
    paired: set[int] = set()
    for product in _pds3_products(root):
        pds4 = observational.get(_product_key(product))
        if pds4 is None:
            found.append(_Found("DLV-024", product, "in the PDS3 volume, but no PDS4 label of the bundle describes "
                                                    "this product"))
            continue
        paired.add(id(pds4))
        pds3 = _read_pds3(product, cache)  # the run's cache: each label parsed once
        if pds3 is not None:
            _compare_times(product, pds3, pds4, found)
            _compare_grids(product, pds3, pds4, found)
    for label in {id(label): label for label in observational.values()}.values():
        if id(label) not in paired:
            found.append(_Found("DLV-024", label.path, "in the PDS4 bundle, but the PDS3 volume has no label of this "
                                                       "product"))


def _product_key(path: Path) -> tuple[str, str]:
    return os.path.normpath(path.parent), path.name.split(".", 1)[0].upper()


def _compare_times(product: Path, pds3: Block, pds4: _Pds4Label, found: list[_Found]) -> None:
    from .identity_rules import parse_time

    for keyword, element, written in (("START_TIME", "start_date_time", pds4.times[0]),
                                      ("STOP_TIME", "stop_date_time", pds4.times[1])):
        text, line = _first(pds3, keyword)
        mine, theirs = parse_time(text), parse_time(written)
        if mine is not None and theirs is not None and abs((mine - theirs).total_seconds()) > 1.0:
            found.append(_Found("DLV-022", pds4.path, f"{element} {(written or '').strip()} differs from {keyword} "
                                                      f"{text} of the PDS3 label {product.name}"
                                                      + (f" (line {line})" if line else ""), None, element))


def _compare_grids(product: Path, pds3: Block, pds4: _Pds4Label, found: list[_Found]) -> None:
    projection = next(pds3.find("IMAGE_MAP_PROJECTION"), None)
    if projection is None or pds4.corner is None:
        return
    scale_value = projection.value("MAP_SCALE")
    samples, lines = projection.number("SAMPLE_PROJECTION_OFFSET"), projection.number("LINE_PROJECTION_OFFSET")
    if scale_value is None or not isinstance(samples, (int, float)) or not isinstance(lines, (int, float)):
        return
    try:
        scale = float(str(scale_value.py)) * (1000.0 if "KM" in (scale_value.unit or "").upper() else 1.0)
    except ValueError:
        return
    if abs(pds4.corner[2] - scale) > 1e-6 * scale:
        return  # MAP_SCALE at another radius than the projection's (HRSC's DLR convention): not this check's model
    ulx, uly = -(samples + 0.5) * scale, (lines + 0.5) * scale  # the corner, half a pixel beyond the first centre
    east, north = (pds4.corner[0] - ulx) / scale, (pds4.corner[1] - uly) / scale
    if abs(east) > 0.5 or abs(north) > 0.5:
        x, y, resolution = pds4.corner
        found.append(_Found("DLV-023", pds4.path, f"cart: upper-left corner ({x:.3f}, {y:.3f}) m at {resolution:g} "
                                                  f"m/pixel lies {east:+.2f} pixel east, {north:+.2f} pixel north of "
                                                  f"the grid of the PDS3 label {product.name} ({ulx:.3f}, {uly:.3f}) m "
                                                  f"at {scale:g} m/pixel"))


def _check_unlabelled(root: Path, labels: list[_Pds4Label], found: list[_Found]) -> None:
    """DLV-016: every file of a bundle is a label or described by one (NASA's validate: a
    warning, UNLABELED_FILE 'warning.file.not_referenced_in_label'). Not files of no delivery
    (the review pages, the release marker); in a delivery that is a PDS3 volume too, not the
    volume's own (VOLDESC.CAT, AAREADME.TXT, INDEX/, CATALOG/, PDS3 labels)."""
    described = {os.path.normpath(label.path) for label in labels}
    described |= {os.path.normpath(p) for label in labels for p in label.described}
    volume = (root / layout.VOLDESC).is_file()
    stems = {(os.path.dirname(p), os.path.basename(p).split(".", 1)[0].upper()) for p in described}
    for path in _all_files(root):
        relative = path.relative_to(root)
        name = relative.as_posix()
        if os.path.normpath(path) in described or name == layout.RELEASED_MARKER or layout.is_review_page(name):
            continue
        if (volume and _volume_part(relative)) or _pds3_label_of_described(path, stems):
            continue
        if path.suffix.lower() in PDS4_LABEL_SUFFIXES and not path.name.lower().endswith(".aux.xml"):
            continue  # taken for a label (NASA's validate too: an empty foo.xml in its suite case 482-4 is none)
        found.append(_Found("DLV-016", path, _unlabelled_message(path)))


def _volume_part(relative: Path) -> bool:
    """A file of the PDS3 volume that shares the delivery with the bundle."""
    return (relative.as_posix() in (layout.VOLDESC, layout.AAREADME, layout.MANIFEST)
            or relative.parts[0] in (layout.INDEX_DIR, layout.CATALOG_DIR))


def _pds3_label_of_described(path: Path, stems: set[tuple[str, str]]) -> bool:
    """A product's detached PDS3 label kept beside the data its PDS4 label describes (X.LBL beside
    a described X.JP2): the same product in the other dialect, not an unlabelled file."""
    key = (os.path.normpath(path.parent), path.name.split(".", 1)[0].upper())
    return key in stems and (path.suffix.lower() == ".lbl" or is_pds3_head(_read_head(path)))


def _unlabelled_message(path: Path) -> str:
    if path.name.lower().endswith(".aux.xml"):
        return ("a GDAL .aux.xml sidecar (statistics GDAL wrote beside a file it opened): no label describes it; "
                "remove it from the bundle")
    if path.name == layout.MANIFEST:
        return (f"no label describes {layout.MANIFEST}: a bundle's checksum manifest is a product with a label "
                f"({layout.MANIFEST_LABEL}, a Product_Ancillary with a Checksum_Manifest; pdsgen deliver writes it)")
    return "no PDS4 label of the bundle describes this file (name it in a label's File, or remove it)"


def _version_key(label: _Pds4Label) -> tuple[int, ...]:
    """version_id M.N compared as numbers (1.10 after 1.9); one not of that form sorts first."""
    try:
        return tuple(int(part) for part in label.version.split("."))
    except ValueError:
        return ()


def _versions(labels: list[_Pds4Label]) -> list[_Pds4Label]:
    """The versions of one LID, oldest first: a bundle directory may keep its release history
    (SPICE archives keep every version of the bundle and of each collection)."""
    return sorted(labels, key=_version_key)


def _which_bundle(versions: list[_Pds4Label]) -> str:
    """The subject of DLV-015's 'does not list': the bundle, or each of its versions."""
    if len(versions) == 1:
        return "the bundle does not list"
    return f"no version of the bundle ({', '.join(v.version for v in versions)}) lists"


def _check_unlisted(versions: list[_Pds4Label], listed: set[str], labels: list[_Pds4Label],
                    found: list[_Found]) -> None:
    """DLV-011: a product under the collection's LID is in the inventory of a version of the
    collection. A newer version need not list an older one's product again: a product's
    membership follows the latest version that lists it (older versions' inventories are
    complete for their own release only, so they are not asked for newer products)."""
    collection = versions[-1]
    prefix = collection.lid + ":"
    names = ", ".join(v.inventory.name for v in versions if v.inventory is not None)
    where = "the inventory" if len(versions) == 1 else "any inventory"
    for label in labels:
        if label.lid.startswith(prefix) and label.lidvid not in listed and label.lid not in listed:
            found.append(_Found("DLV-011", label.path, f"{label.lidvid} is not in {where} of "
                                                       f"{collection.lid} ({names})"))


def _check_inventory(root: Path, collection: _Pds4Label, by_lidvid: dict[str, _Pds4Label],
                     members: dict[str, Path], found: list[_Found]) -> set[str] | None:
    """The inventory of one version of a collection, checked against its own members: what
    it lists (for DLV-011 across the versions), or None when it has none to read."""
    if collection.inventory is None:
        return None
    try:
        text = collection.inventory.read_text(encoding="ascii", errors="replace")
    except OSError as exc:
        found.append(_Found("DLV-010", collection.path, f"cannot read its inventory {collection.inventory.name}: "
                                                        f"{exc.strerror or exc}"))
        return None
    prefix = collection.lid + ":"
    listed: set[str] = set()
    for number, row in enumerate(csv.reader(io.StringIO(text)), 1):
        if len(row) < 2:
            continue
        entry = row[1].strip()
        lid = entry.split("::", 1)[0]
        secondary = row[0].strip().upper() == "S"  # another collection's product: not looked for here
        present = entry in by_lidvid  # an absent member is DLV-010's, whatever its LID (as NASA's validator)
        if not secondary and present and not lid.startswith(prefix):
            found.append(_Found("DLV-013", collection.inventory, f"member {entry} is not under the collection's "
                                                                 f"LID {collection.lid}", number))
        if not secondary:  # a product is primary in one collection, secondary in any number
            if entry in members and members[entry] != collection.inventory:  # a repeat within one: PDS4-056
                found.append(_Found("DLV-012", collection.inventory, f"{entry} is also listed in "
                                                                     f"{members[entry].relative_to(root)}", number))
            members.setdefault(entry, collection.inventory)
        listed.add(entry)
        if secondary:
            continue
        if "::" not in entry:  # the Standards Reference: a primary member is named by its LIDVID
            found.append(_Found("DLV-010", collection.inventory, f"primary member {entry} has no version (::M.N): "
                                                                 "a primary member is named by its LIDVID", number))
        elif not present:
            found.append(_Found("DLV-010", collection.inventory, f"primary member {entry} is listed, but no label "
                                                                 "in the delivery has that LIDVID", number))
    return listed


# --- the Extras against the products -------------------------------------------------------------

_EXTRAS_RULES = {"stale": "DLV-017", "differs": "DLV-018", "absent": "DLV-019"}


def _check_extras(root: Path, found: list[_Found], labels: LabelCache | None) -> None:
    """DLV-017/018/019: the Extras' README.TXT against the delivered labels (archive/extras_check.py)."""
    from ...archive.extras_check import extras_problems

    for problem in extras_problems(root, labels):
        found.append(_Found(_EXTRAS_RULES[problem.kind], problem.file, problem.message, problem.line))


# --- the manifest -------------------------------------------------------------------------------

def _named_inside(root: Path, name: str) -> tuple[Path | None, str | None]:
    """(the path, None) of a file a delivery's own table names (MD5SUMS.TXT, INDEX.TAB), by the
    containment rule; (None, why) for a name no file inside the delivery can have."""
    from ...storage.containment import contained, name_problem

    problem = name_problem(name)
    if problem is not None:
        return None, problem
    path = root.joinpath(*name.split("/"))
    return (path, None) if contained(path, root) is not None else (None, "a link leads out of it")


def _check_manifest(root: Path, labels_only: bool, found: list[_Found]) -> None:
    from ...formats.checksum import file_md5  # start-up: loaded only when a delivery is checked

    manifest = root / layout.MANIFEST
    if not manifest.is_file():
        return
    listed: dict[str, int] = {}
    for number, line in enumerate(manifest.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
        digest, sep, name = line.partition("  ")
        if not sep or not re.fullmatch(r"[0-9a-f]{32}", digest):
            found.append(_Found("DLV-020", manifest, f"not an 'md5  path' line: {line[:60]!r}", number))
            continue
        listed[name] = number
        path, problem = _named_inside(root, name)
        if path is None:  # never read (/dev/zero, ../x): named only
            found.append(_Found("DLV-020", manifest, f"{name!r} is not a file inside the delivery ({problem})",
                                number))
        elif not path.is_file():
            found.append(_Found("DLV-020", manifest, f"{name} is listed but does not exist", number))
        elif not labels_only and file_md5(path) != digest:
            found.append(_Found("DLV-020", path, f"MD5 differs from {layout.MANIFEST} line {number}: the file "
                                                 "changed after the manifest was written; to mend, run pdsgen "
                                                 "deliver again: it rewrites the manifest and keeps text written "
                                                 "into AAREADME.TXT, VOLDESC.CAT or the bundle label (a delivery "
                                                 "text file, [delivery] table, keeps it for good)"))
    for path in _all_files(root):
        name = path.relative_to(root).as_posix()
        if name not in (layout.MANIFEST, layout.MANIFEST_LABEL, layout.RELEASED_MARKER) \
                and not layout.is_review_page(name) \
                and name not in listed:
            found.append(_Found("DLV-021", path, f"not listed in {layout.MANIFEST}"))


# --- the runner hook ----------------------------------------------------------------------------

def check_delivery(root: Path, labels_only: bool = False, labels: LabelCache | None = None) -> list[Finding]:
    """Every DLV finding for the delivery at `root` (severities as registered). `labels`: the
    run's label cache (`pdsgen deliver` reads each label once for all its steps)."""
    from ..registry import rules

    found: list[_Found] = []
    _check_index(root, found, labels)
    _check_placeholders(root, found)
    _check_bundle(root, found, labels)
    _check_extras(root, found, labels)
    _check_quick_looks(root, found, labels)
    _check_manifest(root, labels_only, found)
    table = rules()
    return [Finding(f.rule, table[f.rule].severity, str(f.file), f.message, f.line, f.keyword) for f in found]


def _deliveries(path: Path) -> Iterator[Path]:
    """The deliveries at or under a path given to validate (a delivery's own subdirectories are
    not searched for others)."""
    for dirpath, dirnames, _ in os.walk(path):
        if is_delivery(Path(dirpath)):
            dirnames.clear()
            yield Path(dirpath)
        dirnames.sort()


class DeliveryChecks:
    """The runner's hook: DLV findings of the deliveries among the paths given, handed to each
    file's report as it streams past; files that get no report of their own (INDEX.TAB, the
    manifest, images) get one at the end.

    The deliveries are looked for and checked when the first report asks, not when the run
    starts: the per-file checks (and their progress count) begin at once. With workers (-j N,
    a cluster) the runner asks after the last file, so that the labels are read from what
    the workers return (validate/facts.py) instead of again here."""

    def __init__(self, paths: Iterable[str | os.PathLike[str]], labels_only: bool,
                 labels: LabelCache | None = None) -> None:
        self._paths = [Path(raw) for raw in paths]
        self._labels_only = labels_only
        self._labels = labels
        self._pending: dict[str, list[Finding]] | None = None

    @property
    def pending(self) -> dict[str, list[Finding]]:
        if self._pending is None:
            self._pending = {}
            for path in self._paths:
                for root in _deliveries(path):
                    for finding in self._check(root):
                        self._pending.setdefault(os.path.normpath(finding.file), []).append(finding)
        return self._pending

    def _check(self, root: Path) -> list[Finding]:
        if self._labels is None:  # a plain validation run: no cache to share (the call as it was)
            return check_delivery(root, self._labels_only)
        return check_delivery(root, self._labels_only, self._labels)

    def found(self) -> bool:
        """Whether a delivery lies among the paths (looked for, not checked)."""
        return any(next(_deliveries(path), None) is not None for path in self._paths)

    def take(self, path: str) -> list[Finding]:
        return self.pending.pop(os.path.normpath(path), [])

    def rest(self) -> Iterator[tuple[str, list[Finding]]]:
        while self.pending:
            yield self.pending.popitem()


register(
    Rule("DLV-001", "error", "INDEX.TAB is read as its INDEX.LBL describes (rows, row bytes, columns, formats)",
         None),
    Rule("DLV-002", "error", "every data product of a PDS3 volume is in INDEX.TAB exactly once", None),
    Rule("DLV-003", "error", "every INDEX.TAB row names an existing product label", None),
    Rule("DLV-004", "error", "INDEX.TAB row values equal those of the product's label", None),
    Rule("DLV-005", "error", "VOLUME_ID and DATA_SET_ID agree across INDEX.TAB, INDEX.LBL and VOLDESC.CAT", None),
    Rule("DLV-006", "warning", "no [TO BE WRITTEN: ...] placeholder left in VOLDESC.CAT, AAREADME.TXT, "
                               "bundle or collection labels", None),
    Rule("DLV-007", "warning", "a PDS3 product's identification keywords (DATA_SET_ID, PRODUCER_*, INSTRUMENT_* "
                               "...) are stated, not UNK or N/A (any product label, alone or delivered)",
         check_unstated),
    Rule("DLV-008", "warning", "a PDS4 label's investigation, observing system components and targets are named, "
                               "not UNK or N/A (any label, alone or in a bundle)", check_pds4_unstated,
         target="pds4"),
    Rule("DLV-010", "error", "every primary member of a collection inventory is the LIDVID of a product of the "
                             "delivery", None),
    Rule("DLV-011", "error", "every product under a collection's LID is in its inventory", None),
    Rule("DLV-012", "error", "LIDVIDs are unique across the delivery's labels and inventories", None),
    Rule("DLV-013", "error", "primary inventory members' LIDs are under their collection's LID", None),
    Rule("DLV-014", "warning", "references to products of the bundle (Product_Browse's data product, a "
                               "Reference_List's document ...) resolve in the delivery", None),
    Rule("DLV-015", "error", "the bundle lists every collection, and each primary member it lists exists", None),
    Rule("DLV-016", "warning", "every file of a PDS4 bundle is a label or described by one (a GDAL .aux.xml "
                               "sidecar, a manifest without its label ...)", None),
    Rule("DLV-017", "error", "the Extras were made from the delivered product: the label MD5 README.TXT records "
                             "is the label's (not stale after a remake)", None),
    Rule("DLV-018", "error", "README.TXT's size and VALID_MINIMUM/VALID_MAXIMUM of a product are its label's", None),
    Rule("DLV-019", "warning", "README.TXT documents only products and previews that are delivered", None),
    Rule("DLV-022", "error", "a product's PDS3 START_TIME/STOP_TIME and PDS4 Time_Coordinates agree (to the "
                             "second)", None),
    Rule("DLV-023", "error", "a product's PDS4 cart: grid is its PDS3 label's map grid (upper-left corner to half "
                             "a pixel, where both state one pixel size)", None),
    Rule("DLV-024", "error", "a delivery's PDS3 volume and PDS4 bundle hold the same products", None),
    Rule("DLV-025", "error", "JP2INFO.TXT states the size, bands and bit depth of each JP2 it describes (not "
                             "those of a JP2 since remade)", check_jp2info, needs_data=True),
    Rule("DLV-026", "error", "an Extras quick-look JP2 (QLOOK.JP2) is its delivered product at full scale (not a "
                             "quick look of a product since remade)", None),
    Rule("DLV-020", "error", "every file MD5SUMS.TXT lists exists and has that MD5", None, needs_data=True),
    Rule("DLV-021", "error", "every file of the delivery is listed in MD5SUMS.TXT", None),
)
