"""What a reviewer checks in a PDS3 label, read with the label reader (pdsgen.label).

The label is the reader's (`label.read.LabelFile`, read up to END by
`label.read.read_pds3_label`); the functions that need a label as a mapping
(the Extras' label georeferencing and kind decision) get a read-only view of the
same tree, so no second reader or grammar is involved.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..label.mapping import BlockView, numbers_as_quantities
from ..label.read import LabelFile
from ..label.tree import Block, Value
from ..missions import LabelFacts, detect_mission

# Label keywords shown for each product, in this order: (keyword, what the page calls it).
MAP_KEYWORDS = (
    ("MAP_PROJECTION_TYPE", "projection"),
    ("MAP_SCALE", "scale"),
    ("MAP_RESOLUTION", "resolution"),
    ("MINIMUM_LATITUDE", "minimum latitude"),
    ("MAXIMUM_LATITUDE", "maximum latitude"),
    ("WESTERNMOST_LONGITUDE", "westernmost longitude"),
    ("EASTERNMOST_LONGITUDE", "easternmost longitude"),
)
# Decimals a reviewer needs of a map keyword, where labels write a dozen: a ten-thousandth of a
# degree (a few metres on Mars), a tenth of a pixel per degree. Others are shown as written.
SHOWN_DECIMALS = {"MINIMUM_LATITUDE": 4, "MAXIMUM_LATITUDE": 4, "WESTERNMOST_LONGITUDE": 4,
                  "EASTERNMOST_LONGITUDE": 4, "MAP_RESOLUTION": 1}


def label_view(block: Block) -> Mapping[str, Any]:
    """A block as the mapping the Extras' label georeferencing and kind decision read: every
    number a LabelQuantity (a float, with its unit or None), text as str, a sequence a list."""
    return BlockView(block, numbers_as_quantities())


@dataclass
class LabelFactsShown:
    """The facts of one label the page shows, as text, and what the map needs."""

    product_id: str
    rows: list[tuple[str, str]] = field(default_factory=list)  # (what, value as written)
    projection: str | None = None
    target: str | None = None
    profile: str = "generic"
    kind: str = "product"
    lines: int | None = None
    samples: int | None = None


def _written(value: Value | None, decimals: int | None = None) -> str | None:
    """A value as the label writes it (with its unit), a number to `decimals` when given."""
    if value is None:
        return None
    text = value.raw if value.items is None and value.kind != "string" else str(value.text)
    if decimals is not None and value.items is None and value.is_number:
        text = f"{value.number:.{decimals}f}"
    return f"{text} <{value.unit}>" if value.unit else text


def read_facts(label: LabelFile) -> LabelFactsShown:
    """The facts a reviewer checks: id, size, projection, scale, bounds, extremes, creation time,
    data set; the profile (mission) as pdsgen's mission detection names it; DTM or image."""
    root, path, label_value = label.root, label.path, label.first
    facts = LabelFactsShown(label_value("PRODUCT_ID") or path.stem)
    image = label.image()
    if image is not None:
        lines, samples = image.number("LINES"), image.number("LINE_SAMPLES")
        facts.lines = int(lines) if isinstance(lines, int) else None
        facts.samples = int(samples) if isinstance(samples, int) else None
        if facts.lines is not None and facts.samples is not None:
            bands = image.number("BANDS")
            facts.rows.append(("lines x samples", f"{facts.lines} x {facts.samples}"
                               + (f" x {int(bands)} bands" if isinstance(bands, int) and bands > 1 else "")))
    projection = label.projection()
    if projection is not None:
        for keyword, what in MAP_KEYWORDS:
            written = _written(projection.value(keyword), SHOWN_DECIMALS.get(keyword))
            if written is not None:
                facts.rows.append((what, written))
        facts.projection = projection.text("MAP_PROJECTION_TYPE")
    if image is not None:
        for low, high in (("VALID_MINIMUM", "VALID_MAXIMUM"), ("MINIMUM", "MAXIMUM")):
            if image.value(low) is not None or image.value(high) is not None:
                facts.rows.append(("minimum / maximum",
                                   f"{_written(image.value(low)) or '-'} / {_written(image.value(high)) or '-'}"))
                break
    for keyword, what in (("PRODUCT_CREATION_TIME", "created"), ("DATA_SET_ID", "data set"),
                          ("TARGET_NAME", "target")):
        text = label_value(keyword)
        if text is not None:
            facts.rows.append((what, text))
    facts.target = (label_value("TARGET_NAME") or "").upper() or None
    facts.profile = detect_mission(LabelFacts(
        instrument_id=(label_value("INSTRUMENT_ID") or "").upper(),
        data_set_id=(label_value("DATA_SET_ID") or "").upper(),
        group_names=frozenset(b.name.upper() for b in root.walk() if b is not root),
        file_name=path.name)) or "generic"
    facts.kind = _kind(root, image, path)
    return facts


def _kind(root: Block, image: Block | None, path: Path) -> str:
    """DTM or orthoimage, decided as the Extras decide it (from the label alone)."""
    from ..formats.kind import DTM, decide_kind

    try:
        decision = decide_kind(label_view(root), label_view(image) if image is not None else {}, {}, path,
                               lambda: None)
    except Exception:  # a label the decision cannot place is shown as a plain product
        return "product"
    return "DTM" if decision.kind == DTM else "orthoimage"
