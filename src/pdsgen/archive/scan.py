"""Find the products of a directory and the files each one consists of.

A data product is a PDS3 label (an attached-label .IMG, or a detached .LBL with every
file beside it the label names: its pointers' files, the FILE_NAME of its COMPRESSED_FILE
and UNCOMPRESSED_FILE objects, and the description, structure and catalog files its
reference pointers name, which several labels may share) and/or a PDS4
Product_Observational label (with the files it lists), grouped when they share a file
or a name. Extras images (.jpg, .QLOOK.JP2)
preview the data product whose PRODUCT_ID starts their name; README.TXT and JP2INFO.TXT
are documents. Files a delivery writes itself (index, volume description, bundle,
collection, browse and document labels, manifest) are recognised and made anew.
"""

from __future__ import annotations

import os
import re
import stat
from collections import OrderedDict
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError
from ..formats.sniff import file_head
from ..label.beside import DirectoryNames, directory_listing, resolve_beside
from ..label.read import LabelCache, LabelFile, is_pds3_head, read_pds3_label
from ..label.tree import FILE_OBJECTS, Block, parse_pointer
from ..missions.imars import is_metadata_name as is_imars_metadata
from ..pds4.detect import LABEL_SUFFIXES as PDS4_LABEL_SUFFIXES
from ..pds4.detect import root_name
from ..storage.containment import contained
from . import layout

_PRODUCT_CLASS = re.compile(rb"<product_class>\s*(Product_\w+)\s*</product_class>")
_FILE_NAME = re.compile(r"<file_name>\s*([^<]+?)\s*</file_name>")
_MADE_CLASSES = {b"Product_Bundle", b"Product_Collection", b"Product_Browse", b"Product_Document"}
_MADE_NAMES = {layout.VOLDESC, layout.AAREADME, layout.MANIFEST, layout.MANIFEST_LABEL, layout.RELEASED_MARKER}
_DOCUMENTS = {"README.TXT", "JP2INFO.TXT"}
# The keywords a delivery takes from a PDS3 label: the index columns' and the volume's producer.
KEPT_KEYWORDS = tuple(name for name, _, _ in layout.INDEX_COLUMNS[2:]) + ("PRODUCER_INSTITUTION_NAME",)


@dataclass
class NamedFiles:
    """The files beside a PDS3 label that it names, by whether they are the product's own."""

    data: list[Path] = field(default_factory=list)  # data pointers, COMPRESSED/UNCOMPRESSED_FILE
    support: list[Path] = field(default_factory=list)  # ^DESCRIPTION, ^STRUCTURE, catalogs: shareable


def named_files(root: Block, directory: Path, catalog: Path | None = None,
                listings: dict[Path, DirectoryNames] | None = None, tree: Path | None = None) -> NamedFiles:
    """The existing files beside the label (found as the validator finds them, a name differing
    only in case included) that the label names: every name of every pointer (a pointer to
    several files, {"A.H", "B.C"}, names each) and each FILE_NAME of a COMPRESSED_FILE or
    UNCOMPRESSED_FILE object. A file named as data and as support is data. A reference
    pointer's file not beside the label is looked for in `catalog` (a volume's CATALOG/).
    `listings`: directory listings shared by the labels of one scan, so a directory of N
    products is listed once, not once per label (N^2 work). `tree`: the directory the user
    gave (the label's directory unless told); a file resolving outside it is not found."""
    listings = {} if listings is None else listings

    def find(where: Path, name: str) -> Path | None:
        if where not in listings:
            listings[where] = directory_listing(where)
        exact, other = resolve_beside(where, listings[where], name.replace("\\", "/").rsplit("/", 1)[-1],
                                      tree or directory)
        return exact or other

    named = NamedFiles()

    def add(name: str, into: list[Path]) -> None:
        path = find(directory, name)
        if path is None and into is named.support and catalog is not None:
            path = find(catalog, name)
        if path is not None and path not in named.data and path not in into:
            into.append(path)

    for block in root.walk():
        for stmt in block.statements():
            if stmt.pointer:
                pointer = parse_pointer(stmt)
                for name in pointer.targets:
                    add(name, named.support if pointer.is_reference else named.data)
        file_name = block.text("FILE_NAME") if block.name.upper() in FILE_OBJECTS else None
        if file_name:
            add(file_name, named.data)
    named.support = [path for path in named.support if path not in named.data]
    return named


