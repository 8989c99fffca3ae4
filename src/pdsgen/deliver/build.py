"""`make_delivery`: a directory of products -> a PDS3 volume and/or a PDS4 bundle.

The delivery is built in a work directory beside the target (products hard-linked,
or copied across file systems; PDS4 product labels rewritten with their bundle LID)
and swapped in by renames when complete, so an interrupted run leaves the previous
delivery as it was, and nothing stale (a product taken away, an old index) survives a
re-run. The MD5 manifest is written last, over every file of the finished tree.
"""

from __future__ import annotations

import functools
import logging
import os
import re
import shutil
from collections.abc import Iterator
from pathlib import Path

from .. import clock
from ..archive import layout
from ..archive.scan import DataProduct, SourceSet, bundle_label, is_pds3_label, scan
from ..dialect import DIALECT_NAMES, Dialect
from ..errors import InputError, OutputError, PdsgenError, param
from ..formats.checksum import bytes_md5, file_md5
from ..label.read import LabelCache, LabelFile, read_pds3_label
from ..progress import advance
from ..storage.staging import refuse_link, replace_directory
from . import bundle
from .index import IndexWriter
from .result import Delivery
from .text import DeliveryText, load_text, previous_text
from .volume import VolumeFacts, aareadme_text, voldesc_text

log = logging.getLogger(__name__)


class _Tree:
    """The work directory being filled, with the MD5 of every file placed in it."""

    def __init__(self, root: Path, given: Path, made: Path) -> None:
        self.root = root
        self.given = given  # the products' directory: nothing from outside it is delivered ...
        self.made = made  # ... but the PDS4 labels this run migrated from PDS3 ones
        self.md5: dict[str, str] = {}

    def place(self, source: Path, relative: str) -> str:
        """Hard-link (or copy) a source file to `relative`; returns its MD5.

        The last guard of containment: a file (or a link's target) outside the directory the
        user gave is refused, whichever step named it."""
        from ..storage.containment import contained

        if contained(source, self.given) is None and contained(source, self.made) is None:
            raise InputError(source, f"lies outside {self.given}; a delivery holds only the files it was given")
        target = self.root / relative
        if relative in self.md5 or target.exists():
            raise InputError(source, f"two files would be delivered as {relative}")
        target.parent.mkdir(parents=True, exist_ok=True)
        try:
            if source.is_symlink():
                raise OSError("a symbolic link is delivered as the file it points at")
            os.link(source, target)
        except OSError:
            shutil.copy2(source, target)
        self.md5[relative] = file_md5(target)
        return self.md5[relative]

    def write(self, relative: str, data: str | bytes) -> bundle.FileFacts:
        target = self.root / relative
        if relative in self.md5 or target.exists():
            raise InputError(None, f"two files would be delivered as {relative}")
        target.parent.mkdir(parents=True, exist_ok=True)
        raw = data.encode("utf-8") if isinstance(data, str) else data
        target.write_bytes(raw)
        self.md5[relative] = bytes_md5(raw)
        return bundle.FileFacts(target.name, len(raw), self.md5[relative])

    def facts(self, relative: str) -> bundle.FileFacts:
        target = self.root / relative
        return bundle.FileFacts(target.name, target.stat().st_size, self.md5[relative])


