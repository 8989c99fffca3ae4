"""Migrate a whole PDS3 volume into a PDS4 bundle, every data file unchanged.

One pass through the volume, in path order: each PDS3 label is migrated as `pdsgen migrate`
migrates one product (migrate_product: byte-identical copies of its files beside the PDS4
label, or the label beside the originals in place) as soon as it is met, and forgotten; what
the run keeps is a few strings per product (its LID, its path for the index and crosswalk),
written out as it goes (inventories, crosswalk), so memory stays flat however large the
volume. After the pass: documents, browse images, format files, the index check, the
collection and bundle labels, the crosswalk and the checksum manifest. What becomes of each
part of a volume is the table in volume_files.VOLUME_PARTS.

Nothing is left behind by a failed run: the bundle is built in a work directory beside the
target and renamed into place when complete (storage/staging.replace_directory); in place,
the files this run wrote are removed again.
"""

from __future__ import annotations

import logging
import os
import shutil
from collections import Counter
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import IO, Any

from .. import clock
from ..archive import layout
from ..archive.scan import is_pds3_label, named_files, walk
from ..encode import shown, table_field
from ..errors import InputError, OutputError, PdsgenError, param
from ..formats.checksum import bytes_md5, file_md5
from ..formats.sniff import file_head
from ..label.read import LabelCache, read_pds3_label
from ..label.tree import Block
from ..pds4.checksum_manifest import manifest_label
from ..pds4.content import digest_file
from ..pds4.detect import is_pds4_label
from ..pds4.label import render_pds4
from ..pds4.model import CURRENT_IM
from ..results import CommandResult
from ..storage.containment import contained
from ..storage.staging import replace_directory
from ..validate.model import Finding
from ..validate.report import finding_line
from ..validate.runner import iter_reports
from .identity import check_bundle_lid, check_product_lid, lid_part, product_id, text
from .product import migrate_product
from .volume_catalog import BundleFacts, bundle_facts, volume_data_sets
from .volume_files import (
    BROWSE_DIRS,
    DOCUMENT_DIRS,
    DOCUMENT_SUFFIXES,
    INDEX_DIRS,
    MADE_ANEW,
    SOFTWARE_DIRS,
    SOFTWARE_REASON,
    TOP_DOCUMENTS,
    document_standard,
    image_encoding,
)
from .volume_index import VolumeIndex, find_index

log = logging.getLogger(__name__)

VERSION = "1.0"
MANIFEST, MANIFEST_LABEL = layout.MANIFEST, layout.MANIFEST_LABEL  # the checksum manifest and its label
CROSSWALK = "crosswalk.csv"
# collection -> (collection_type, the bundle's reference_type)
COLLECTION_KINDS = {"document": ("Document", "bundle_has_document_collection"),
                    "browse": ("Browse", "bundle_has_browse_collection"),
                    "miscellaneous": ("Miscellaneous", "bundle_has_miscellaneous_collection")}
DATA_KIND = ("Data", "bundle_has_data_collection")
# How a LID that two products would share is made unique (stated in the report and the docs).
# The crosswalk's role of a format file: in the bundle, read through the labels naming it.
FORMAT_ROLE = "format file kept at its path: no PDS4 class; the PDS3 labels naming it read it"
COLLISION_RULE = ("the first product in path order keeps <collection>:<product ID>; a later one is "
                  "<collection>:<its path without the extension, '/' as '_'>, then _2, _3 ...")


