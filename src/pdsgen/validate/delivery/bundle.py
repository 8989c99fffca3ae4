"""DLV-010 to DLV-016: a PDS4 bundle's labels, collections, inventories and references against
each other (PDS4 labels read with lxml, CSV inventories with the csv module)."""

from __future__ import annotations

import csv
import os
from pathlib import Path

from ...archive import layout
from ...bounded import text_lines
from ...errors import InputError
from ...label.parser import is_pds3_head
from ...pds4.detect import LABEL_SUFFIXES as PDS4_LABEL_SUFFIXES
from .model import DeliveryModel, Pds4Record
from .parts import Found, all_files, read_head


def check_bundle(model: DeliveryModel, found: list[Found]) -> bool:
    """The bundle's checks on the model's PDS4 labels; whether the delivery is a bundle."""
    root, labels = model.root, model.pds4
    bundles = [label for label in labels if label.product_class == "Product_Bundle"]
    if not bundles:
        return False
    by_lidvid: dict[str, Pds4Record] = {}
    by_lid: dict[str, list[Pds4Record]] = {}
    for label in labels:
        other = by_lidvid.get(label.lidvid)
        if other is not None:
            found.append(Found("DLV-012", label.path, f"LIDVID {label.lidvid} is also that of "
                                                       f"{other.path.relative_to(root)}"))
        by_lidvid.setdefault(label.lidvid, label)
        by_lid.setdefault(label.lid, []).append(label)
    versions = _versions([b for b in bundles if b.lid == bundles[0].lid])  # a bundle may keep its release history
    bundle = versions[-1]
    collections = [label for label in labels if label.product_class == "Product_Collection"]
    listed = {ref for version in versions for ref, _, _ in version.members}
    for collection in collections:  # a collection version belongs to the bundle versions that list it
        if collection.lidvid not in listed and collection.lid not in listed:
            found.append(Found("DLV-015", bundle.path, f"{_which_bundle(versions)} collection {collection.lidvid} "
                                                        f"({collection.path.relative_to(root)})"))
    for version in versions:  # each version against its own members
        for ref, status, line in version.members:  # a secondary member is another bundle's: not looked for
            if status.lower() == "primary" and ref not in by_lidvid and ref not in by_lid:
                found.append(Found("DLV-015", version.path, f"primary member {ref} is no collection of this "
                                                             "delivery", line))
    owned = bundle.lid + ":"
    for label in labels:
        for ref, line in label.references:
            if ref.startswith(owned) and ref not in by_lidvid and ref not in by_lid:
                found.append(Found("DLV-014", label.path, f"{ref} is no product of this delivery (one "
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
    return True



def _check_unlabelled(root: Path, labels: list[Pds4Record], found: list[Found]) -> None:
    """DLV-016: every file of a bundle is a label or described by one (NASA's validate: a
    warning, UNLABELED_FILE 'warning.file.not_referenced_in_label'). Not files of no delivery
    (the review pages, the release marker); in a delivery that is a PDS3 volume too, not the
    volume's own (VOLDESC.CAT, AAREADME.TXT, INDEX/, CATALOG/, PDS3 labels)."""
    described = {os.path.normpath(label.path) for label in labels}
    described |= {os.path.normpath(p) for label in labels for p in label.described}
    volume = (root / layout.VOLDESC).is_file()
    stems = {(os.path.dirname(p), os.path.basename(p).split(".", 1)[0].upper()) for p in described}
    for path in all_files(root):
        relative = path.relative_to(root)
        name = relative.as_posix()
        if os.path.normpath(path) in described or name == layout.RELEASED_MARKER or layout.is_review_page(name):
            continue
        if (volume and _volume_part(relative)) or _pds3_label_of_described(path, stems):
            continue
        if path.suffix.lower() in PDS4_LABEL_SUFFIXES and not path.name.lower().endswith(".aux.xml"):
            continue  # taken for a label (NASA's validate too: an empty foo.xml in its suite case 482-4 is none)
        found.append(Found("DLV-016", path, _unlabelled_message(path)))


def _volume_part(relative: Path) -> bool:
    """A file of the PDS3 volume that shares the delivery with the bundle."""
    return (relative.as_posix() in (layout.VOLDESC, layout.AAREADME, layout.MANIFEST)
            or relative.parts[0] in (layout.INDEX_DIR, layout.CATALOG_DIR))


def _pds3_label_of_described(path: Path, stems: set[tuple[str, str]]) -> bool:
    """A product's detached PDS3 label kept beside the data its PDS4 label describes (X.LBL beside
    a described X.JP2): the same product in the other dialect, not an unlabelled file."""
    key = (os.path.normpath(path.parent), path.name.split(".", 1)[0].upper())
    return key in stems and (path.suffix.lower() == ".lbl" or is_pds3_head(read_head(path)))


def _unlabelled_message(path: Path) -> str:
    if path.name.lower().endswith(".aux.xml"):
        return ("a GDAL .aux.xml sidecar (statistics GDAL wrote beside a file it opened): no label describes it; "
                "remove it from the bundle")
    if path.name == layout.MANIFEST:
        return (f"no label describes {layout.MANIFEST}: a bundle's checksum manifest is a product with a label "
                f"({layout.MANIFEST_LABEL}, a Product_Ancillary with a Checksum_Manifest; pdsgen deliver writes it)")
    return "no PDS4 label of the bundle describes this file (name it in a label's File, or remove it)"


def _version_key(label: Pds4Record) -> tuple[int, ...]:
    """version_id M.N compared as numbers (1.10 after 1.9); one not of that form sorts first."""
    try:
        return tuple(int(part) for part in label.version.split("."))
    except ValueError:
        return ()


def _versions(labels: list[Pds4Record]) -> list[Pds4Record]:
    """The versions of one LID, oldest first: a bundle directory may keep its release history
    (SPICE archives keep every version of the bundle and of each collection)."""
    return sorted(labels, key=_version_key)


def _which_bundle(versions: list[Pds4Record]) -> str:
    """The subject of DLV-015's 'does not list': the bundle, or each of its versions."""
    if len(versions) == 1:
        return "the bundle does not list"
    return f"no version of the bundle ({', '.join(v.version for v in versions)}) lists"


def _check_unlisted(versions: list[Pds4Record], listed: set[str], labels: list[Pds4Record],
                    found: list[Found]) -> None:
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
            found.append(Found("DLV-011", label.path, f"{label.lidvid} is not in {where} of "
                                                       f"{collection.lid} ({names})"))


def _check_inventory(root: Path, collection: Pds4Record, by_lidvid: dict[str, Pds4Record],
                     members: dict[str, Path], found: list[Found]) -> set[str] | None:
    """The inventory of one version of a collection, checked against its own members: what
    it lists (for DLV-011 across the versions), or None when it has none to read."""
    if collection.inventory is None:
        return None
    try:
        lines = text_lines(collection.inventory, "inventory", "ascii")
    except InputError as exc:
        found.append(Found("DLV-010", collection.path, f"cannot read its inventory {collection.inventory.name}: "
                                                        f"{exc.problem}"))
        return None
    prefix = collection.lid + ":"
    listed: set[str] = set()
    for number, row in enumerate(csv.reader(lines), 1):
        if len(row) < 2:
            continue
        entry = row[1].strip()
        lid = entry.split("::", 1)[0]
        secondary = row[0].strip().upper() == "S"  # another collection's product: not looked for here
        present = entry in by_lidvid  # an absent member is DLV-010's, whatever its LID (as NASA's validator)
        if not secondary and present and not lid.startswith(prefix):
            found.append(Found("DLV-013", collection.inventory, f"member {entry} is not under the collection's "
                                                                 f"LID {collection.lid}", number))
        if not secondary:  # a product is primary in one collection, secondary in any number
            if entry in members and members[entry] != collection.inventory:  # a repeat within one: PDS4-056
                found.append(Found("DLV-012", collection.inventory, f"{entry} is also listed in "
                                                                     f"{members[entry].relative_to(root)}", number))
            members.setdefault(entry, collection.inventory)
        listed.add(entry)
        if secondary:
            continue
        if "::" not in entry:  # the Standards Reference: a primary member is named by its LIDVID
            found.append(Found("DLV-010", collection.inventory, f"primary member {entry} has no version (::M.N): "
                                                                 "a primary member is named by its LIDVID", number))
        elif not present:
            found.append(Found("DLV-010", collection.inventory, f"primary member {entry} is listed, but no label "
                                                                 "in the delivery has that LIDVID", number))
    return listed

