"""pdsgen: planetary terrain models and orthoimages to PDS3 archive products.

The public API is importable from here, like `rasterio.open`:
`from pdsgen import write_dtm, write_ortho, make_extras, validate_paths` and the
error types. They are loaded on first use, so `import pdsgen` stays cheap and
the modules that read `__version__` never import themselves in a cycle.
"""

from __future__ import annotations

import importlib
from typing import Any

# Single source of the version: pyproject.toml reads it from here (hatch), and
# SOFTWARE_NAME in every label states it.
__version__ = "0.1.0"

_LAZY = {
    "write_dtm": "pdsgen.products.dtm",
    "write_ortho": "pdsgen.products.ortho",
    "make_extras": "pdsgen.extras",
    "validate_paths": "pdsgen.validate",
    "register_mission": "pdsgen.missions",
    "Mission": "pdsgen.missions",
    "PdsgenError": "pdsgen.errors",
    "InputError": "pdsgen.errors",
    "OutputError": "pdsgen.errors",
    "ParamsError": "pdsgen.errors",
}

__all__ = ["__version__", *_LAZY]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'pdsgen' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