@dataclass
class VolumeMigration(CommandResult):
    """What `pdsgen migrate VOLUME_DIR` did: counts by class, and every product refused, file left
    out, index row without a product, product without a row and LID collision, each by name."""

    bundle: Path
    bundle_lid: str
    counts: Counter[str] = field(default_factory=Counter)
    failures: list[str] = field(default_factory=list)
    left_out: list[tuple[str, str]] = field(default_factory=list)  # (path in the volume, why)
    kept: list[str] = field(default_factory=list)  # .FMT files kept at their paths, no PDS4 class
    unindexed: list[str] = field(default_factory=list)  # products the index does not list
    missing: list[str] = field(default_factory=list)  # index rows naming no product of the volume
    collisions: list[str] = field(default_factory=list)
    main_files: list[Path] = field(default_factory=list)  # bundle, collection labels, crosswalk, manifest
    index: str | None = None  # the index table taken as the manifest (path in the volume)
    validation: list[Finding] = field(default_factory=list)  # `pdsgen validate` on the bundle as written
    described: list[str] = field(default_factory=list)  # each product's own warnings (a keyword overridden ...)

    @property
    def files(self) -> tuple[Path, ...]:
        """The bundle's own files (bundle and collection labels, inventories, crosswalk, manifest);
        the products' labels and copies are counted in `counts`, not listed (a volume has thousands)."""
        return tuple(self.main_files)

    @property
    def refused(self) -> tuple[str, ...]:
        return tuple(self.failures)

    @property
    def warnings(self) -> tuple[str, ...]:
        return (*self.described,
                *(f"{path}: left out: {why}" for path, why in self.left_out),
                *(f"{path}: a product the index {self.index} does not list" for path in self.unindexed),
                *(f"{self.index} row {row}" for row in self.missing),
                *self.collisions,
                *(finding_line(finding) for finding in self.validation))

    @property
    def summary_lines(self) -> tuple[str, ...]:
        counts = ", ".join(f"{n} {kind}" for kind, n in sorted(self.counts.items()))
        return (f"BUNDLE   {self.bundle} ({self.bundle_lid}): {counts or 'nothing'}",
                f"INDEX    {self.index or 'none found'}: {len(self.unindexed)} product(s) without a row, "
                f"{len(self.missing)} row(s) without a product",
                f"{len(self.failures)} product(s) refused, {len(self.left_out)} file(s) left out, "
                f"{len(self.kept)} format file(s) kept, {len(self.collisions)} LID collision(s) resolved")

    def details(self) -> dict[str, Any]:
        return {"bundle_lid": self.bundle_lid, "counts": dict(self.counts), "refused_products": self.failures,
                "left_out": [{"path": p, "reason": r} for p, r in self.left_out], "kept": self.kept,
                "unindexed": self.unindexed, "index_rows_without_product": self.missing,
                "collisions": self.collisions, "index": self.index, "described": self.described,
                "validation": [finding.as_dict() for finding in self.validation]}


def migrate_volume(volume: str | os.PathLike[str], outdir: str | os.PathLike[str] | None = None, *,
                   bundle_lid: str, in_place: bool = False, overwrite: bool = False) -> VolumeMigration:
    """The PDS4 bundle of the PDS3 volume `volume`, written to `outdir` (or, `in_place`, beside the
    volume's own files). Raises InputError/OutputError for what the user must fix (nothing is
    written then); a product PDS4 cannot describe is refused, listed, and the others go on."""
    source = Path(volume)
    if not source.is_dir():
        raise InputError(source, "not a directory (a PDS3 volume)")
    check_bundle_lid(bundle_lid)
    if bundle_lid.split(":")[1:3] != ["nasa", "pds"]:
        raise InputError(None, f"{param('bundle_lid', bundle_lid)}: expected urn:nasa:pds:NAME")
    if in_place:
        return _run(source, source, bundle_lid, in_place=True, overwrite=True)
    if outdir is None:
        raise OutputError(None, "give an output directory, or migrate in place")
    target = Path(outdir)
    _check_target(source, target, overwrite)
    work = target.parent / f".{target.name}.migrate-volume-{os.getpid()}"
    try:
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir(parents=True)
        result = _run(source, work, bundle_lid, in_place=False, overwrite=False)
        result.validation = [_moved(finding, work, target) for finding in result.validation]
        replace_directory(work, target)
    except BaseException as exc:
        shutil.rmtree(work, ignore_errors=True)
        if isinstance(exc, OSError) and not isinstance(exc, PdsgenError):
            raise OutputError(target, f"the bundle could not be written ({exc.strerror or exc}); "
                                      "nothing was changed") from None
        raise
    result.bundle = target
    result.main_files = [target / path.relative_to(work) for path in result.main_files]
    return result


