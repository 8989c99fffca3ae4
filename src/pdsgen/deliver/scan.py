"""Find the products of a directory and the files each one consists of.

A data product is a PDS3 label (an attached-label .IMG, or a detached .LBL with the
files its pointers name) and/or a PDS4 Product_Observational label (with the files it
lists), grouped when they share a file or a name. Extras images (.jpg, .QLOOK.JP2)
preview the data product whose PRODUCT_ID starts their name; README.TXT and JP2INFO.TXT
are documents. Files a delivery writes itself (index, volume description, bundle,
collection, browse and document labels, manifest) are recognised and made anew.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError
from ..formats.sniff import file_head
from ..missions.imars import is_metadata_name as is_imars_metadata
from ..pds4.detect import LABEL_SUFFIXES as PDS4_LABEL_SUFFIXES
from ..validate.lexer import parse_label
from ..validate.model import Block
from . import layout

_END = re.compile(rb"(?:^|\n)[ \t]*END[ \t]*\r?(?:\n|$)")
_LABEL_LIMIT = 4 << 20
_PRODUCT_CLASS = re.compile(rb"<product_class>\s*(Product_\w+)\s*</product_class>")
_FILE_NAME = re.compile(r"<file_name>\s*([^<]+?)\s*</file_name>")
_MADE_CLASSES = {b"Product_Bundle", b"Product_Collection", b"Product_Browse", b"Product_Document"}
_MADE_NAMES = {layout.VOLDESC, layout.AAREADME, layout.MANIFEST, layout.REVIEW_PAGE}
_DOCUMENTS = {"README.TXT", "JP2INFO.TXT"}
# The keywords a delivery takes from a PDS3 label: the index columns' and the volume's producer.
KEPT_KEYWORDS = tuple(name for name, _, _ in layout.INDEX_COLUMNS[2:]) + ("PRODUCER_INSTITUTION_NAME",)


def read_pds3_label(path: Path) -> Block | None:
    """The label tree of a PDS3 label file (attached or detached), read up to its END line
    (the data after an attached label is never read); None when it is no PDS3 label."""
    head = file_head(path, 64) or b""
    if not head.lstrip().upper().startswith((b"PDS_VERSION_ID", b"CCSD3")):
        return None
    chunks: list[bytes] = []
    with open(path, "rb") as stream:
        size = 0
        while size < _LABEL_LIMIT:
            chunk = stream.read(65536)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
            if _END.search(b"".join(chunks[-2:])):
                break
    return parse_label(b"".join(chunks).decode("latin-1")).root


def label_value(root: Block, keyword: str) -> str | None:
    """A keyword's value as written (strings unquoted), at the root or the first block that has it."""
    for block in root.walk():
        value = block.value(keyword)
        if value is not None and value.items is None:
            return value.text
    return None


def pointed_files(root: Block, directory: Path) -> list[str]:
    """Names of the existing files beside the label that its data pointers name (every name
    of a pointer to several files, {"A.H", "B.C"})."""
    names: list[str] = []
    for block in root.walk():
        for stmt in block.statements():
            if not stmt.pointer:
                continue
            for value in stmt.value.scalars():
                if value.kind in ("string", "ident") and not value.text.isdigit():
                    name = value.text.replace("\\", "/").rsplit("/", 1)[-1]
                    if (directory / name).is_file() and name not in names:
                        names.append(name)
    return names


@dataclass
class DataProduct:
    """One data product: its id, the PDS3 and/or PDS4 label, and all its files (paths in the source)."""

    product_id: str
    files: list[Path] = field(default_factory=list)
    pds3_label: Path | None = None
    pds4_label: Path | None = None


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
    if len(parts) == 1 and relative.name in _MADE_NAMES:
        return True
    if parts[0] == layout.INDEX_DIR and relative.name in (layout.INDEX_TABLE, layout.INDEX_LABEL):
        return True
    if relative.name.startswith("collection_") and relative.suffix in (".xml", ".csv"):
        return True
    if relative.suffix.lower() in PDS4_LABEL_SUFFIXES:
        match = _PRODUCT_CLASS.search(file_head(path, 4096) or b"")
        return match is not None and match.group(1) in _MADE_CLASSES
    return False


