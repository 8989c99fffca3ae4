"""`pdsgen validate --json`: the run as a `CommandResult`, in the one shape of every command's --json.

Apart from report.py, so that a validation without --json loads no command result
(`pdsgen validate`'s start-up budget, tests/test_cli_startup.py).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..results import CommandResult, finding_counts
from .report import Tally


@dataclass
class ValidationRun(CommandResult):
    """`pdsgen validate --json`: the run told in the one shape of every command's --json
    (pdsgen/results.py) - the report file written (if any) as `files`, no warning of the
    command's own, the counts and every finding as facts. The --format json *report* is
    another thing: a CI format of its own (files checked, each with its findings)."""

    tally: Tally
    findings: list[dict[str, Any]] = field(default_factory=list)
    report: str | None = None  # the --output file, when one was written
    warnings: tuple[str, ...] = ()

    @property
    def files(self) -> tuple[Path, ...]:
        return (Path(self.report),) if self.report else ()

    @property
    def summary_lines(self) -> tuple[str, ...]:
        return (self.tally.summary_line(),)

    @property
    def exit_code(self) -> int:
        return self.tally.exit_code

    def details(self) -> dict[str, Any]:
        tally = self.tally
        return {"checked": tally.files, "failed": tally.files_failed,
                "finding_counts": finding_counts(tally.errors, tally.warnings, tally.info),
                "placeholders": tally.placeholders, "fail_on": tally.fail_on, "exit_code": tally.exit_code,
                "verdict": tally.summary_line(), "findings": self.findings}