def _check_target(source: Path, target: Path, overwrite: bool) -> None:
    if target.exists() and not target.is_dir():
        raise OutputError(target, "exists and is not a directory")
    resolved, src = target.resolve(), source.resolve()
    if resolved == src or src in resolved.parents or resolved in src.parents:
        raise InputError(target, f"the bundle and the volume {source} must not contain each other "
                                 "(migrate in place to write the labels beside the volume's files)")
    if target.is_dir() and any(target.iterdir()) and not overwrite:
        raise OutputError(target, "exists and is not empty (give overwrite to replace it)")


def _run(source: Path, dest: Path, bundle_lid: str, *, in_place: bool, overwrite: bool) -> VolumeMigration:
    run = _Run(source, dest, bundle_lid, in_place, overwrite)
    try:
        run.walk()
        run.finish()
        run.result.validation = validated(dest)
    except BaseException:
        run.close()
        if in_place:
            run.undo()
        raise
    return run.result
# PDS4 Standards Reference 6D.2: a LID is at most 255 characters. A longer one is cut, and made
# unique again by the MD5 of the whole LID it stands for.
MAX_LID = 255
LENGTH_RULE = "its first 246 characters, '_' and the first 8 hex digits of the MD5 of the whole LID"


# A PDS4 label the PDS3 volume carried is not a document of it: its LID is not the bundle's, and
# migrate writes the bundle's own label of the same data (often under the very same name).
PDS4_LABEL_REASON = "a PDS4 label the volume carried: the bundle's own labels describe its files"


def _shortened(lid: str) -> str:
    return f"{lid[:MAX_LID - 9]}_{bytes_md5(lid.encode())[:8]}"