class _Previous:
    """What the delivery at the target held before this run (nothing when new), and whether this
    run may give what changed a new version.

    Versions advance only once a delivery is released (layout.RELEASED_MARKER at its root, which
    the person handing it over creates) or when asked (`new_version`): until then a re-run
    brings the delivery up to date under the versions it has, so fixing a product or a sentence
    before anything went out does not make version 2."""

    def __init__(self, target: Path, new_version: bool = False) -> None:
        self.root = target
        self.released = self.file(layout.RELEASED_MARKER).is_file()
        self.new_version = new_version
        self.advanced = False  # set when this run gave anything a new version
        self.md5: dict[str, str] = {}
        manifest = self.file(layout.MANIFEST)
        if manifest.is_file():
            for line in manifest.read_text(encoding="utf-8", errors="replace").splitlines():
                digest, _, name = line.partition("  ")
                if name:
                    self.md5[name] = digest
        self.exists = manifest.is_file()

    def file(self, relative: str) -> Path:
        """The previous delivery's file RELATIVE (there or not), by the containment rule; a
        symbolic link there is refused in one line: it is neither read nor carried into the
        new delivery as the file it points at."""
        from ..storage.containment import checked_name, contained

        path = self.root.joinpath(*checked_name(relative, self.root).parts)
        if path.is_symlink() or contained(path, self.root) is None:
            raise InputError(path, "is a symbolic link in the previous delivery; a delivery holds files, "
                                   "not links (remove it, then deliver again)")
        return path

    @functools.cached_property
    def _voldesc(self) -> LabelFile | None:
        """The previous run's VOLDESC.CAT, read once (None when there is none)."""
        path = self.file(layout.VOLDESC)
        return read_pds3_label(path) if path.is_file() else None

    def volume_id(self) -> str | None:
        return self._voldesc.first("VOLUME_ID") if self._voldesc is not None else None

    def volume_version(self) -> int:
        text = self._voldesc.first("VOLUME_VERSION_ID") if self._voldesc is not None else None
        number = (text or "").rsplit(" ", 1)[-1]
        return int(number) if number.isdigit() else 0

    def bundle_label(self) -> Path | None:
        """The previous delivery's bundle label, found by its root element (Product_Bundle) as
        validate and review find it, whatever its name (bundle.xml, bundle_NAME.xml)."""
        label = bundle_label(self.root) if self.exists else None
        return self.file(label.name) if label is not None else None

    @property
    def advancing(self) -> bool:
        """Whether what changed since the previous run gets the next version."""
        return self.new_version or self.released

    def next_version(self, old: str | None, changed: bool) -> str:
        """`old` kept unless it is none, or it changed and versions advance (then the next)."""
        if old and not (changed and self.advancing):
            return old
        self.advanced = self.advanced or old is not None
        return bundle.next_version(old)


def make_delivery(source: str | os.PathLike[str], out: str | os.PathLike[str] | None = None,
                  dialect: str | Dialect = Dialect.PDS3, volume_id: str | None = None,
                  bundle_lid: str | None = None, shown_as: str | None = None,
                  text: str | os.PathLike[str] | DeliveryText | None = None, new_version: bool = False) -> Delivery:
    """Make (or bring up to date) a delivery of the products in `source`.

    dialect: "pds3" (volume: DATA/, EXTRAS/, INDEX/, VOLDESC.CAT, AAREADME.TXT), "pds4"
    (bundle: Product_Bundle, data/browse/document collections with inventories, browse and
    document labels) or "both". `out` is the delivery directory (default: `source` itself,
    whose products are then moved into the layout). `shown_as`: how the review page names the
    delivery when `out` is a local copy of it (an s3:// prefix). `text`: the delivery's own
    words (a TOML file's [delivery] table, deliver/text.py); a field it does not give is kept
    from the previous delivery's files where a person wrote it. `new_version`: give the volume,
    the bundle and whatever changed the next version (otherwise versions advance only once the
    delivery is released: layout.RELEASED_MARKER). Raises InputError for what the user must
    fix; nothing is changed then.
    """
    if dialect not in DIALECT_NAMES:
        raise InputError(None, f"dialect must be one of {', '.join(DIALECT_NAMES)}, not {dialect!r}")
    chosen = Dialect(dialect)
    source_dir = Path(source)
    if not source_dir.is_dir():
        raise InputError(source_dir, "not a directory of products")
    target = Path(out) if out is not None else source_dir
    refuse_link(target)
    in_place = target.exists() and target.resolve() == source_dir.resolve()
    if not in_place:
        _check_target(source_dir, target)
    given_text = load_text(text) if text is not None and not isinstance(text, DeliveryText) else text
    previous = _Previous(target, new_version)
    pds3, pds4 = chosen.pds3, chosen.pds4
    volume_id = _volume_id(volume_id or (previous.volume_id() if pds3 else None), pds3)
    bundle_lid = _bundle_lid(bundle_lid or (_previous_bundle_lid(previous) if pds4 else None), pds4)
    words = (given_text or DeliveryText()).over(previous_text(target, volume_id) if previous.exists else DeliveryText())
    index = _IndexRows(volume_id) if pds3 else None
    labels = LabelCache()  # each label is read once for the scan, the checks and the review page
    found = scan(source_dir, on_pds3=index.add if index else None, labels=labels)
    if found.imars:
        raise InputError(found.imars[0], "an iMars product (GeoTIFF + PVL metadata) has neither a PDS3 nor a "
                                         "PDS4 label, so no PDS volume or bundle can hold it; make the HRSC "
                                         f"products with {param('profile', 'hrsc')} "
                                         f"({param('label', 'both')} for PDS4)")
    if not found.products:
        raise InputError(source_dir, "holds no data product (no PDS3 or PDS4 product label)")
    _check_dialects(found, pds3, pds4)
    _check_unique_product_ids(found)
    _check_extras_current(source_dir, labels)
    log.info("%s: %d data product(s), %d preview(s), %d document(s), %d other file(s)", source_dir,
             len(found.products), len(found.previews), len(found.documents), len(found.others))
    work = target.parent / f".{target.name}.deliver-{os.getpid()}"
    try:
        if work.exists():
            shutil.rmtree(work)
        work.mkdir(parents=True)
    except OSError as exc:
        raise OutputError(target, f"cannot be written here ({exc.strerror or exc})") from None
    migrated = target.parent / f".{target.name}.migrate-{os.getpid()}"  # PDS4 labels of PDS3-only products
    try:
        if pds4:
            _migrate_pds3_only(found, migrated, bundle_lid, labels, source_dir)
        tree = _Tree(work, source_dir, migrated)
        result = _build(found, tree, previous, source_dir, in_place, chosen, index, bundle_lid, words)
        _carry_release_marker(previous, work)
        from ..review import write_review  # the review page, after (and outside) the manifest

        write_review(work, labels_only=True, shown_as=shown_as or str(target), labels=labels)
        replace_directory(work, target)
        log.info("delivery built in %s and moved to %s", work, target)
    except BaseException as exc:
        shutil.rmtree(work, ignore_errors=True)
        if isinstance(exc, OSError) and not isinstance(exc, PdsgenError):  # disk full, permissions ...
            raise OutputError(target, f"the delivery could not be written ({exc.strerror or exc}); "
                                      "nothing was changed") from None
        raise
    finally:
        shutil.rmtree(migrated, ignore_errors=True)
    result.path = target
    return result


