"""DLV family: a delivery (a PDS3 volume, a PDS4 bundle, its MD5 manifest) checked as a whole.

This module registers the family and holds its checks of one file (DLV-007, DLV-008, DLV-025)
and the runner's hook; the checks across a delivery's files are the package validate/delivery/
(one module a part), loaded only when a delivery is checked, so that a plain validation's
start-up imports none of it. The PDS4 label reader those checks join is registered here as a
per-file fact (validate/facts.py), so that the workers of a parallel run read each label for
them.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ...archive import layout
from ...label.tree import Block, Statement
from .. import facts
from ..model import Finding, Hit
from ..registry import Rule, register

if TYPE_CHECKING:
    from ...label.read import LabelCache
    from ..context import FileContext


def is_delivery(directory: Path) -> bool:
    """A directory `pdsgen deliver` made (or one laid out the same way), or any PDS4 bundle: a
    Product_Bundle label at its root, named bundle.xml, bundle_*.xml or anything else."""
    from ...archive.scan import bundle_labels

    return directory.is_dir() and ((directory / layout.MANIFEST).is_file()
                                   or (directory / layout.INDEX_DIR / layout.INDEX_LABEL).is_file()
                                   or bool(bundle_labels(directory)))


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


def check_jp2info(ctx: FileContext) -> Iterator[Hit]:
    """DLV-025: the JP2INFO.TXT a COMPRESSED_FILE's ^DESCRIPTION names describes the JP2 beside it."""
    for block in ctx.root.walk():
        if block.kind != "OBJECT" or block.name.upper() != "COMPRESSED_FILE":
            continue
        jp2_name, info_name = block.text("FILE_NAME"), block.text("^DESCRIPTION")
        if not jp2_name or not info_name or ctx.outside(jp2_name) or ctx.outside(info_name):
            continue
        from ..delivery.jp2 import jp2_header, jp2info_entries, shape

        jp2, info = ctx.resolve(jp2_name)[0], ctx.resolve(info_name)[0]
        if jp2 is None or info is None or not jp2.is_file() or not info.is_file():
            continue  # a missing file is the pointer rules'
        entry = jp2info_entries(info).get(jp2_name.upper())
        header = jp2_header(jp2) if entry is not None else None
        if entry is not None and header is not None and entry[:4] != header:
            yield Hit(f"describes {jp2_name} as {shape(entry[:4])}, but the JP2 is {shape(header)}: "
                      f"{info.name} was written for another version of the JP2 (make the product again, or "
                      "deliver the JP2INFO.TXT made with it)", entry[4], file=str(info))



@facts.fact("pds4")
def pds4_label_parts(path: Path) -> Any:
    """What the delivery checks read of one PDS4 label (validate/delivery/model.read_pds4), or None."""
    from ..delivery.model import read_pds4

    return read_pds4(path)


def _pds4_parts_of_run(path: Path) -> Any:
    """A PDS4 label's parts as a worker read them, or read here."""
    return facts.of(pds4_label_parts, path)


# --- the runner hook ----------------------------------------------------------------------------

def check_delivery(root: Path, labels_only: bool = False, labels: LabelCache | None = None) -> list[Finding]:
    """Every DLV finding for the delivery at `root` (severities as registered). `labels`: the
    run's label cache (`pdsgen deliver` reads each label once for all its steps)."""
    from ..delivery import delivery_findings
    from ..registry import rules

    found = delivery_findings(root, labels_only, labels, _pds4_parts_of_run)
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
    Rule("DLV-027", "error", "an Extras browse or thumbnail JPEG is the size the Extras make of its delivered "
                             "product (not a preview of a product since remade)", None),
    Rule("DLV-028", "warning", "every preview image beside an Extras README.TXT is one it documents", None),
    Rule("DLV-029", "error", "a product's README.TXT entry, the previews it lists and its PDS4 label's LID name "
                             "that product, not another of the delivery", None),
    Rule("DLV-020", "error", "every file MD5SUMS.TXT lists exists and has that MD5", None, needs_data=True),
    Rule("DLV-021", "error", "every file of the delivery is listed in MD5SUMS.TXT", None),
    Rule("DLV-030", "error", "everything a delivery holds is a regular file of it (a FIFO, socket, device, or a link "
                             "dangling or leading outside is named, never opened)", None),
)
