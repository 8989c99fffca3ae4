"""DLV-017/018/019 (the Extras' README.TXT against the delivered labels, archive/extras_check.py)
and DLV-026 (a quick look against its product)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from .jp2 import jp2_header
from .parts import Found, read_pds3

if TYPE_CHECKING:
    from ...label.read import LabelCache

_EXTRAS_RULES = {"stale": "DLV-017", "differs": "DLV-018", "absent": "DLV-019"}


def check_extras(root: Path, found: list[Found], labels: LabelCache | None) -> None:
    """DLV-017/018/019: the Extras' README.TXT against the delivered labels (archive/extras_check.py)."""
    from ...archive.extras_check import extras_problems

    for problem in extras_problems(root, labels):
        found.append(Found(_EXTRAS_RULES[problem.kind], problem.file, problem.message, problem.line))


def check_quick_looks(root: Path, found: list[Found], labels: LabelCache | None) -> None:
    """DLV-026: each quick-look JP2 README.TXT lists is its product at full scale: the size of the
    image its delivered label describes (archive/extras_check finds the product of each entry)."""
    from ...archive.extras_check import product_of, read_entries, readmes

    for readme in readmes(root):
        for entry in read_entries(readme):
            product = product_of(root, readme, entry)
            label = read_pds3(product, labels) if product is not None else None
            image = next(label.find("IMAGE"), None) if label is not None else None
            if product is None or image is None:
                continue
            samples, lines = image.number("LINE_SAMPLES"), image.number("LINES")
            for name, _ in entry.files:
                path = readme.parent / name
                header = jp2_header(path) if name.upper().endswith(".QLOOK.JP2") and path.is_file() else None
                if header is not None and (header[0], header[1]) != (samples, lines):
                    found.append(Found("DLV-026", path, f"{header[0]} samples x {header[1]} lines, but the "
                                                         f"quick look of {product.name} is the product at full "
                                                         f"scale ({samples} samples x {lines} lines): a quick look "
                                                         f"of another version of the product (pdsgen extras "
                                                         f"{product.name} -o {readme.parent.name} --overwrite)"))

