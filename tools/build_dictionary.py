"""Regenerate schemas/pds3_dictionary.json from the PDS3 data dictionary.

Usage (from the repository root):

    python tools/build_dictionary.py [PATH/TO/pdsdd.full] [OUTPUT.json]

Defaults: ../shared/corpus/reference/pdsdd.full and schemas/pds3_dictionary.json.

Input: the Planetary Science Data Dictionary dump (`pdsdd.full`, PSDD pdscat1r77): one
`OBJECT = ELEMENT_DEFINITION` per keyword (GENERAL_DATA_TYPE, UNIT_ID,
STANDARD_VALUE_TYPE, MINIMUM/MAXIMUM, MINIMUM/MAXIMUM_LENGTH, STANDARD_VALUE_SET), the
UNIT_LIST, and the object definitions. Mission namespaces (MRO:, MEX:) are not in the
PSDD; they come from the hand-maintained schemas/pds3_namespaces.json and are merged
in under "namespaces". schemas/pds3_dictionary_overrides.json corrects PSDD limits that
PDS-accepted archives exceed (each with its evidence); the PSDD value stays beside the
corrected one as psdd_<field>. Unit spellings that PDS archives use but the 2010 unit list
writes differently (METERS/PIXEL, PIXEL/DEGREE, BYTES ...) are listed in UNIT_ALIASES
below. The output is what `pdsgen.validate` reads for its DICT rules.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from pdsgen.validate.lexer import parse_label  # noqa: E402

DEFAULT_INPUT = REPO.parent / "shared" / "corpus" / "reference" / "pdsdd.full"
DEFAULT_OUTPUT = REPO / "schemas" / "pds3_dictionary.json"
NAMESPACES = REPO / "schemas" / "pds3_namespaces.json"
OVERRIDES = REPO / "schemas" / "pds3_dictionary_overrides.json"

# Spellings of units found in released PDS3 labels (HiRISE, HRSC, LOLA, CRISM ...)
# that are not ids or names in the PSDD unit list; compared case-insensitively.
UNIT_ALIASES = [
    "BYTES", "BYTE", "PIXEL", "PIXELS", "PIX", "DEGREES", "DEGREE", "METERS", "METER",
    "METRES", "KILOMETERS", "KILOMETRES", "METERS/PIXEL", "METRES/PIXEL", "M/PIX", "M/PIXEL",
    "KM/PIXEL", "KM/PIX", "PIXEL/DEGREE", "PIXELS/DEGREE", "PIX/DEG", "PIXEL/DEG",
    "MICROSECONDS", "MILLISECONDS", "NANOMETERS", "MICROMETERS", "DEGC",
    "W*M**-2*SR**-1", "W*M**-2*SR**-1*UM**-1", "W/(M**2*SR*UM)", "DN", "C", "K",
    "DEG/PIXEL", "RAD/PIXEL", "MRAD/PIXEL", "KM/S",
]

_ELEMENT = re.compile(r"^OBJECT = ELEMENT_DEFINITION\s*$(.*?)^END_OBJECT = ELEMENT_DEFINITION", re.M | re.S)
_OBJECT = re.compile(r"^OBJECT = (?:GENERIC|SPECIFIC)_OBJECT_DEFINITION\s*$(.*?)^END_OBJECT", re.M | re.S)
_UNIT = re.compile(r"\('([^']*)','([^']*)'\)")
_UNIT_LIST = re.compile(r"^OBJECT = UNIT_LIST\s*$(.*?)^END_OBJECT = UNIT_LIST", re.M | re.S)


def _number(value) -> float | int | None:
    return value.py if value is not None and value.is_number else None


def element(text: str) -> tuple[str, dict] | None:
    """One ELEMENT_DEFINITION body -> (name, compact definition)."""
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


def build(source: Path) -> dict:
    text = source.read_bytes().decode("latin-1")
    elements = dict(filter(None, (element(m.group(1)) for m in _ELEMENT.finditer(text))))
    units_text = _UNIT_LIST.search(text)
    units = _UNIT.findall(units_text.group(1)) if units_text else []
    objects = sorted({
        (parse_label("PDS_VERSION_ID = PDS3\n" + m.group(1) + "\nEND\n").root.text("NAME") or "").upper()
        for m in _OBJECT.finditer(text)
    } - {""})
    for name, change in json.loads(OVERRIDES.read_text())["elements"].items():
        entry = elements[name]
        for field, value in change.items():
            if field != "reason":
                entry[f"psdd_{field}"] = entry.get(field)
                entry[field] = value
        entry["override_reason"] = change["reason"]
    header = re.search(r"Online Database: (\S+)", text)
    return {
        "source": f"{source.name} ({header.group(1) if header else 'unknown database'})",
        "units": sorted({u for u, _ in units}),
        "unit_names": sorted({n for _, n in units}),
        "unit_aliases": UNIT_ALIASES,
        "objects": objects,
        "elements": dict(sorted(elements.items())),
        "namespaces": json.loads(NAMESPACES.read_text())["namespaces"],
    }


def main(argv: list[str]) -> int:
    source = Path(argv[1]) if len(argv) > 1 else DEFAULT_INPUT
    output = Path(argv[2]) if len(argv) > 2 else DEFAULT_OUTPUT
    data = build(source)
    output.write_text(json.dumps(data, indent=0, sort_keys=False) + "\n")
    print(f"{output}: {len(data['elements'])} keywords, {len(data['units'])} units, "
          f"{sum(len(v) for v in data['namespaces'].values())} namespace keywords")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
