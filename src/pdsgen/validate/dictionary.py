"""The keyword dictionary (schemas/pds3_dictionary.json), loaded once per process.

Built by tools/build_dictionary.py from the PDS3 data dictionary (PSDD) plus the
mission namespaces; see that script for what each entry holds.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from ..bounded import load_json, read_bytes
from ..errors import PdsgenError
from ..label.data_dictionary import dictionary_path, version_text
from ..label.grammar import PLACEHOLDERS as GRAMMAR_PLACEHOLDERS
from ..missions.hrsc import NOT_APPLICABLE as HRSC_NOT_APPLICABLE
from .psdd import DICTIONARY_BYTES, parse_psdd

PLACEHOLDERS = GRAMMAR_PLACEHOLDERS
# Numbers missions write where a value does not apply or is not known: the 32-bit integer
# minimum, -9.99e+31 (VICAR/MIPL), HRSC's -1e+32 (DLR). Like "N/A" they skip range checks.
NUMERIC_PLACEHOLDERS = frozenset({-2147483648, -9.99e31, HRSC_NOT_APPLICABLE})


@dataclass(frozen=True)
class Dictionary:
    elements: dict[str, dict]
    namespaces: dict[str, dict[str, dict]]
    units: frozenset[str]  # upper-cased ids, names and aliases
    version: str = ""  # "pdscat1r102 (generated 2017-09-25)", and any extra dictionaries

    def lookup(self, keyword: str) -> dict | None:
        """Definition of a keyword (NAMESPACE:NAME looks in the mission namespace)."""
        name = keyword.upper()
        if ":" in name:
            namespace, _, base = name.partition(":")
            return self.namespaces.get(namespace, {}).get(base)
        return self.elements.get(name)

    def knows_unit(self, unit: str) -> bool:
        return unit.strip().upper() in self.units


_SNIFF_BYTES = 64 * 1024


def read_extra(path: str | os.PathLike[str]) -> dict:
    """One user-named dictionary, refused (PdsgenError) unless it is a PSDD dump.

    A wrong file (an image, an empty file, a label) would otherwise add nothing and the
    run would look as if the dictionary had been applied. It is read by the bounded reader (a
    regular file, at most DICTIONARY_BYTES); a NUL in the first bytes marks a binary file,
    refused before it is parsed."""
    data = read_bytes(path, DICTIONARY_BYTES, "dictionary")
    more = None if b"\0" in data[:_SNIFF_BYTES] else parse_psdd(Path(path), data.decode("latin-1"))
    if more is None or not (more["elements"] or more["units"]):
        raise PdsgenError(path, "not a PSDD data dictionary (no ELEMENT_DEFINITION or UNIT_LIST object)")
    return more


@cache
def load(extra: tuple[str, ...] = ()) -> Dictionary:
    """The project dictionary, with the elements and units of `extra` PSDD-format files
    (later files win) merged over it. Raises PdsgenError for an extra file that is not one."""
    data = load_json(dictionary_path())
    elements = dict(data["elements"])
    units = {u.upper() for u in data["units"]}
    units |= {n.upper() for n in data["unit_names"]}
    units |= {a.upper() for a in data["unit_aliases"]}
    names = [version_text(data)]
    for path in extra:
        more = read_extra(path)
        elements.update(more["elements"])
        units |= {u.upper() for u in more["units"]} | {n.upper() for n in more["unit_names"]}
        names.append(f"{Path(path).name} ({more.get('version') or 'unknown version'})")
    return Dictionary(elements, data["namespaces"], frozenset(units), " + ".join(names))


def version(extra: tuple[str, ...] = ()) -> str:
    """The data dictionary a run checks against, for reports and `--version`."""
    return load(extra).version
