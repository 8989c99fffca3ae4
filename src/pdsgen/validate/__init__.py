"""Validate PDS3 labels, label sets and their data: `pdsgen validate` and its Python API.

    from pdsgen.validate import validate_paths
    report = validate_paths(["out/"], strict=True)
    print(report.summary())

Rules have stable ids (FILE-001, MAP-003 ...) in one table (`rules()`, see registry.py),
grouped in families, each family one module in families/ that registers its rules.
"""

from __future__ import annotations

from . import families  # importing the built-in families registers their rules
from .config import Baseline, Settings
from .model import Finding
from .registry import rules
from .report import FileReport, Report, render
from .runner import discover, iter_reports, validate_file, validate_paths

__all__ = ["families", "Baseline", "Finding", "FileReport", "Report", "Settings", "render", "rules", "discover",
           "iter_reports", "validate_file", "validate_paths"]