def is_preview(name: str) -> bool:
    lower = name.lower()
    return lower.endswith((".jpg", ".jpeg", ".qlook.jp2"))


def walk(root: Path) -> Iterator[Path]:
    """Every file under root (hidden ones too: a delivery made in place keeps them), sorted."""
    for dirpath, dirnames, filenames in os.walk(root):
        here = Path(dirpath)
        dirnames.sort()
        for name in sorted(filenames):
            path = here / name
            if path.is_file():
                yield path


# Told each PDS3 product as its label is read, with the label's values of KEPT_KEYWORDS.
LabelValues = Callable[["DataProduct", dict[str, str | None]], None]


def scan(source: Path, on_pds3: LabelValues | None = None) -> SourceSet:
    """The products, previews, documents and other files of `source` (recursively).

    `on_pds3` receives each PDS3 product's label values as the label is read; nothing of the
    label is kept here, so memory does not grow with the labels' size."""
    result = SourceSet()
    pds3: list[Path] = []
    pds4: list[Path] = []
    candidates: list[Path] = []
    for path in walk(source):
        relative = path.relative_to(source)
        if is_made_by_delivery(path, relative):
            continue
        name = path.name
        if name.upper() in _DOCUMENTS:
            result.documents.append(path)
        elif is_preview(name):
            result.previews.append(path)
        elif path.suffix.lower() in PDS4_LABEL_SUFFIXES:
            pds4.append(path)
        elif is_imars_metadata(name):
            result.imars.append(path)
        elif path.suffix.lower() == ".lbl" or _starts_like_pds3(path):
            pds3.append(path)
        else:
            candidates.append(path)
    result.products = _group(pds3, pds4, on_pds3)
    owned = {f for p in result.products for f in p.files}
    result.others = [p for p in candidates if p not in owned]
    return result


def _starts_like_pds3(path: Path) -> bool:
    head = file_head(path, 64) or b""
    return head.lstrip().upper().startswith((b"PDS_VERSION_ID", b"CCSD3"))


def _group(pds3: list[Path], pds4: list[Path], on_pds3: LabelValues | None) -> list[DataProduct]:
    products: list[DataProduct] = []
    by_file: dict[Path, DataProduct] = {}
    by_stem: dict[tuple[Path, str], DataProduct] = {}
    for label in pds3:
        root = read_pds3_label(label)
        if root is None:
            raise InputError(label, "a .LBL file that is not a PDS3 label (no PDS_VERSION_ID)")
        product_id = label_value(root, "PRODUCT_ID") or label.stem
        product = DataProduct(product_id, [label], label)
        if on_pds3 is not None:
            on_pds3(product, {name: label_value(root, name) for name in KEPT_KEYWORDS})
        for name in pointed_files(root, label.parent):
            member = label.parent / name
            if member != label and name.upper() not in _DOCUMENTS:  # ^DESCRIPTION = "JP2INFO.TXT": a document
                product.files.append(member)
        _claim(product, by_file, label)
        products.append(product)
        by_stem[(label.parent, label.stem.upper())] = product
    for label in pds4:
        if _PRODUCT_CLASS.search(file_head(label, 4096) or b"") is None:
            continue  # some other XML file: not a PDS4 label
        names = _FILE_NAME.findall(label.read_text(encoding="utf-8", errors="replace"))
        members = [label.parent / n for n in names]
        found = next((by_file[m] for m in members if m in by_file), None)
        found = found or by_stem.get((label.parent, label.stem.upper()))
        if found is None:
            found = DataProduct(label.stem, [])
            products.append(found)
        if found.pds4_label is not None:
            raise InputError(label, f"a second PDS4 label for product {found.product_id} "
                                    f"(the first is {found.pds4_label.name})")
        found.pds4_label = label
        for member in [label, *members]:
            if not member.is_file():
                raise InputError(label, f"names {member.name}, which does not exist")
            if member not in found.files:
                found.files.append(member)
            by_file.setdefault(member, found)
    return products


def _claim(product: DataProduct, by_file: dict[Path, DataProduct], label: Path) -> None:
    for member in product.files:
        other = by_file.get(member)
        if other is not None and other is not product:
            raise InputError(label, f"{member.name} is already part of product {other.product_id}")
        by_file[member] = product
