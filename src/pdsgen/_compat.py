"""Standard-library modules that arrived after the oldest Python pdsgen supports.

`tomllib` is in the standard library from Python 3.11; on 3.10 the same parser
is the `tomli` package (a dependency only there). Import TOML support from here.
"""

from __future__ import annotations

import sys

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised by the Python 3.10 install test
    import tomli as tomllib

__all__ = ["tomllib"]
