"""Read a Planetary Science Data Dictionary dump (`pdsdd.full` format) into plain dicts.

Used by tools/build_dictionary.py to make schemas/pds3_dictionary.json, and at run time
for extra dictionaries a user names (`pdsgen validate --dictionary FILE`), e.g. a local
data dictionary of a mission or a test dictionary.
"""

from __future__ import annotations

import re
from pathlib import Path

from ..label.parser import parse_label
from ..label.tree import Value

_ELEMENT = re.compile(r"^OBJECT = ELEMENT_DEFINITION\s*$(.*?)^END_OBJECT = ELEMENT_DEFINITION", re.M | re.S)
_OBJECT = re.compile(r"^OBJECT = (?:GENERIC|SPECIFIC)_OBJECT_DEFINITION\s*$(.*?)^END_OBJECT", re.M | re.S)
_UNIT = re.compile(r"\('([^']*)','([^']*)'\)")
_UNIT_LIST = re.compile(r"^OBJECT = UNIT_LIST\s*$(.*?)^END_OBJECT = UNIT_LIST", re.M | re.S)


def _number(value: Value | None) -> float | int | None:
    return value.number if value is not None and value.is_number else None


def element(text: str) -> tuple[str, dict] | None:
    """One ELEMENT_DEFINITION body -> (NAME, compact definition)."""
    block = parse_label("PDS_VERSION_ID = PDS3\n" + text + "\nEND\n").root
    name = block.text("NAME")
    if not name:
        return None
    entry: dict = {"type": block.text("GENERAL_DATA_TYPE") or "CONTEXTDEPENDENT"}
    unit = block.text("UNIT_ID")
    if unit and unit.upper() not in ("NONE", "N/A"):
        entry["unit"] = unit
    entry["values_type"] = block.text("STANDARD_VALUE_TYPE") or "NONE"
    for key, out in (("MINIMUM", "min"), ("MAXIMUM", "max"),
                     ("MINIMUM_LENGTH", "min_length"), ("MAXIMUM_LENGTH", "max_length")):
        number = _number(block.value(key))
        if number is not None:
            entry[out] = number
    values = block.value("STANDARD_VALUE_SET")
    if values is not None:
        entry["values"] = sorted({" ".join(str(v.py).split()) for v in values.scalars()})
    return name.upper(), entry


def read_psdd(path: Path) -> dict:
    """Elements, units and object names of one dictionary dump."""
    text = Path(path).read_bytes().decode("latin-1")
    elements = dict(filter(None, (element(m.group(1)) for m in _ELEMENT.finditer(text))))
    units_text = _UNIT_LIST.search(text)
    units = _UNIT.findall(units_text.group(1)) if units_text else []
    objects = sorted({
        (parse_label("PDS_VERSION_ID = PDS3\n" + m.group(1) + "\nEND\n").root.text("NAME") or "").upper()
        for m in _OBJECT.finditer(text)
    } - {""})
    header = re.search(r"Online Database: (\S+)", text)
    generated = re.search(r"Generated: ([^*\r\n]+?)\s*\*/", text)
    return {
        "source": f"{Path(path).name} ({header.group(1) if header else 'unknown database'})",
        "version": header.group(1) if header else None,
        "generated": generated.group(1) if generated else None,
        "units": sorted({u for u, _ in units}),
        "unit_names": sorted({n for _, n in units}),
        "objects": objects,
        "elements": dict(sorted(elements.items())),
    }