class _Run:
    """One migration's state: a few strings per product, streams for inventories and crosswalk."""

    def __init__(self, source: Path, dest: Path, bundle_lid: str, in_place: bool, overwrite: bool) -> None:
        self.source, self.dest, self.bundle_lid = source, dest, bundle_lid
        self.in_place, self.overwrite = in_place, overwrite
        self.result = VolumeMigration(dest, bundle_lid)
        self.today = clock.today()
        self.lids: set[str] = set()
        self.product_lidvids: dict[str, str] = {}  # PRODUCT_ID (upper) and label stem (upper) -> LIDVID
        self.owned: set[str] = set()  # volume paths (posix) a product label describes
        self.candidates: list[str] = []  # files no rule placed yet: owned by a product, a document, or left out
        self.documents: list[str] = []
        self.browse: list[tuple[str, str]] = []  # (path, encoding)
        self.formats: list[str] = []
        self.catalogs: list[Path] = []
        self.first_product: Path | None = None
        self.inventories: dict[str, IO[str]] = {}
        self.records: Counter[str] = Counter()
        self.crosswalk = self._open(CROSSWALK)
        self.crosswalk_rows = 0
        self.widths = [1, 1, 1, 1]
        self.index: VolumeIndex | None = None
        self.rows: dict[str, int] = {}
        self.written: list[Path] = [self.dest / CROSSWALK]
        self.label_names: set[Path] = set()  # labels of documents and browse images written so far
        self.data_sets = volume_data_sets(self._top("VOLDESC.CAT"))

    # --- the pass through the volume ----------------------------------------------------------

    def walk(self) -> None:
        index_dir = next((d for d in sorted(self.source.iterdir()) if _is_index_dir(d, self.source)), None)
        self.index = find_index(self.source, index_dir) if index_dir is not None else None
        if self.index is not None:
            self.result.index = self.index.table.relative_to(self.source).as_posix()
            for number, row_path, _ in self.index.rows():
                if row_path:
                    self.rows.setdefault(row_path, number)
        log.info("%s: index %s, %d row(s)", self.source, self.result.index or "none", len(self.rows))
        for path in walk(self.source):
            relative = path.relative_to(self.source)
            if self.in_place and self._made_here(relative):
                continue
            self._place(path, relative)

    def _made_here(self, relative: Path) -> bool:
        """A file an earlier in-place run wrote (a PDS4 label under this bundle's LID, an inventory,
        the crosswalk, the manifest): made anew. An XML file of the volume's own is the volume's."""
        name = relative.name
        if name in (CROSSWALK, MANIFEST, MANIFEST_LABEL) \
                or (name.startswith("collection_") and relative.suffix in (".xml", ".csv")):
            return True
        if relative.suffix.lower() != ".xml":
            return False
        head = file_head(self.dest / relative, 4096) or b""
        return f"<logical_identifier>{self.bundle_lid}".encode() in head

    def _place(self, path: Path, relative: Path) -> None:
        top = relative.parts[0].upper() if len(relative.parts) > 1 else ""
        name = relative.as_posix()
        if top in SOFTWARE_DIRS:
            self.result.left_out.append((name, SOFTWARE_REASON))
        elif len(relative.parts) == 1 and relative.name.upper() in MADE_ANEW | {"REVIEW.HTML"}:
            self.result.left_out.append((name, "made anew: the bundle's own manifest replaces it"))
        elif top in DOCUMENT_DIRS or (not top and relative.name.upper() in TOP_DOCUMENTS) \
                or relative.suffix.upper() in DOCUMENT_SUFFIXES:
            self.documents.append(name)
            if top == "CATALOG":
                self.catalogs.append(path)
        elif relative.suffix.upper() == ".FMT":
            self.formats.append(name)
        elif top in BROWSE_DIRS and (encoding := image_encoding(path)) is not None:
            self.browse.append((name, encoding))
        elif relative.suffix.lower() == ".lbl" or is_pds3_label(path):
            self._product(path, relative)
        else:
            self.candidates.append(name)

    def _product(self, label: Path, relative: Path) -> None:
        """Migrate one product now (its label parsed once, for this and for migrate_product)."""
        labels = LabelCache()
        found = read_pds3_label(label, labels)
        if found is None:
            self.candidates.append(relative.as_posix())
            return
        root = found.root
        pid, _ = product_id(root, label.stem)
        collection = self._data_collection(text(root, "DATA_SET_ID"))
        lid = self._unique_lid(collection, pid, relative)
        target = (self.dest / relative).parent
        try:
            migrated = migrate_product(label, None if self.in_place else target, bundle_lid=self.bundle_lid,
                                       collection=collection, lid=lid, in_place=self.in_place,
                                       overwrite=self.overwrite, labels=labels, root=self.source)
        except PdsgenError as exc:
            self.lids.discard(lid)
            self.result.failures.append(str(exc))
            reason = str(exc).splitlines()[0].split(": ", 1)[-1]
            self._crosswalk_row(pid, relative.as_posix(), "", f"left out: the label of a refused product ({reason})")
            self._refused_files(root, label, relative)
            return
        self.first_product = self.first_product or label
        self.result.described.extend(migrated.warnings)
        lidvid = f"{lid}::{VERSION}"
        self.product_lidvids.setdefault(pid.upper(), lidvid)
        self.product_lidvids.setdefault(label.name.split(".", 1)[0].upper(), lidvid)
        members = [relative.as_posix()]
        for path in migrated.files:
            origin = path if self.in_place else self.source / path.relative_to(self.dest)
            members.append(origin.relative_to(self.source).as_posix())
        self.owned.update(members)
        if relative.parts[0].upper() not in INDEX_DIRS:  # the index lists the products, not itself
            self._check_indexed(members)
        self._member(collection, lidvid)
        self._crosswalk_row(pid, relative.as_posix(), lidvid, "PDS3 label")
        for member in dict.fromkeys(members[1:]):
            if member != members[0]:  # an attached label is its own data file
                self._crosswalk_row(pid, member, lidvid, "data file")
        self.result.counts["Product_Observational"] += 1
        if self.result.counts["Product_Observational"] % 1000 == 0:
            log.info("%d product(s) migrated", self.result.counts["Product_Observational"])
        if self.in_place:
            self.written.append(migrated.label_path)

    def _refused_files(self, root: Block, label: Path, relative: Path) -> None:
        """The data files of a refused product are left out as such (never taken for documents)."""
        for path in named_files(root, label.parent, tree=self.source).data:
            name = path.relative_to(self.source).as_posix()
            if name not in self.owned:
                self.owned.add(name)
                self.result.left_out.append((name, f"a data file of the refused product {relative.as_posix()}"))

    def _unique_lid(self, collection: str, pid: str, relative: Path) -> str:
        """The product's LID by COLLISION_RULE: unique within the bundle, valid, lower case."""
        base = f"{self.bundle_lid}:{collection}:"
        lid = base + lid_part(pid)
        if lid in self.lids:
            first = lid
            lid = base + lid_part(relative.with_suffix("").as_posix())
            number = 1
            while lid in self.lids:
                number += 1
                lid = f"{base}{lid_part(relative.with_suffix('').as_posix())}_{number}"
            self.result.collisions.append(f"{relative.as_posix()}: LID {first} is taken by an earlier product; "
                                          f"given {lid} ({COLLISION_RULE})")
        if len(lid) > MAX_LID:
            short = _shortened(lid)
            self.result.collisions.append(f"{relative.as_posix()}: LID {lid} is longer than {MAX_LID} characters; "
                                          f"given {short} ({LENGTH_RULE})")
            lid = short
        check_product_lid(lid)
        self.lids.add(lid)
        return lid

    def _check_indexed(self, members: list[str]) -> None:
        if self.index is None:
            return
        keys = {m.upper() for m in members if m.upper() in self.rows}
        if not keys:
            self.result.unindexed.append(members[0])
        for key in keys:
            self.rows.pop(key)

    def _data_collection(self, data_set_id: str | None) -> str:
        """The data collection of a product: `data` for a volume of one data set (VOLDESC.CAT
        names at most one), else data_<data set> by the product's DATA_SET_ID (`data` without one)."""
        if len(self.data_sets) <= 1 or not data_set_id:
            return "data"
        return f"data_{lid_part(data_set_id)}"

    # --- streams ------------------------------------------------------------------------------

    def _open(self, relative: str) -> IO[str]:
        path = self.dest / relative
        if self.in_place and path.exists() and not self._made_here(Path(relative)):
            raise OutputError(path, "exists in the volume; it is not a file a migration wrote")
        return open(path, "w", encoding="ascii", newline="")

    def _member(self, collection: str, lidvid: str) -> None:
        if collection not in self.inventories:
            self.inventories[collection] = self._open(_inventory_name(collection))
            self.written.append(self.dest / _inventory_name(collection))
        self.inventories[collection].write(f"P,{lidvid}\r\n")
        self.records[collection] += 1

    def _crosswalk_row(self, pid: str, path: str, lidvid: str, role: str) -> None:
        """One PDS3 file and what it became: the LIDVID of the product holding it and its role there
        (PDS3 label, data file, document ...), or no LIDVID and why it was left out. Each field
        through the table-field encoder: a CR LF in a PRODUCT_ID cannot split the row."""
        said = shown(role).encode("ascii", "backslashreplace").decode().replace('"', "'")  # pdsgen's own words
        values = [table_field(value, name, self.source) for value, name in
                  zip((pid, path, lidvid, said), ("PRODUCT_ID", "file", "LIDVID", "role"), strict=True)]
        self.widths = [max(w, len(v)) for w, v in zip(self.widths, values, strict=True)]
        self.crosswalk.write(",".join(f'"{v}"' for v in values) + "\r\n")
        self.crosswalk_rows += 1

    def close(self) -> None:
        for stream in (self.crosswalk, *self.inventories.values()):
            stream.close()

    def undo(self) -> None:
        for path in self.written:
            path.unlink(missing_ok=True)

    # --- after the pass -----------------------------------------------------------------------

    def finish(self) -> None:
        for name in self.candidates:
            if name in self.owned:
                continue
            path = self.source / name
            if is_pds4_label(path):  # pdsgen's own --label both products carry one beside each PDS3 label
                self.result.left_out.append((name, PDS4_LABEL_REASON))
            elif document_standard(path) in ("7-Bit ASCII Text", "UTF-8 Text", "PDF", "PDF/A", "HTML"):
                self.documents.append(name)
            else:
                self.result.left_out.append((name, "no PDS3 label describes it and it is no document"))
        self.candidates = []
        self._documents()
        self._browse()
        self._formats()
        self._crosswalk_rest()
        self.result.missing = [f"{number}: {path} is no product of the volume"
                               for path, number in sorted(self.rows.items(), key=lambda item: item[1])]
        self.close()
        facts = bundle_facts(self._top("VOLDESC.CAT"), self.catalogs, self.first_product)
        members = self._collections(facts)
        self._bundle_label(facts, members)
        self._manifest()

    def _top(self, name: str) -> Path | None:
        return next((p for p in sorted(self.source.iterdir()) if _is_named(p, name, self.source)), None)

    def _copy(self, name: str) -> Path:
        """The volume's file `name` in the bundle: a byte-identical copy (in place: the file itself)."""
        source = self.source / name
        if self.in_place:
            return source
        target = self.dest / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)
        return target

    def _label_path(self, copy: Path) -> Path:
        """The PDS4 label beside a file: <stem>.xml, or <name>.xml where <stem>.xml is taken."""
        label = copy.with_suffix(".xml")
        if label in self.label_names or (label.exists() and not self.in_place):
            label = copy.with_name(copy.name + ".xml")
        self.label_names.add(label)
        return label

    def _write(self, path: Path, text: str) -> None:
        if self.in_place and path.exists() and not self._made_here(path.relative_to(self.dest)):
            raise OutputError(path, "exists in the volume; it is not a file a migration wrote")
        path.write_text(text, encoding="utf-8")
        if self.in_place:
            self.written.append(path)

    def _documents(self) -> None:
        """Each document a Product_Document; a PDS3 label of a document (X.LBL beside X.PDF)
        travels in it as a second file."""
        names = set(self.documents)
        beside = {}
        for name in self.documents:
            stem = name.rsplit(".", 1)[0]
            if name.upper().endswith(".LBL"):
                partner = next((n for n in names if n != name and n.rsplit(".", 1)[0] == stem), None)
                if partner is not None:
                    beside[partner] = name
        for name in self.documents:
            if name in beside.values() or name in self.owned:  # a detached label's X.TXT table is data
                continue
            files = [name] + ([beside[name]] if name in beside else [])
            standards = [document_standard(self.source / f) for f in files]
            if standards[0] is None:
                self.result.left_out.append((name, "a document in a format PDS4 has no document_standard_id for"))
                continue
            lid = self._unique_lid("document", Path(name).stem, Path(name))
            copies = [self._copy(f) for f in files]
            for file, role in zip(files, ("document", "PDS3 label of the document"), strict=False):
                self._crosswalk_row(Path(name).stem.upper(), file, f"{lid}::{VERSION}", role)
            described = [{**_facts(c), "standard": s or "7-Bit ASCII Text"} for c, s in zip(copies, standards,
                                                                                              strict=True)]
            title = f"{Path(name).name}: document of the PDS3 volume"
            self._write(self._label_path(copies[0]), render_pds4("volume_document.xml.j2", {
                **self._head("Product_Document", lid, title, cited=title), "date": self.today,
                "edition": f"{Path(name).name} as published on the PDS3 volume", "files": described},
                source=self.source))
            self._member("document", f"{lid}::{VERSION}")
            self.result.counts["Product_Document"] += 1

    def _browse(self) -> None:
        for name, encoding in self.browse:
            if name in self.owned:  # an image a PDS3 label describes is that product's data
                continue
            data = self._previewed(Path(name).name)
            if data is None:
                self.result.left_out.append((name, "a browse image whose name starts with no product's "
                                                   "PRODUCT_ID or label name"))
                continue
            copy = self._copy(name)
            stem = Path(name).name.rsplit(".", 1)[0]
            lid = self._unique_lid("browse", stem, Path(name))
            self._crosswalk_row(stem.upper(), name, f"{lid}::{VERSION}", f"browse image of {data}")
            self._write(self._label_path(copy), render_pds4("volume_browse.xml.j2", {
                **self._head("Product_Browse", lid, f"Browse image {Path(name).name} of {data.split('::')[0]}"),
                "data_lidvid": data, "file": _facts(copy), "encoding": encoding}, source=self.source))
            self._member("browse", f"{lid}::{VERSION}")
            self.result.counts["Product_Browse"] += 1

    def _previewed(self, image: str) -> str | None:
        """The LIDVID of the product a browse image previews: the longest PRODUCT_ID or label name
        its name starts with, up to a '.' (X.browse.jpg) or a '_' (X_BR.JPG)."""
        stem = image.split(".", 1)[0].upper()
        parts = stem.split("_")
        for end in range(len(parts), 0, -1):
            found = self.product_lidvids.get("_".join(parts[:end]))
            if found is not None:
                return found
        return None

    def _crosswalk_rest(self) -> None:
        """The files no product holds, in the crosswalk too: each format file kept, each file left
        out, with the reason - so every file of the volume has a row."""
        for name in self.result.kept:
            self._crosswalk_row(Path(name).stem.upper(), name, "", FORMAT_ROLE)
        for name, why in self.result.left_out:
            self._crosswalk_row(Path(name).stem.upper(), name, "", f"left out: {why}")

    def _formats(self) -> None:
        for name in self.formats:
            if name not in self.owned:
                self._copy(name)
            self.result.kept.append(name)

    def _collections(self, facts: BundleFacts) -> list[tuple[str, str]]:
        """The crosswalk, then each collection's label (its inventory was written as members came)."""
        self._crosswalk_label()
        entries = []
        for collection in sorted(self.records):
            kind, reference_type = COLLECTION_KINDS.get(collection, DATA_KIND)
            lid = f"{self.bundle_lid}:{collection}"
            label = self.dest / f"collection_{collection}.xml"
            records = self.records[collection]
            description = f"{records} {kind.lower()} product(s) of the PDS3 volume, migrated to PDS4."
            self._write(label, render_pds4("volume_collection.xml.j2", {
                **self._head("Product_Collection", lid, f"{kind} collection {collection} of {facts.title}",
                             cited=description),
                "collection_type": kind, "inventory": _inventory_name(collection), "records": records,
                "description": description}, source=self.source))
            self.result.main_files.append(label)
            self.result.main_files.append(self.dest / _inventory_name(collection))
            entries.append((f"{lid}::{VERSION}", reference_type))
        return entries

    def _crosswalk_label(self) -> None:
        lid = f"{self.bundle_lid}:miscellaneous:crosswalk"
        self.lids.add(lid)
        path = self.dest / CROSSWALK
        fields = [("pds3_product_id", self.widths[0] + 2, "The product's PDS3 PRODUCT_ID (else its label's name; "
                                                          "a document's or left-out file's name)."),
                  ("pds3_path", self.widths[1] + 2, "The path of the PDS3 file in the volume."),
                  ("pds4_lidvid", self.widths[2] + 2, "The LIDVID of the PDS4 product holding the file (empty for "
                                                      "a file no product holds)."),
                  ("role", self.widths[3] + 2, "What the file is in that product (PDS3 label, data file, "
                                               "document ...), or why it was left out.")]
        label = self.dest / "crosswalk.xml"
        self._write(label, render_pds4("volume_crosswalk.xml.j2", {
            **self._head("Product_Ancillary", lid, "Crosswalk: PDS3 products of the volume and their PDS4 LIDVIDs"),
            "bundle_lid": self.bundle_lid, "file": _facts(path), "records": self.crosswalk_rows, "fields": fields},
            source=self.source))
        self._member("miscellaneous", f"{lid}::{VERSION}")
        self._member("miscellaneous", f"{self.manifest_lid}::{VERSION}")  # its label is written after it
        self.inventories["miscellaneous"].close()
        self.result.counts["Product_Ancillary"] += 1
        self.result.main_files += [label, path]

    def _bundle_label(self, facts: BundleFacts, members: list[tuple[str, str]]) -> None:
        name = self.bundle_lid.rsplit(":", 1)[-1]
        # the authors in the description (CITATION_DESC names them; author_list is deprecated in IM 1.24)
        described = facts.citation or (f"{facts.authors}, {facts.title}" if facts.authors else facts.title)
        citation = {"year": facts.year or self.today[:4], "keywords": facts.keywords, "description": described}
        label = self.dest / f"bundle_{name}.xml"
        self._write(label, render_pds4("volume_bundle.xml.j2", {
            **self._head("Product_Bundle", self.bundle_lid, facts.title), "aliases": facts.aliases,
            "citation": citation, "references": facts.references, "description": facts.description,
            "members": members}, source=self.source))
        self.result.counts["Product_Bundle"] += 1
        self.result.main_files.insert(0, label)

    def _head(self, product_class: str, lid: str, title: str, cited: str | None = None) -> dict[str, object]:
        """The Identification_Area's values; `cited`: a Citation_Information description (the
        Schematron requires one in documents and collections)."""
        citation = {"year": self.today[:4], "keywords": (), "description": cited} if cited else None
        return {"product_class": product_class, "lid": lid, "version_id": VERSION, "title": title,
                "aliases": (), "citation": citation, "pds": CURRENT_IM.namespace("pds")}

    @property
    def manifest_lid(self) -> str:
        return f"{self.bundle_lid}:miscellaneous:{lid_part(Path(MANIFEST).stem)}"

    def _manifest(self) -> None:
        """MD5SUMS.TXT over every file of the bundle (in place: the volume's files too), written last,
        then its label (a Product_Ancillary of the miscellaneous collection, pds4/checksum_manifest:
        every file of the bundle is described), which the manifest cannot list."""
        lines = []
        for path in walk(self.dest):
            relative = path.relative_to(self.dest).as_posix()
            if relative not in (MANIFEST, MANIFEST_LABEL):
                lines.append(f"{file_md5(path)}  {relative}\n")
        manifest = self.dest / MANIFEST
        manifest.write_text("".join(lines), encoding="utf-8")
        label = self.dest / MANIFEST_LABEL
        self._write(label, manifest_label(manifest, self.manifest_lid, VERSION))
        self.lids.add(self.manifest_lid)
        self.result.counts["Product_Ancillary"] += 1
        self.result.main_files += [manifest, label]


