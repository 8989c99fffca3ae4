"""Validate PDS3 labels, label sets and their data: `pdsgen validate` and its Python API.

    from pdsgen.validate import validate_paths
    report = validate_paths(["out/"], strict=True)  # a ValidationReport
    print(report.summary())

Rules have stable ids (FILE-001, MAP-003 ...) in one table (`rules()`, see registry.py),
grouped in families, each family one module in families/ that registers its rules.

The names below are loaded when first used, so that a part of pdsgen that needs one
piece of the validator (a product writer checking its label against the data
dictionary) does not import all of it; `rules()` loads every built-in family.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from . import families
    from .config import Baseline, RuleSettings
    from .model import Finding
    from .registry import rules
    from .report import FileReport, ValidationReport, render
    from .runner import ValidationJob, discover, iter_reports, validate_file, validate_paths

# public name -> the module (in this package) that defines it
_HOMES = {"Baseline": "config", "RuleSettings": "config", "Finding": "model", "rules": "registry",
          "FileReport": "report", "ValidationReport": "report", "render": "report", "ValidationJob": "runner",
          "discover": "runner", "iter_reports": "runner", "validate_file": "runner", "validate_paths": "runner"}

__all__ = ["families", "Baseline", "Finding", "FileReport", "ValidationReport", "RuleSettings", "ValidationJob",
           "render", "rules", "discover", "iter_reports", "validate_file", "validate_paths"]


def __getattr__(name: str) -> Any:
    if name == "families":
        return importlib.import_module(f"{__name__}.families")
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_HOMES[name]}"), name)
    globals()[name] = value
    return value
