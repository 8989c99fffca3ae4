"""A delivery as one model: what each product is made of, read once per run.

A product of a delivery is told by several files: its PDS3 label (and the data beside it), its
PDS4 label, its row of INDEX.TAB, its inventory entry, its lines of MD5SUMS.TXT, its entry of the
Extras' README.TXT and the previews that entry lists, its entry of JP2INFO.TXT. The checks across
a delivery compare those parts with each other; this module reads each part once (PDS3 labels
through the run's LabelCache, PDS4 labels through the run's reader, validate/facts.py) and keeps
of each a small record - paths, ints, strings - so that the memory a delivery takes is a small
constant per product, whatever the checks ask and however often.

The records are the validator's own reading: PRODUCT_ID and the times, the IMAGE object's size
and valid range, the map grid of IMAGE_MAP_PROJECTION, README.TXT by archive/extras_check's
reader (the Extras' file format). An index row's other keywords are compared as the row is read
(row_values), with the label's one reading, and not kept.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ...archive import layout
from ...bounded import text_lines
from ...errors import InputError
from ...label.beside import outside_tree
from ...label.parser import is_pds3_head
from ...label.tree import Block
from ...pds4.detect import LABEL_SUFFIXES as PDS4_LABEL_SUFFIXES
from .parts import all_files, first, read_head, read_pds3

if TYPE_CHECKING:
    from ...archive.extras_check import DocumentedLabel, ReadmeEntry
    from ...label.read import LabelCache

_MANIFEST_LINE = re.compile(r"[0-9a-f]{32}")


@dataclass(frozen=True)
class Grid:
    """A PDS3 label's map grid: MAP_SCALE in metres a pixel and the projection offsets."""

    scale: float
    sample_offset: float
    line_offset: float


@dataclass(slots=True)
class Pds3Record:
    """What the checks compare of one PDS3 label: PRODUCT_ID, the first START_TIME and STOP_TIME
    with their lines, the IMAGE object's size and valid range, the map grid - a few fields in
    slots, so that a volume of 100,000 products keeps little."""

    path: Path
    product_id: str | None = None
    times: tuple[tuple[str | None, int | None], tuple[str | None, int | None]] = ((None, None), (None, None))
    size: tuple[int, int] | None = None  # (LINE_SAMPLES, LINES) of the IMAGE object
    valid: tuple[float | None, float | None] = (None, None)  # VALID_MINIMUM, VALID_MAXIMUM the IMAGE states
    grid: Grid | None = None

    def time(self, keyword: str) -> tuple[str | None, int | None]:
        """START_TIME's or STOP_TIME's first value and line."""
        return self.times[0] if keyword == "START_TIME" else self.times[1]


@dataclass(slots=True)
class ExtrasEntry:
    """One product as an Extras README.TXT documents it, and the delivered label it names."""

    readme: Path
    entry: ReadmeEntry
    product: Path | None


@dataclass(frozen=True)
class ManifestLine:
    """One line of MD5SUMS.TXT: its digest and name, or (None, the line) when it is no 'md5  path'."""

    number: int
    digest: str | None
    name: str


@dataclass(slots=True)
class Product:
    """One data product of the delivery (a PDS3 label of DATA/ and the PDS4 label describing a
    file of its name), with the parts that tell it."""

    key: tuple[str, str]
    label: Path | None = None  # the PDS3 label (None: a product of the PDS4 bundle only)
    pds3: Pds3Record | None = None  # its record (None too when the file is no PDS3 label)
    pds4: Pds4Record | None = None
    extras: list[ExtrasEntry] = field(default_factory=list)