def _carry_release_marker(previous: _Previous, work: Path) -> None:
    """A released delivery that this run left at its versions is still the one released; once
    anything got a new version, the new version is not released until its marker is made."""
    if previous.released and not previous.advanced:
        shutil.copy2(previous.file(layout.RELEASED_MARKER), work / layout.RELEASED_MARKER)


def _migrate_pds3_only(found: SourceSet, staging: Path, bundle_lid: str | None, labels: LabelCache,
                       source: Path) -> None:
    """A PDS3-only product gets the PDS4 label `pdsgen migrate` writes (its files unchanged); the
    files its label names may lie anywhere in `source`, the tree given (a volume's LABEL/*.FMT)."""
    from ..migrate import migrate_product  # on first use: a PDS3 volume never needs it

    for product in found.products:
        if product.pds4_label is None and product.pds3_label is not None:
            migrated = migrate_product(product.pds3_label, staging, bundle_lid=bundle_lid, copy=False, labels=labels,
                                       root=source)
            product.pds4_label = migrated.label_path
            for path in migrated.files:  # every file the PDS4 label describes travels with it
                if path not in product.files:
                    product.files.append(path)
                if path in found.others:
                    found.others.remove(path)


def _check_target(source: Path, target: Path) -> None:
    if target.exists() and not target.is_dir():
        raise OutputError(target, "exists and is not a directory")
    resolved, src = target.resolve(), source.resolve()
    if src in resolved.parents:
        raise InputError(target, f"the delivery cannot be inside the products' directory {source}")
    if resolved in src.parents:  # the swap would remove the products' directory with the old delivery
        raise InputError(source, f"the products' directory is inside the delivery {target}; "
                                 "run pdsgen deliver on the delivery itself")
    if target.is_dir() and any(target.iterdir()) and not (target / layout.MANIFEST).is_file():
        raise OutputError(target, f"exists and is not a delivery (no {layout.MANIFEST}); "
                                  "give a new or empty directory")