def label_root(path: Path, labels: LabelCache | None = None) -> Block | None:
    """The label tree of a PDS3 label file; None when it is none or cannot be read."""
    found = read_pds3_label(path, labels)
    return found.root if found is not None else None


def pointed_files(root: Block, directory: Path) -> list[str]:
    """Names of the existing files beside the label that its pointers name."""
    named = named_files(root, directory)
    return [path.name for path in [*named.data, *named.support]]


@dataclass
class DataProduct:
    """One data product: its id, the PDS3 and/or PDS4 label, and all its files (paths in the source)."""

    product_id: str
    files: list[Path] = field(default_factory=list)
    pds3_label: Path | None = None
    pds4_label: Path | None = None
    # Description, structure and catalog files its PDS3 label names: delivered beside the
    # label, and possibly shared with other products.
    support: list[Path] = field(default_factory=list)
    # Its PDS3 label states no PRODUCT_ID, so product_id is the label's file name: what a
    # delivery writes for it (INDEX.TAB, a LID) says so (deliver's warnings; validate's IDN-001).
    id_from_file: bool = False


@dataclass
class SourceSet:
    """What a directory holds, by role."""

    products: list[DataProduct] = field(default_factory=list)
    previews: list[Path] = field(default_factory=list)  # Extras images
    documents: list[Path] = field(default_factory=list)  # README.TXT, JP2INFO.TXT
    others: list[Path] = field(default_factory=list)  # files that belong to nothing above
    imars: list[Path] = field(default_factory=list)  # iMars metadata (*_ucl.pvl): no PDS label


def is_made_by_delivery(path: Path, relative: Path) -> bool:
    """Files a delivery writes: made anew by every run, never taken as products."""
    parts = relative.parts
    if len(parts) == 1 and (relative.name in _MADE_NAMES or layout.is_review_page(relative.name)):
        return True
    if parts[0] == layout.INDEX_DIR and relative.name in (layout.INDEX_TABLE, layout.INDEX_LABEL):
        return True
    if relative.name.startswith("collection_") and relative.suffix in (".xml", ".csv"):
        return True
    if relative.suffix.lower() in PDS4_LABEL_SUFFIXES:
        match = _PRODUCT_CLASS.search(file_head(path, 4096) or b"")
        return match is not None and match.group(1) in _MADE_CLASSES
    return False


def root_element(path: Path) -> str | None:
    """The local name of the root element of an XML file, or None when the file is no XML, its
    root cannot be found or it cannot be read (pds4/detect's one reading of a prolog: linear time
    whatever the prolog holds). A PDS4 label is what its root says: a bundle label is a
    Product_Bundle whatever its file name (`bundle.xml` is the common one)."""
    return root_name(path)


# directory -> (a stamp of its XML files, the bundle labels among them): a directory walked again
# (validate looks for deliveries when a run starts and when its first report asks; review and
# deliver look too) reads no prolog again while none of its XML files changed
_BUNDLES: OrderedDict[str, tuple[int, list[Path]]] = OrderedDict()
_MAX_BUNDLE_DIRECTORIES = 1024


def bundle_labels(directory: Path) -> list[Path]:
    """The PDS4 bundle labels (root element Product_Bundle) at the top of `directory`, sorted. The
    directory is listed once, through the listing every look-up of the run shares, and the
    prologs of its XML files are read once while they are unchanged (each file's modification
    time and size, one stat each, make the directory's stamp)."""
    names = sorted(directory / name for name in directory_listing(directory).names
                   if name.endswith(PDS4_LABEL_SUFFIXES))
    stats = [_regular_stat(path) for path in names]
    stamp = hash(tuple(stats))  # one integer a directory, however many files it holds
    key = os.path.abspath(directory)
    cached = _BUNDLES.get(key)
    if cached is not None and cached[0] == stamp:
        _BUNDLES.move_to_end(key)
        return list(cached[1])
    found = [path for path, regular in zip(names, stats, strict=True)
             if regular is not None and root_element(path) == "Product_Bundle"]
    _BUNDLES[key] = (stamp, found)
    while len(_BUNDLES) > _MAX_BUNDLE_DIRECTORIES:
        _BUNDLES.popitem(last=False)
    return list(found)