class DeliveryModel:
    """The parts of the delivery at `root`, each read once: PDS3 labels (on first ask, through the
    run's cache), the PDS4 labels, the Extras' README.TXT entries and MD5SUMS.TXT's lines."""

    def __init__(self, root: Path, labels: LabelCache | None, read_pds4: Pds4Reader) -> None:
        """`read_pds4`: the run's reader of one PDS4 label (what a worker read of it through
        read_pds4 below, or read here: validate/facts.py)."""
        self.root = root
        self.labels = labels
        self._read_pds4 = read_pds4
        self._pds3: dict[str, Pds3Record | None] = {}
        self._pds4: list[Pds4Record] | None = None
        self._pds3_labels: list[str] | None = None
        self._extras: list[ExtrasEntry] | None = None
        self._products: list[Product] | None = None

    # --- PDS3 labels -------------------------------------------------------------------------

    def label_tree(self, path: Path) -> Block | None:
        """A PDS3 label's tree through the run's cache (a label no record is kept of: the index
        label, VOLDESC.CAT)."""
        return read_pds3(path, self.labels)

    def pds3(self, path: Path) -> Pds3Record | None:
        """The record of the PDS3 label at `path` (read once), None when it is no PDS3 label."""
        key = os.path.normpath(path)
        if key not in self._pds3:
            tree = read_pds3(path, self.labels)
            self._pds3[key] = _pds3_record(path, tree) if tree is not None else None
        return self._pds3[key]

    def row_values(self, path: Path, keywords: list[str]) -> dict[str, tuple[str | None, int | None]] | None:
        """The first value and line of each keyword an index row holds of the PDS3 label at
        `path` (None when it is no PDS3 label), read with the label's record - the one reading of
        the label - and not kept: the row is compared once, the record keeps a handful."""
        key = os.path.normpath(path)
        tree = read_pds3(path, self.labels)
        if key not in self._pds3:
            self._pds3[key] = _pds3_record(path, tree) if tree is not None else None
        return {keyword: first(tree, keyword) for keyword in keywords} if tree is not None else None

    @property
    def pds3_labels(self) -> Iterator[Path]:
        """The PDS3 product labels of the volume's DATA directory, found once (the index and the
        joined products both ask), kept as one string each (not a Path: small at 100,000)."""
        if self._pds3_labels is None:
            self._pds3_labels = [os.fspath(path) for path in pds3_products(self.root)]
        return (Path(name) for name in self._pds3_labels)

    # --- PDS4 labels -------------------------------------------------------------------------

    @property
    def pds4(self) -> list[Pds4Record]:
        """Every PDS4 label of the delivery, in the order of its files."""
        if self._pds4 is None:
            named = (path for path in all_files(self.root) if path.suffix.lower() in PDS4_LABEL_SUFFIXES)
            self._pds4 = [label for label in (self._read_pds4(path) for path in named) if label is not None]
        return self._pds4

    # --- the Extras ---------------------------------------------------------------------------

    @property
    def extras(self) -> list[ExtrasEntry]:
        """Every README.TXT entry of the delivery's Extras, with the delivered label it names."""
        if self._extras is None:
            from ...archive.extras_check import product_of, read_entries, readmes

            self._extras = [ExtrasEntry(readme, entry, product_of(self.root, readme, entry))
                            for readme in readmes(self.root) for entry in read_entries(readme)]
        return self._extras

    def label_facts(self, extras: ExtrasEntry) -> DocumentedLabel | None:
        """What README.TXT is compared with, of the label an entry names: its record's size and
        valid range, and the label's MD5 (read for a documented product only)."""
        from ...archive.extras_check import DocumentedLabel
        from ...formats.checksum import label_md5

        record = self.pds3(extras.product) if extras.product is not None else None
        if record is None:
            return None
        valid = {keyword: value for keyword, value in zip(("VALID_MINIMUM", "VALID_MAXIMUM"), record.valid, strict=True)
                 if value is not None}
        return DocumentedLabel(label_md5(record.path), record.size, valid)

    # --- the manifest -------------------------------------------------------------------------

    def manifest(self) -> Iterator[ManifestLine]:
        """MD5SUMS.TXT's lines, one at a time (none when the delivery has none): its one reader,
        the manifest check, streams them, so they are not kept (a line a file, not a product)."""
        return _manifest_lines(self.root / layout.MANIFEST)

    # --- products -----------------------------------------------------------------------------

    @property
    def products(self) -> list[Product]:
        """The data products of DATA/: each PDS3 product label, each PDS4 Product_Observational
        label there, joined when the PDS4 label describes a file of the PDS3 product's name
        (X.IMG, X.JP2), with the Extras entries of each."""
        if self._products is None:
            self._products = self._join()
        return self._products

    def _join(self) -> list[Product]:
        observational: dict[tuple[str, str], Pds4Record] = {}
        data = self.root / layout.DATA_DIR
        for label in self.pds4:  # the data products: those of DATA/, where the volume's are
            if label.product_class == "Product_Observational" and data in label.path.parents:
                for path in label.described:
                    observational.setdefault(product_key(Path(path)), label)
        products: list[Product] = []
        paired: set[int] = set()
        for path in self.pds3_labels:
            key = product_key(path)
            product = Product(key, path, self.pds3(path), observational.get(key))
            if product.pds4 is not None:
                paired.add(id(product.pds4))
            products.append(product)
        for label in {id(label): label for label in observational.values()}.values():
            if id(label) not in paired:  # a product of the bundle only
                products.append(Product(product_key(label.path), None, None, label))
        by_label = {os.path.normpath(p.pds3.path): p for p in products if p.pds3 is not None}
        for entry in self.extras:
            documented = by_label.get(os.path.normpath(entry.product)) if entry.product is not None else None
            if documented is not None:
                documented.extras.append(entry)
        return products


