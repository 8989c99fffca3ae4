"""Numbers out of label keywords, in the units the checks compute in (km, m/pixel), and the
IMAGE objects that hold an image's size (LINES, LINE_SAMPLES)."""

from __future__ import annotations

from ..label.tree import Block

_METRES = ("M", "METERS", "METER", "METRES", "METRE")


def number(block: Block, key: str) -> float | None:
    """A keyword's numeric value as a float, or None if absent or not a number."""
    val = block.value(key)
    if val is None or not val.is_number:
        return None
    return float(val.number)


def kilometres(block: Block, key: str) -> float | None:
    """A length keyword in km (the PDS default unit for radii), converting <M>/<METERS>."""
    val = block.value(key)
    value = number(block, key)
    if value is None or val is None:
        return None
    return value / 1000.0 if (val.unit or "KM").upper() in _METRES else value


def metres_per_pixel(block: Block) -> float | None:
    """MAP_SCALE in metres per pixel (the dictionary's default unit is KM/PIXEL)."""
    val = block.value("MAP_SCALE")
    value = number(block, "MAP_SCALE")
    if value is None or val is None:
        return None
    unit = (val.unit or "KM/PIXEL").upper().replace(" ", "")
    return value * 1000.0 if unit.startswith("KM") else value


def is_image(block: Block) -> bool:
    """An IMAGE object (any *IMAGE) stating its size. Here, in a plain module, so that the rule
    families and the offset fit (map_offsets.py) share it without importing one another."""
    return block.kind == "OBJECT" and block.name.upper().endswith("IMAGE") and (
        block.get("LINES") is not None or block.get("LINE_SAMPLES") is not None
    )
