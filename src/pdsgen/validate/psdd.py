"""Read a Planetary Science Data Dictionary dump (`pdsdd.full` format) into plain dicts.

Used by tools/build_dictionary.py to make schemas/pds3_dictionary.json, and at run time
for extra dictionaries a user names (`pdsgen validate --dictionary FILE`), e.g. a local
data dictionary of a mission or a test dictionary.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

from ..bounded import read_bytes
from ..label.parser import parse_label
from ..label.tree import Value

# A dictionary dump is larger than a label (the PSDD's is about 10 MB): its own cap.
DICTIONARY_BYTES = 64 * 1024 * 1024
_ELEMENT = ("OBJECT = ELEMENT_DEFINITION", "END_OBJECT = ELEMENT_DEFINITION")
_OBJECT = (("OBJECT = GENERIC_OBJECT_DEFINITION", "OBJECT = SPECIFIC_OBJECT_DEFINITION"), "END_OBJECT")
_UNIT = re.compile(r"\('([^']*)','([^']*)'\)")
_UNIT_LIST = ("OBJECT = UNIT_LIST", "END_OBJECT = UNIT_LIST")


def bodies(lines: list[str], opening: str | tuple[str, ...], closing: str) -> Iterator[str]:
    """The text between each line that is OPENING (trailing white space aside) and the next
    line starting with CLOSING, in one pass over LINES: an object that never ends is skipped
    without reading on to the end of the file from it (the dump's objects are not nested;
    an opening inside an open object belongs to its body, as before)."""
    openings = (opening,) if isinstance(opening, str) else opening
    start: int | None = None
    for number, line in enumerate(lines):
        if start is None:
            if line.rstrip() in openings:
                start = number + 1
        elif line.startswith(closing):
            yield "\n".join(lines[start:number])
            start = None


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


def _generated(line: str) -> str | None:
    """The date of a "Generated: DATE */" header line, else None."""
    _, marker, rest = line.partition("Generated: ")
    stamp, star, after = rest.partition("*")
    return stamp.strip() or None if marker and star and after.startswith("/") else None


def read_psdd(path: Path) -> dict:
    """Elements, units and object names of one dictionary dump (a regular file, size-capped)."""
    return parse_psdd(Path(path), read_bytes(path, DICTIONARY_BYTES, "dictionary").decode("latin-1"))


def parse_psdd(path: Path, text: str) -> dict:
    """Elements, units and object names of one dictionary dump's TEXT, in time linear in it."""
    lines = text.splitlines()
    elements = dict(filter(None, (element(body) for body in bodies(lines, *_ELEMENT))))
    units_text = next(bodies(lines, *_UNIT_LIST), None)
    units = _UNIT.findall(units_text) if units_text else []
    objects = sorted({
        (parse_label("PDS_VERSION_ID = PDS3\n" + body + "\nEND\n").root.text("NAME") or "").upper()
        for body in bodies(lines, *_OBJECT)
    } - {""})
    header = re.search(r"Online Database: (\S+)", text)
    generated = next((found for found in map(_generated, lines) if found), None)
    return {
        "source": f"{Path(path).name} ({header.group(1) if header else 'unknown database'})",
        "version": header.group(1) if header else None,
        "generated": generated,
        "units": sorted({u for u, _ in units}),
        "unit_names": sorted({n for _, n in units}),
        "objects": objects,
        "elements": dict(sorted(elements.items())),
    }
