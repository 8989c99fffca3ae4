"""The PDS3 data dictionary pdsgen ships (schemas/pds3_dictionary.json) and its version.

The validator loads the dictionary from here and states its version in every report;
`pdsgen --version` states it too. This module is light on purpose (no validator
imports), so asking for the version does not load the validator.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from ..bounded import load_json
from ..resources import schemas_dir


def dictionary_path() -> Path:
    """The shipped dictionary (built by tools/build_dictionary.py from the PSDD)."""
    return schemas_dir() / "pds3_dictionary.json"


def version_text(data: dict) -> str:
    """"pdscat1r102 (generated 2017-09-25)" from a dictionary dump's header fields."""
    version = data.get("version") or data.get("source", "unknown")
    generated = data.get("generated")
    if generated:
        return f"{version} (generated {_iso_date(generated)})"
    return version


_MONTH_DAYS = (31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31)
_MONTHS = ("JAN", "FEB", "MAR", "APR", "MAY", "JUN", "JUL", "AUG", "SEP", "OCT", "NOV", "DEC")


def _iso_date(stamp: str) -> str:
    """"2017-09-25" from the dump's ctime stamp "Mon Sep 25 14:04:29 2017" (any other text as
    it is). Read by hand: datetime.strptime would import the locale machinery on every run
    that checks a label, a tenth of a small product's own time."""
    parts = stamp.split()
    if len(parts) == 5 and parts[1].upper() in _MONTHS and parts[2].isdigit() and parts[4].isdigit():
        day = int(parts[2])
        if 1 <= day <= _MONTH_DAYS[_MONTHS.index(parts[1].upper())]:
            return f"{int(parts[4]):04d}-{_MONTHS.index(parts[1].upper()) + 1:02d}-{day:02d}"
    return stamp


@cache
def shipped_version() -> str:
    """The version of the shipped dictionary, as the validator's reports state it."""
    return version_text(load_json(dictionary_path()))
