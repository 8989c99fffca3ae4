"""The Extras against the delivered products, on the delivery's model: DLV-017/018/019 (README.TXT
against the labels, archive/extras_check.py), DLV-026 (a quick look against its product),
DLV-027 (a browse or thumbnail against its product), DLV-028 (a preview README.TXT does not list)."""

from __future__ import annotations

from pathlib import Path

from .jp2 import jp2_header
from .jpeg import jpeg_size
from .model import DeliveryModel, ExtrasEntry
from .parts import Found

_EXTRAS_RULES = {"stale": "DLV-017", "differs": "DLV-018", "absent": "DLV-019"}


def check_extras(model: DeliveryModel, found: list[Found]) -> None:
    """DLV-017/018/019: each README.TXT entry against the record of the label it names."""
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
    return [extras.readme.parent / name for name, _ in extras.entry.files]


def check_previews(model: DeliveryModel, found: list[Found]) -> None:
    """DLV-027: each browse and thumbnail JPEG an entry lists is the size the Extras make of the
    delivered product (formats/preview_size, the Extras' own arithmetic) at the width the file
    has: a browse of a product since remade at another size is not. The annotated browses
    (margins around the browse) are left to their browse."""
    from ...formats.preview_size import browse_size, thumbnail_size

    for extras in model.extras:
        record = model.pds3(extras.product) if extras.product is not None else None
        if record is None or record.size is None:
            continue
        previews = [(path, kind, jpeg_size(path)) for path, kind in _previews(extras)]
        browse = next((browse_size(*record.size, size[0]) for _, kind, size in previews
                       if kind == "browse" and size is not None), None)
        for path, kind, size in previews:
            if size is None:
                continue
            if kind == "browse":
                made = browse_size(*record.size, size[0])
            elif browse is not None:  # a thumbnail is made of the browse
                made = thumbnail_size(*browse, size[0])
            else:
                continue
            if size != made:
                found.append(Found("DLV-027", path, f"{size[0]} x {size[1]} pixels, but the {kind} the Extras make "
                                                    f"{size[0]} pixels wide of {record.path.name} "
                                                    f"({record.size[0]} samples x {record.size[1]} lines) is "
                                                    f"{made[0]} x {made[1]}: a {kind} of another version of the "
                                                    f"product (pdsgen extras {record.path.name} -o "
                                                    f"{extras.readme.parent.name} --overwrite)"))


def _previews(extras: ExtrasEntry) -> list[tuple[Path, str]]:
    """The browse and thumbnail files an entry lists (by the kind its description states)."""
    listed = []
    for name, _ in extras.entry.files:
        stated = extras.entry.preview_size(name)
        path = extras.readme.parent / name
        if stated is not None and path.is_file():
            listed.append((path, stated[0]))
    return listed


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