def _volume_id(volume_id: str | None, needed: bool) -> str | None:
    if not needed:
        return volume_id
    if not volume_id:
        raise InputError(None, f"a PDS3 volume needs {param('volume_id')} (e.g. {param('volume_id', 'MROHR_1001')})")
    if not layout.VOLUME_ID_PATTERN.fullmatch(volume_id):
        raise InputError(None, f"{param('volume_id', volume_id)}: up to 11 upper-case letters, digits and "
                               "underscores, starting with a letter")
    return volume_id


def _bundle_lid(lid: str | None, needed: bool) -> str | None:
    if not needed:
        return lid
    if not lid:
        raise InputError(None, f"a PDS4 bundle needs {param('bundle_lid')} (urn:nasa:pds:NAME)")
    if not layout.BUNDLE_LID_PATTERN.fullmatch(lid):
        raise InputError(None, f"{param('bundle_lid', lid)}: expected urn:nasa:pds:NAME, NAME in lower-case "
                               "letters, digits, '.', '_' and '-'")
    return lid


def _previous_bundle_lid(previous: _Previous) -> str | None:
    label = previous.bundle_label()
    if label is None:
        return None
    text = label.read_text(encoding="utf-8", errors="replace")
    start, end = text.find("<logical_identifier>"), text.find("</logical_identifier>")
    return text[start + len("<logical_identifier>"):end].strip() if 0 <= start < end else None


def _check_unique_product_ids(found: SourceSet) -> None:
    """Two labels with one PRODUCT_ID would be one index row and one LID: refuse, naming both."""
    seen: dict[str, DataProduct] = {}
    for product in found.products:
        first = seen.setdefault(product.product_id.upper(), product)
        if first is not product:
            raise InputError(product.pds3_label or product.pds4_label,
                             f"has the product ID {product.product_id} of {first.pds3_label or first.pds4_label} "
                             "too; each product of a delivery needs its own")


def _check_extras_current(source: Path, labels: LabelCache) -> None:
    """Stale Extras are refused, in one line naming the files and the remedy: a product remade
    after its Extras (README.TXT records the label's MD5, archive/extras_check.py)."""
    from ..archive.extras_check import extras_problems

    stale = [problem for problem in extras_problems(source, labels) if problem.kind != "absent"]
    if stale:
        names = sorted({f"{p.file.parent.name}/{p.file.name}" for p in stale})
        raise InputError(stale[0].file, f"stale Extras ({len(stale)} disagreement(s) with the products, in "
                                        f"{', '.join(names)}): {stale[0].message}")


def _check_dialects(found: SourceSet, pds3: bool, pds4: bool) -> None:
    for product in found.products:
        if pds3 and product.pds3_label is None:
            raise InputError(product.pds4_label, "has no PDS3 label, which a PDS3 volume needs "
                                                 f"(make the product with {param('label', 'both')})")


def _build(found: SourceSet, tree: _Tree, previous: _Previous, source: Path, in_place: bool, dialect: Dialect,
           index: _IndexRows | None, bundle_lid: str | None, words: DeliveryText) -> Delivery:
    result = Delivery(tree.root, dialect, volume_id=index.writer.volume_id if index else None, bundle_lid=bundle_lid)
    today = clock.today()
    total = len(found.products) + len(found.previews) + len(found.documents)
    done = 0
    data_members: dict[str, tuple[DataProduct, list[str]]] = {}
    for product in found.products:
        relatives = [_place_product_file(tree, f, product) for f in product.files]
        data_members[product.product_id.upper()] = (product, relatives)
        done += 1
        advance(done, total, "products")
    _place_support_files(tree, found)
    preview_paths = []
    for preview in found.previews:
        preview_paths.append((preview, f"{layout.EXTRAS_DIR}/{preview.name}"))
        tree.place(preview, preview_paths[-1][1])
        done += 1
        advance(done, total, "products")
    document_paths = []
    for document in found.documents:
        directory = layout.DATA_DIR if document.name.upper() == "JP2INFO.TXT" else layout.EXTRAS_DIR
        document_paths.append((document, f"{directory}/{document.name}"))
        tree.place(document, document_paths[-1][1])
        done += 1
        advance(done, total, "products")
    if in_place:
        for other in found.others:
            tree.place(other, other.relative_to(source).as_posix())
    result.skipped, result.in_place = list(found.others), in_place
    result.named_by_file = [(p.pds3_label, p.product_id) for p in found.products if p.id_from_file and p.pds3_label]
    result.products, result.previews, result.documents = len(found.products), len(preview_paths), len(document_paths)
    writer = None
    if dialect.pds4:
        assert bundle_lid is not None
        writer = _write_bundle(tree, previous, bundle_lid, data_members, preview_paths, document_paths, today, result,
                               words)
    else:
        _carry_pds4_labels(tree, data_members)
    if index is not None:
        _write_volume(tree, previous, index, today, result, words)
    if writer is not None:  # the manifest's product and the bundle label: from what the files above hold
        writer.manifest_member()
        writer.bundle_label(writer.collections(("miscellaneous",)))
    result.placeholders = _placeholders(tree.root)
    result.file_count = _write_manifest(tree)
    if writer is not None:
        result.file_count += writer.manifest_label()
    return result


