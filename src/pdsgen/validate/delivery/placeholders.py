"""DLV-006: no [TO BE WRITTEN: ...] placeholder left in a delivery's own texts."""

from __future__ import annotations

from pathlib import Path

from ...archive import layout
from ...bounded import read_text
from ...errors import InputError
from .parts import Found

_TEXT_FILES = (layout.VOLDESC, layout.AAREADME)


def check_placeholders(root: Path, found: list[Found]) -> None:
    from ...archive.scan import bundle_labels

    files = [root / name for name in _TEXT_FILES] + bundle_labels(root)
    files += [root / directory / layout.collection_label_name(c) for c, (_, _, directory) in
              layout.COLLECTIONS.items()]
    for path in files:
        try:  # bounded: a FIFO named VOLDESC.CAT is not waited on, a huge file not held
            text = read_text(path, what="delivery text", encoding="latin-1")
        except InputError:
            continue
        for match in layout.PLACEHOLDER_PATTERN.finditer(text):
            number = text.count("\n", 0, match.start()) + 1
            found.append(Found("DLV-006", path, "text still to be written: " + " ".join(match.group(0).split()),
                                number))