def bundle_label(directory: Path) -> Path | None:
    """The bundle label of a delivery's root (the first by name when it keeps several versions),
    found by its root element, not its file name: `bundle.xml` as well as `bundle_NAME.xml`."""
    return next(iter(bundle_labels(directory)), None)


def _regular_stat(path: Path) -> tuple[int, int] | None:
    """(modification time in ns, size) of a regular file, None for anything else."""
    try:
        found = path.stat()
    except OSError:
        return None
    return (found.st_mtime_ns, found.st_size) if stat.S_ISREG(found.st_mode) else None


def is_preview(name: str) -> bool:
    lower = name.lower()
    return lower.endswith((".jpg", ".jpeg", ".qlook.jp2"))


def walk(root: Path, strict: bool = True) -> Iterator[Path]:
    """Every file under root (hidden ones too: a delivery made in place keeps them), sorted.

    A symbolic link to a file outside root is refused (`strict`, a delivery) or passed over (a
    review): only what the user gave is taken (directory links are not followed at all)."""
    for dirpath, dirnames, filenames in os.walk(root):
        here = Path(dirpath)
        dirnames.sort()
        for name in sorted(filenames):
            path = here / name
            if path.is_file():
                if path.is_symlink() and contained(path, root) is None:
                    if strict:
                        raise InputError(path, f"is a symbolic link to a file outside {root}; it is not taken")
                    continue
                yield path


# Told each PDS3 product as its label is read, with the label's values of KEPT_KEYWORDS.
LabelValues = Callable[["DataProduct", dict[str, str | None]], None]


def scan(source: Path, on_pds3: LabelValues | None = None, labels: LabelCache | None = None,
         strict: bool = True) -> SourceSet:
    """The products, previews, documents and other files of `source` (recursively).

    `strict` (a delivery): a PDS4 label naming a file that is missing or outside `source` is
    refused; otherwise (a review) that file is left out and the validator's finding tells.
    `on_pds3` receives each PDS3 product's label values as the label is read; nothing of the
    label is kept here (unless in `labels`, the run's cache, for the steps after), so memory
    does not grow with the labels' size."""
    result = SourceSet()
    pds3: list[Path] = []
    pds4: list[Path] = []
    candidates: list[Path] = []
    for path in walk(source, strict):
        relative = path.relative_to(source)
        if is_made_by_delivery(path, relative):
            continue
        name = path.name
        if name.upper() in _DOCUMENTS:
            result.documents.append(path)
        elif is_preview(name):
            result.previews.append(path)
        elif path.suffix.lower() in PDS4_LABEL_SUFFIXES:  # a PDS4 label, or other XML (a GDAL .aux.xml)
            (pds4 if _PRODUCT_CLASS.search(file_head(path, 4096) or b"") else candidates).append(path)
        elif is_imars_metadata(name):
            result.imars.append(path)
        elif path.suffix.lower() == ".lbl" or is_pds3_label(path):
            pds3.append(path)
        else:
            candidates.append(path)
    result.products = _group(pds3, pds4, on_pds3, source, labels, strict)
    owned = {f for p in result.products for f in (*p.files, *p.support)}
    result.others = [p for p in candidates if p not in owned]
    return result


def is_pds3_label(path: Path) -> bool:
    """A file that begins as a PDS3 label does (PDS_VERSION_ID, or an SFDU wrapper)."""
    return is_pds3_head(file_head(path, 64) or b"")


@dataclass
class _Pds3Label:
    """What a PDS3 label tells the delivery (the label's tree itself is not kept)."""

    path: Path
    product_id: str | None  # None: the label states none
    values: dict[str, str | None]
    named: NamedFiles