def _placeholders(root: Path) -> int:
    """The [TO BE WRITTEN: ...] placeholders in the text pdsgen wrote around the products."""
    files = [root / layout.VOLDESC, root / layout.AAREADME, *root.glob("bundle_*.xml"),
             *(root / directory / layout.collection_label_name(collection)
               for collection, (_, _, directory) in layout.COLLECTIONS.items())]
    return sum(len(layout.PLACEHOLDER_PATTERN.findall(path.read_text(encoding="latin-1")))
               for path in files if path.is_file())


def _place_product_file(tree: _Tree, path: Path, product: DataProduct) -> str:
    relative = f"{layout.DATA_DIR}/{path.name}"
    if path == product.pds4_label:
        return relative  # written by _write_bundle (with its bundle LID) or _carry_pds4_labels
    tree.place(path, relative)
    return relative


def _place_support_files(tree: _Tree, found: SourceSet) -> None:
    """Description, structure and catalog files the PDS3 labels name, once each however many
    labels share one (a data file of a product is placed already): beside the labels in DATA/,
    except catalog files with labels of their own (DSMAP.CAT), which go to CATALOG/ - where a
    reader looks for them, and where the volume's checks do not take them for data products."""
    placed = {f for product in found.products for f in product.files}
    for product in found.products:
        for path in product.support:
            if path not in placed:
                directory = layout.CATALOG_DIR if is_pds3_label(path) else layout.DATA_DIR
                tree.place(path, f"{directory}/{path.name}")
                placed.add(path)


def _carry_pds4_labels(tree: _Tree, data_members: dict[str, tuple[DataProduct, list[str]]]) -> None:
    """A PDS3 volume keeps a product's PDS4 label as the product made it."""
    for product, _ in data_members.values():
        if product.pds4_label is not None:
            tree.place(product.pds4_label, f"{layout.DATA_DIR}/{product.pds4_label.name}")


# --- PDS3 ---------------------------------------------------------------------------------------

class _IndexRows:
    """The index rows, written (to the writer's scratch file) as the scan reads each label."""

    def __init__(self, volume_id: str | None) -> None:
        assert volume_id is not None
        self.writer = IndexWriter(volume_id)
        self.institution: str | None = None

    def add(self, product: DataProduct, values: dict[str, str | None]) -> None:
        assert product.pds3_label is not None
        values["PRODUCT_ID"] = values.get("PRODUCT_ID") or product.product_id
        values["PRODUCT_CREATION_TIME"] = values.get("PRODUCT_CREATION_TIME") or made_at(product.pds3_label)
        self.writer.add(f"{layout.DATA_DIR}/{product.pds3_label.name}", values)
        self.institution = self.institution or values.get("PRODUCER_INSTITUTION_NAME")


def made_at(label: Path) -> str:
    """When a product was made, for a label that does not say: its label file's modification time
    (UTC, to the second; the product's own file, not the time of delivery), no later than
    SOURCE_DATE_EPOCH when that is set (a reproducible build's fixed time: pdsgen.clock)."""
    return clock.no_later_than_epoch(label.stat().st_mtime).strftime("%Y-%m-%dT%H:%M:%S")


