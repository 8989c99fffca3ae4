"""What a validator rule reports: the severities, the finding and a check's hit.

The label tree the rules read is the label reader's (`pdsgen.label.tree`).
"""

from __future__ import annotations

from dataclasses import dataclass

SEVERITIES = ("error", "warning", "info")


@dataclass(slots=True)
class Finding:
    """One reported problem: everything a person or a CI system needs to act on it."""

    rule: str
    severity: str
    file: str
    message: str
    line: int | None = None
    keyword: str | None = None

    def as_dict(self) -> dict:
        return {
            "rule": self.rule,
            "severity": self.severity,
            "file": self.file,
            "line": self.line,
            "keyword": self.keyword,
            "message": self.message,
        }


@dataclass(slots=True)
class Hit:
    """What a check function yields; the runner adds rule id, severity and file."""

    message: str
    line: int | None = None
    keyword: str | None = None
    file: str | None = None  # set when the problem is in another file than the label
    severity: str | None = None  # when the rule's severity depends on the case (see the rule's note)
