"""A delivery (a PDS3 volume, a PDS4 bundle, its MD5 manifest) checked as a whole: the DLV
family's checks across files (validate/families/delivery_rules.py registers the rules and
runs these once per delivery; this package is loaded only when a delivery is checked).

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

One module a part: index.py (DLV-001..005), placeholders.py (DLV-006), bundle.py
(DLV-010..016), dialects.py (DLV-022..024), extras.py (DLV-017..019, DLV-026..028),
identifiers.py (DLV-029), manifest.py (DLV-020, DLV-021); model.py the delivery's one model
they read their parts from, parts.py what they share.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ...archive import layout
from .bundle import check_bundle
from .dialects import check_both_dialects
from .extras import check_extras, check_quick_looks, check_undocumented
from .identifiers import check_identifiers
from .index import check_index
from .manifest import check_manifest
from .model import DeliveryModel, Pds4Reader
from .parts import Found
from .placeholders import check_placeholders

if TYPE_CHECKING:
    from ...label.read import LabelCache


def delivery_findings(root: Path, labels_only: bool, labels: LabelCache | None, read_pds4: Pds4Reader) -> list[Found]:
    """Every DLV finding of the delivery at `root`, in report order, each check reading the parts
    of the delivery's one model (model.py), built here once. `read_pds4`: the run's reader of one
    PDS4 label (what a worker read of it, or read here: validate/facts.py)."""
    model = DeliveryModel(root, labels, read_pds4)
    found: list[Found] = []
    check_index(model, found)
    check_placeholders(root, found)
    if check_bundle(model, found) and (root / layout.VOLDESC).is_file():
        check_both_dialects(model, found)
    check_extras(model, found)
    check_quick_looks(model, found)
    check_undocumented(model, found)
    check_identifiers(model, found)
    check_manifest(model, labels_only, found)
    return found