def _write_volume(tree: _Tree, previous: _Previous, index: _IndexRows, today: str, result: Delivery,
                  words: DeliveryText) -> None:
    writer = index.writer
    (tree.root / layout.INDEX_DIR).mkdir(exist_ok=True)
    log.info("%s/%s: %d row(s)", layout.INDEX_DIR, layout.INDEX_TABLE, writer.rows)
    for path in writer.write(tree.root / layout.INDEX_DIR):
        tree.md5[path.relative_to(tree.root).as_posix()] = file_md5(path)
    version = previous.volume_version() or 1
    if previous.exists and (previous.new_version or (previous.released and _volume_changed(tree, previous))):
        version += 1
        previous.advanced = True
    facts = VolumeFacts(writer.volume_id, version, today, tuple(writer.data_set_ids), index.institution,
                        result.products, result.previews, words)
    tree.write(layout.VOLDESC, voldesc_text(facts))
    tree.write(layout.AAREADME, aareadme_text(facts))


def _volume_changed(tree: _Tree, previous: _Previous) -> bool:
    """Whether any file other than the volume's own description differs from the previous run."""
    own = {layout.VOLDESC, layout.AAREADME}
    now = {k: v for k, v in tree.md5.items() if k not in own and not _made_last(k)}
    before = {k: v for k, v in previous.md5.items() if k not in own and not _made_last(k)}
    return now != before


def _made_last(relative: str) -> bool:
    """Files written after every other, from what those hold: the bundle label, the miscellaneous
    collection (the manifest's label's), the manifest and its label. Whether they changed follows
    from the others; they are left out when a run asks what changed."""
    return (relative in (layout.MANIFEST, layout.MANIFEST_LABEL) or relative.startswith(f"{layout.MISCELLANEOUS_DIR}/")
            or ("/" not in relative and relative.startswith("bundle_") and relative.endswith(".xml")))


# --- PDS4 ---------------------------------------------------------------------------------------

def _changed(tree: _Tree, previous: _Previous, relatives: list[str]) -> bool:
    return any(previous.md5.get(r) != tree.md5.get(r) for r in relatives)


def _write_bundle(tree: _Tree, previous: _Previous, bundle_lid: str,
                  data_members: dict[str, tuple[DataProduct, list[str]]],
                  preview_paths: list[tuple[Path, str]], document_paths: list[tuple[Path, str]],
                  today: str, result: Delivery, words: DeliveryText) -> _BundleWriter:
    """The bundle's products and their collections; the manifest's collection and the bundle label
    come after every other file (`_BundleWriter.manifest_member`, `.bundle_label`)."""
    writer = _BundleWriter(tree, previous, bundle_lid, today, result, words)
    for key, (product, relatives) in data_members.items():
        writer.data_product(key, product, relatives)
    for preview, relative in preview_paths:
        writer.preview(preview, relative, data_members)
    for document, relative in document_paths:
        writer.document(document, relative)
    writer.collections(("data", "browse", "document"))
    return writer


