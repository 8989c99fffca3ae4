"""The PDS3 data dictionary pdsgen ships (schemas/pds3_dictionary.json) and its version.

The validator loads the dictionary from here and states its version in every report;
`pdsgen --version` states it too. This module is light on purpose (no validator
imports), so asking for the version does not load the validator.
"""

from __future__ import annotations

import json
from datetime import datetime
from functools import cache
from pathlib import Path

from ..resources import schemas_dir


def dictionary_path() -> Path:
    """The shipped dictionary (built by tools/build_dictionary.py from the PSDD)."""
    return schemas_dir() / "pds3_dictionary.json"


def version_text(data: dict) -> str:
    """"pdscat1r102 (generated 2017-09-25)" from a dictionary dump's header fields."""
    version = data.get("version") or data.get("source", "unknown")
    generated = data.get("generated")
    if generated:
        try:
            generated = datetime.strptime(generated, "%a %b %d %H:%M:%S %Y").date().isoformat()
        except ValueError:
            pass
        return f"{version} (generated {generated})"
    return version


@cache
def shipped_version() -> str:
    """The version of the shipped dictionary, as the validator's reports state it."""
    return version_text(json.loads(dictionary_path().read_text()))