def _read_pds3(label: Path, source: Path, listings: dict[Path, DirectoryNames],
               labels: LabelCache | None) -> _Pds3Label:
    try:
        found = labels.open_pds3(label) if labels is not None else LabelFile.read_pds3(label)
    except OSError as exc:
        raise InputError(label, f"cannot be read ({exc.strerror or exc})") from None
    if found is None:
        raise InputError(label, "a .LBL file that is not a PDS3 label (no PDS_VERSION_ID)")
    root = found.root
    named = named_files(root, label.parent, source / layout.CATALOG_DIR, listings, source)
    # ^DESCRIPTION = "JP2INFO.TXT", README.TXT: documents, delivered as such
    named.data = [p for p in named.data if p != label and p.name.upper() not in _DOCUMENTS]
    named.support = [p for p in named.support if p != label and p.name.upper() not in _DOCUMENTS]
    return _Pds3Label(label, found.first("PRODUCT_ID") or None,
                      {name: found.first(name) for name in KEPT_KEYWORDS}, named)


def _group(pds3: list[Path], pds4: list[Path], on_pds3: LabelValues | None, source: Path,
           labels: LabelCache | None, strict: bool = True) -> list[DataProduct]:
    products: list[DataProduct] = []
    by_file: dict[Path, DataProduct] = {}
    by_stem: dict[tuple[Path, str], DataProduct] = {}
    listings: dict[Path, DirectoryNames] = {}  # each directory listed once for all the labels in it
    read = [_read_pds3(path, source, listings, labels) for path in pds3]
    # A catalog or description file another label points to (DSMAP.CAT) is that label's
    # support, even where it has a PDS3 label of its own: not a data product.
    support = {path for one in read for path in one.named.support}
    for one in read:
        if one.path in support:
            continue
        # a label stating no PRODUCT_ID: the product is named by its file, and marked so (never silently)
        product = DataProduct(one.product_id or one.path.stem, [one.path, *one.named.data], one.path,
                              support=one.named.support, id_from_file=one.product_id is None)
        if on_pds3 is not None:
            on_pds3(product, one.values)
        _claim(product, by_file, one.path)
        products.append(product)
        by_stem[(one.path.parent, one.path.stem.upper())] = product
    for label in pds4:
        if _PRODUCT_CLASS.search(file_head(label, 4096) or b"") is None:
            continue  # some other XML file: not a PDS4 label
        names = _FILE_NAME.findall(label.read_text(encoding="utf-8", errors="replace"))
        members = _pds4_members(label, names, source, strict)
        found = next((by_file[m] for m in members if m in by_file), None)
        found = found or by_stem.get((label.parent, label.stem.upper()))
        if found is None:
            found = DataProduct(label.stem, [])  # a PDS4 product: its LID part follows the label file
            products.append(found)
        if found.pds4_label is not None:
            raise InputError(label, f"a second PDS4 label for product {found.product_id} "
                                    f"(the first is {found.pds4_label.name})")
        found.pds4_label = label
        for member in [label, *members]:
            if member not in found.files:
                found.files.append(member)
            by_file.setdefault(member, found)
    return products


def _pds4_members(label: Path, names: list[str], source: Path, strict: bool) -> list[Path]:
    """The files a PDS4 label lists, each an existing file inside `source`; a missing or
    outside one refuses the label when `strict`, else is left out (its finding tells)."""
    members = []
    for name in names:
        member = label.parent / name
        if not member.is_file():
            problem = "which does not exist"
        elif contained(member, source) is None:
            problem = f"which lies outside {source}"
        else:
            members.append(member)
            continue
        if strict:
            raise InputError(label, f"names {name}, {problem}")
    return members


def _claim(product: DataProduct, by_file: dict[Path, DataProduct], label: Path) -> None:
    for member in product.files:
        other = by_file.get(member)
        if other is not None and other is not product:
            raise InputError(label, f"{member.name} is already part of product {other.product_id}")
        by_file[member] = product