class _BundleWriter:
    """The PDS4 labels and inventories of one run; versions follow what the previous run wrote."""

    def __init__(self, tree: _Tree, previous: _Previous, bundle_lid: str, today: str, result: Delivery,
                 words: DeliveryText) -> None:
        self.tree, self.previous, self.bundle_lid, self.today, self.result = tree, previous, bundle_lid, today, result
        self.words = words
        self.name = bundle_lid.rsplit(":", 1)[-1]
        self.members: dict[str, list[str]] = {c: [] for c in layout.COLLECTIONS}
        self.old = {c: bundle.read_inventory(previous.file(f"{d}/{layout.inventory_name(c)}"))
                    for c, (_, _, d) in layout.COLLECTIONS.items()}
        self.data_lidvid: dict[str, str] = {}  # product id (upper) -> its LIDVID
        self.data_changed: set[str] = set()  # LIDs of data products new or re-versioned: their previews follow
        self.entries: list[dict[str, str]] = []  # the bundle's member entries, one per collection written
        self.manifest_lidvid = ""

    def _member(self, collection: str, lid: str, changed: bool) -> str:
        """The member's LIDVID (its previous version unless it changed), listed in its collection."""
        before = self.old[collection].get(lid)
        version = self.previous.next_version(before, changed)
        lidvid = f"{lid}::{version}"
        self.members[collection].append(lidvid)
        if version != before:
            self.result.changed.append(lidvid)
            if collection == "data":
                self.data_changed.add(lid)
        return lidvid

    def data_product(self, key: str, product: DataProduct, relatives: list[str]) -> None:
        """The product's own PDS4 label, with the LID under the data collection and its version."""
        assert product.pds4_label is not None
        lid = f"{self.bundle_lid}:data:{layout.lid_part(product.product_id)}"
        label = f"{layout.DATA_DIR}/{product.pds4_label.name}"
        text = product.pds4_label.read_text(encoding="utf-8")
        changed = (_changed(self.tree, self.previous, [r for r in relatives if r != label])
                   or _label_changed(self.previous.file(label), text))
        lidvid = self._member("data", lid, changed)
        self.tree.write(label, bundle.set_identification(text, lid, lidvid.split("::")[1]))
        self.data_lidvid[key] = lidvid

    def preview(self, preview: Path, relative: str, data_members: dict[str, tuple[DataProduct, list[str]]]) -> None:
        """A Product_Browse label beside an Extras image, referring to the data product it previews."""
        key = preview.name.split(".", 1)[0].upper()
        if key not in self.data_lidvid:
            raise InputError(preview, "previews no data product of the delivery (its name must start with "
                                      "the PRODUCT_ID of one)")
        stem = relative.rsplit(".", 1)[0]
        lid = f"{self.bundle_lid}:browse:{layout.lid_part(Path(stem).name)}"
        data_lid = self.data_lidvid[key].split("::")[0]
        changed = _changed(self.tree, self.previous, [relative]) or data_lid in self.data_changed
        lidvid = self._member("browse", lid, changed)
        title = f"Preview {preview.name} of {data_members[key][0].product_id}"
        self.tree.write(f"{stem}.xml", bundle.render("browse.xml.j2", {
            **_head("Product_Browse", lid, lidvid.split("::")[1], title), "data_lidvid": self.data_lidvid[key],
            "file": self.tree.facts(relative), "encoding": bundle.encoding_of(preview.name)}))

    def document(self, document: Path, relative: str) -> None:
        """A Product_Document label beside README.TXT or JP2INFO.TXT."""
        stem = relative.rsplit(".", 1)[0]
        lid = f"{self.bundle_lid}:document:{layout.lid_part(Path(stem).name)}"
        version = self._member("document", lid, _changed(self.tree, self.previous, [relative])).split("::")[1]
        title = f"{document.name}: {_document_title(document.name)}"
        self.tree.write(f"{stem}.xml", bundle.render("document.xml.j2", {
            **_head("Product_Document", lid, version, title), "citation": title, "year": self.today[:4],
            "date": self.today, "edition": f"{document.name} version {version}", "file": self.tree.facts(relative)}))

    def manifest_member(self) -> None:
        """The checksum manifest as a product of the miscellaneous collection (its label is written
        after it, `manifest_label`): a new version when a file it lists, other than those made
        last from the rest (_made_last), changed."""
        now = {k: v for k, v in self.tree.md5.items() if not _made_last(k)}
        before = {k: v for k, v in self.previous.md5.items() if not _made_last(k)}
        lid = f"{self.bundle_lid}:miscellaneous:{layout.lid_part(Path(layout.MANIFEST).stem)}"
        self.manifest_lidvid = self._member("miscellaneous", lid, now != before)

    def manifest_label(self) -> int:
        """The manifest's Product_Ancillary label beside it, written after it (it gives the
        manifest's MD5, so no manifest lists it); the number of files written."""
        from ..pds4.checksum_manifest import manifest_label

        lid, _, version = self.manifest_lidvid.partition("::")
        self.tree.write(layout.MANIFEST_LABEL, manifest_label(self.tree.root / layout.MANIFEST, lid, version))
        return 1

    def collections(self, names: tuple[str, ...]) -> list[dict[str, str]]:
        """Each collection of `names` that has members: its inventory and label; the bundle's
        entries so far (those collections' added)."""
        entries = self.entries
        for collection, (kind, reference_type, directory) in layout.COLLECTIONS.items():
            if collection not in names:
                continue
            lidvids = self.members[collection]
            if not lidvids:
                continue
            inventory = bundle.inventory_text(lidvids)
            before = self.previous.file(f"{directory}/{layout.inventory_name(collection)}")
            unchanged = before.is_file() and before.read_bytes() == inventory.encode("ascii")
            old_label = self.previous.file(f"{directory}/{layout.collection_label_name(collection)}")
            old_version = bundle.read_version(old_label)
            version = self.previous.next_version(old_version, not unchanged)
            self.tree.write(f"{directory}/{layout.inventory_name(collection)}", inventory)
            lid = f"{self.bundle_lid}:{collection}"
            count = f"{len(lidvids)} {collection} product(s) of bundle {self.name}"
            self.tree.write(f"{directory}/{layout.collection_label_name(collection)}", bundle.render(
                "collection.xml.j2", {
                    **_head("Product_Collection", lid, version, f"{kind} collection of bundle {self.name}"),
                    "citation": f"The {count}.", "year": self.today[:4], "collection_type": kind,
                    "authors": self.words.authors, "keywords": self.words.keywords,
                    "inventory": layout.inventory_name(collection), "records": len(lidvids),
                    "description": f"{count}."}))
            entries.append({"lidvid": f"{lid}::{version}", "reference_type": reference_type})
        return entries

    def bundle_label(self, entries: list[dict[str, str]]) -> None:
        """The Product_Bundle label: a new version when its set of collection LIDVIDs changed."""
        old_label = self.previous.bundle_label()
        old_version = bundle.read_version(old_label) if old_label else None
        old_text = old_label.read_text(encoding="utf-8", errors="replace") if old_label else ""
        old_entries = set(re.findall(r"<lidvid_reference>\s*([^<]*?)\s*</lidvid_reference>", old_text))
        same = old_version is not None and old_entries == {e["lidvid"] for e in entries}
        version = self.previous.next_version(old_version, not same or self.previous.new_version)
        result, words = self.result, self.words
        counts = (f"{result.products} data product(s), {result.previews} preview(s) and "
                  f"{result.documents} document(s), made by pdsgen.")
        self.tree.write(layout.bundle_label_name(self.bundle_lid), bundle.render("bundle.xml.j2", {
            **_head("Product_Bundle", self.bundle_lid, version, words.title or f"Bundle {self.name}"),
            "citation": words.description or layout.PLACEHOLDER.format(what="the citation description of the bundle"),
            "year": self.today[:4], "members": entries, "authors": words.authors, "keywords": words.keywords,
            "description": words.description or counts}))
        result.bundle_version = version
        log.info("bundle %s::%s: %d product(s) new or with a new version", self.bundle_lid, version,
                 len(result.changed))


