"""Validate PDS3 labels, label sets and their data: `pdsgen validate` and its Python API.

    from pdsgen.validate import validate_paths
    report = validate_paths(["out/"], strict=True)
    print(report.summary())

Rules have stable ids (FILE-001, MAP-003 ...) in one table (`rules.rules()`), grouped in
families, each family in its own module.
"""

from __future__ import annotations

from .config import Baseline, Settings
from .model import Finding
from .registry import rules
from .report import FileReport, Report, render
from .runner import discover, iter_reports, validate_file, validate_paths

__all__ = ["Baseline", "Finding", "FileReport", "Report", "Settings", "render", "rules", "discover",
           "iter_reports", "validate_file", "validate_paths"]
