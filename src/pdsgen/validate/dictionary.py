"""The keyword dictionary (schemas/pds3_dictionary.json), loaded once per process.

Built by tools/build_dictionary.py from the PDS3 data dictionary (PSDD) plus the
mission namespaces; see that script for what each entry holds.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from ..errors import PdsgenError
from ..label.grammar import PLACEHOLDERS as GRAMMAR_PLACEHOLDERS
from ..resources import schemas_dir
from .psdd import read_psdd

PLACEHOLDERS = GRAMMAR_PLACEHOLDERS


@dataclass(frozen=True)
class Dictionary:
    elements: dict[str, dict]
    namespaces: dict[str, dict[str, dict]]
    units: frozenset[str]  # upper-cased ids, names and aliases

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
    run would look as if the dictionary had been applied. A NUL in the first bytes marks
    a binary file, refused before the whole of it is read as text."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(_SNIFF_BYTES)
        more = None if b"\0" in head else read_psdd(Path(path))
    except OSError as exc:
        raise PdsgenError(path, f"cannot read the dictionary: {exc.strerror or exc}") from None
    if more is None or not (more["elements"] or more["units"]):
        raise PdsgenError(path, "not a PSDD data dictionary (no ELEMENT_DEFINITION or UNIT_LIST object)")
    return more


@cache
def load(extra: tuple[str, ...] = ()) -> Dictionary:
    """The project dictionary, with the elements and units of `extra` PSDD-format files
    (later files win) merged over it. Raises PdsgenError for an extra file that is not one."""
    data = json.loads((schemas_dir() / "pds3_dictionary.json").read_text())
    elements = dict(data["elements"])
    units = {u.upper() for u in data["units"]}
    units |= {n.upper() for n in data["unit_names"]}
    units |= {a.upper() for a in data["unit_aliases"]}
    for path in extra:
        more = read_extra(path)
        elements.update(more["elements"])
        units |= {u.upper() for u in more["units"]} | {n.upper() for n in more["unit_names"]}
    return Dictionary(elements, data["namespaces"], frozenset(units))
