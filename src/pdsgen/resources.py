"""Locate the label templates and schema data, installed or in a source checkout.

A wheel carries `templates/` and `schemas/` inside the package (see pyproject's
force-include); an editable install or a plain source tree has them at the top of
the repository, two levels above this file.
"""

from __future__ import annotations

import os
from functools import cache
from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent


@cache
def resource_dir(name: str) -> Path:
    """Return the directory holding the `templates` or `schemas` data."""
    for candidate in (_PACKAGE_DIR / name, _PACKAGE_DIR.parents[1] / name):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"pdsgen data directory {name!r} is missing from the installation")


def templates_dir() -> Path:
    return resource_dir("templates")


def schemas_dir() -> Path:
    return resource_dir("schemas")


def user_cache_dir(name: str) -> Path:
    """pdsgen's cache directory `name` for this user: ~/.cache/pdsgen/NAME, or under
    $XDG_CACHE_HOME. Only a place to keep things that can be made again; not created here."""
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(root) / "pdsgen" / name