def pds3_products(root: Path) -> Iterator[Path]:
    """PDS3 product labels of the volume's DATA directory."""
    data = root / layout.DATA_DIR
    if not data.is_dir():
        return
    for path in all_files(data):
        if path.suffix.lower() in (*PDS4_LABEL_SUFFIXES, ".txt", ".csv", ".jp2", ".jpg"):
            continue
        if path.suffix.lower() == ".lbl" or is_pds3_head(read_head(path)):
            yield path


PDS_NS = "{http://pds.nasa.gov/pds4/pds/v1}"
Pds4Reader = Callable[[Path], "Pds4Record | None"]


@dataclass
class Pds4Record:
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



def read_pds4(path: Path) -> Pds4Record | None:
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
    label = Pds4Record(path, root.tag[len(PDS_NS):], lid, version)
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


def product_key(path: Path) -> tuple[str, str]:
    """A product's key: its directory and the first part of its file name, upper case (X.IMG,
    X.LBL, X.JP2 and X.xml are one product's)."""
    return os.path.normpath(path.parent), path.name.split(".", 1)[0].upper()


def _pds3_record(path: Path, tree: Block) -> Pds3Record:
    record = Pds3Record(path, first(tree, "PRODUCT_ID")[0], (first(tree, "START_TIME"), first(tree, "STOP_TIME")))
    image = next(tree.find("IMAGE"), None)
    if image is not None:
        samples, lines = image.number("LINE_SAMPLES"), image.number("LINES")
        if isinstance(samples, int) and isinstance(lines, int):
            record.size = (samples, lines)
        low, high = image.number("VALID_MINIMUM"), image.number("VALID_MAXIMUM")
        record.valid = (float(low) if isinstance(low, (int, float)) else None,
                        float(high) if isinstance(high, (int, float)) else None)
    record.grid = _grid(tree)
    return record


def _grid(tree: Block) -> Grid | None:
    """IMAGE_MAP_PROJECTION's MAP_SCALE (metres a pixel) and projection offsets."""
    projection = next(tree.find("IMAGE_MAP_PROJECTION"), None)
    if projection is None:
        return None
    scale_value = projection.value("MAP_SCALE")
    samples, lines = projection.number("SAMPLE_PROJECTION_OFFSET"), projection.number("LINE_PROJECTION_OFFSET")
    if scale_value is None or not isinstance(samples, (int, float)) or not isinstance(lines, (int, float)):
        return None
    try:
        scale = float(str(scale_value.py)) * (1000.0 if "KM" in (scale_value.unit or "").upper() else 1.0)
    except ValueError:
        return None
    return Grid(scale, float(samples), float(lines))


def _manifest_lines(manifest: Path) -> Iterator[ManifestLine]:
    try:
        lines = text_lines(manifest, "manifest", "utf-8")
    except InputError:  # none, or no regular file: DLV-020/021 need a manifest to read
        return
    for number, line in enumerate(lines, 1):
        digest, sep, name = line.partition("  ")
        if sep and _MANIFEST_LINE.fullmatch(digest):
            yield ManifestLine(number, digest, name)
        else:
            yield ManifestLine(number, None, line)
