"""The Extras against the delivered products, on the delivery's model: DLV-017/018/019 (README.TXT
against the labels, archive/extras_check.py), DLV-026 (a quick look against its product),
DLV-027 (a browse or thumbnail against its product), DLV-028 (a preview README.TXT does not list)."""

from __future__ import annotations

from pathlib import Path

from .jp2 import jp2_header
from .model import DeliveryModel, ExtrasEntry
from .parts import Found

_EXTRAS_RULES = {"stale": "DLV-017", "differs": "DLV-018", "absent": "DLV-019", "preview": "DLV-027"}


def check_extras(model: DeliveryModel, found: list[Found]) -> None:
    """DLV-017/018/019/027: each README.TXT entry against the record of the label it names."""
    from ...archive.extras_check import entry_problems

    for extras in model.extras:
        for problem in entry_problems(extras.readme, extras.entry, extras.product, model.label_facts(extras)):
            found.append(Found(_EXTRAS_RULES[problem.kind], problem.file, problem.message, problem.line))


def check_quick_looks(model: DeliveryModel, found: list[Found]) -> None:
    """DLV-026: each quick-look JP2 README.TXT lists is its product at full scale: the size of the
    image its delivered label describes."""
    for extras in model.extras:
        record = model.pds3(extras.product) if extras.product is not None else None
        if record is None or record.size is None:
            continue
        samples, lines = record.size
        for path in _listed(extras):
            header = jp2_header(path) if path.name.upper().endswith(".QLOOK.JP2") and path.is_file() else None
            if header is not None and (header[0], header[1]) != (samples, lines):
                found.append(Found("DLV-026", path, f"{header[0]} samples x {header[1]} lines, but the "
                                                    f"quick look of {record.path.name} is the product at full "
                                                    f"scale ({samples} samples x {lines} lines): a quick look "
                                                    f"of another version of the product (pdsgen extras "
                                                    f"{record.path.name} -o {extras.readme.parent.name} --overwrite)"))


def _listed(extras: ExtrasEntry) -> list[Path]:
    """The files an entry lists, by the containment rule (a name leading out is never read)."""
    from ...archive.extras_check import named_in

    return [path for name, _ in extras.entry.files if (path := named_in(extras.readme.parent, name)) is not None]


def check_undocumented(model: DeliveryModel, found: list[Found]) -> None:
    """DLV-028: every preview image beside an Extras README.TXT is one of its entries' files (one
    it does not list is left from Extras made before: of a product since removed or renamed)."""
    from ...archive.scan import is_preview

    listed: dict[Path, set[str]] = {}
    for extras in model.extras:
        listed.setdefault(extras.readme, set()).update(name for name, _ in extras.entry.files)
    for readme, names in listed.items():
        for path in sorted(readme.parent.iterdir()):
            if path.is_file() and is_preview(path.name) and path.name not in names:
                found.append(Found("DLV-028", path, f"a preview {readme.name} does not document: left from Extras "
                                                    "made before (remove it, or make the Extras again)"))