def _head(product_class: str, lid: str, version: str, title: str) -> dict[str, object]:
    return {"product_class": product_class, "lid": lid, "version_id": version, "title": title,
            "citation": None, "year": None, "authors": None, "keywords": None}


def _label_changed(before: Path, text: str) -> bool:
    try:
        old = before.read_text(encoding="utf-8")
    except OSError:
        return True
    return bundle.identification_free(old) != bundle.identification_free(text)


def _document_title(name: str) -> str:
    return {"README.TXT": "what the preview images show and how they were made",
            "JP2INFO.TXT": "how the JPEG 2000 files are encoded"}.get(name.upper(), "document")


# --- manifest -----------------------------------------------------------------------------------

def _write_manifest(tree: _Tree) -> int:
    """MD5SUMS.TXT over every file of the tree, in path order, written last."""
    lines = []
    for path in _files(tree.root):
        relative = path.relative_to(tree.root).as_posix()
        lines.append(f"{tree.md5.get(relative) or file_md5(path)}  {relative}\n")
    (tree.root / layout.MANIFEST).write_text("".join(lines), encoding="utf-8")
    log.info("%s: MD5 of %d file(s)", layout.MANIFEST, len(lines))
    return len(lines) + 1


def _files(root: Path) -> Iterator[Path]:
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames.sort()
        for name in sorted(filenames):
            if Path(dirpath) == root and name == layout.MANIFEST:
                continue
            yield Path(dirpath) / name
