"""What the SET rules know of one PDS3 label: a small picklable digest of it.

A worker process takes it from the label (families/set_rules.py `summarise`) and hands it
back with the file's report; the SET rules then compare the digests of one directory (or
of the whole run). It lives here, below the registry and the families, because the
registry types a rule's `set_check` with it and the runner carries it.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class LabelSummary:
    path: str
    product_id: str | None = None
    product_id_line: int | None = None
    sources: list[str] = field(default_factory=list)
    sources_line: int | None = None
    projection: tuple | None = None
    projection_line: int | None = None
    describes_nothing: bool = False
    first_line: int | None = None
    referenced: list[str] = field(default_factory=list)  # upper-case names other files go by