def validated(bundle: Path) -> list[Finding]:
    """What `pdsgen validate BUNDLE` finds in the bundle as written (its default rules, no
    configuration file): migrate runs the validator's own checks on every label it wrote and
    every PDS3 label it carried before the bundle is put in place, so each finding validate
    makes afterwards was told by migrate first, in the same words (a plain-PDF document's
    PDS4-061, a genuine PDS3 label's dictionary warnings)."""
    return [finding for report in iter_reports([bundle]) for finding in report.findings]  # reports not kept


def _moved(finding: Finding, work: Path, target: Path) -> Finding:
    """A finding of the work directory as it reads once the bundle is renamed into place."""
    path = Path(finding.file)
    if path.is_absolute() and work in path.parents:
        return replace(finding, file=str(target / path.relative_to(work)))
    return finding


def _is_index_dir(path: Path, volume: Path) -> bool:
    """The volume's index directory (INDEX, whatever the case), a link leading out of it not."""
    return path.is_dir() and path.name.upper() in INDEX_DIRS and contained(path, volume) is not None


def _is_named(path: Path, name: str, volume: Path) -> bool:
    """A file at the volume's top named `name`, case aside (VOLDESC.CAT, voldesc.cat); a link
    leading out of the volume is not read (the one containment rule)."""
    return path.name.upper() == name and path.is_file() and contained(path, volume) is not None


def _inventory_name(collection: str) -> str:
    return f"collection_{collection}_inventory.csv"


def _facts(path: Path) -> dict[str, object]:
    content = digest_file(path)
    return {"name": path.name, "size": content.size, "md5": content.md5}
