"""The review page of a delivery (or any directory of products): what it holds, seen at a
glance in a browser - summary, footprints on a map of the body, each product's previews,
label facts, index row, files and findings - as one self-contained, offline HTML file.

`write_review` is the API behind `pdsgen review` (and what `pdsgen deliver` calls);
`HtmlWriter` is `pdsgen validate --format html`. Nothing else imports this package.
"""

from __future__ import annotations

import os
import re
from collections import Counter
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ..archive.layout import REVIEW_PAGE
from ..archive.scan import scan, walk
from ..errors import InputError, OutputError
from ..label.read import LabelCache
from ..progress import advance
from ..results import CommandResult, finding_counts
from ..storage.staging import staged_files
from ..validate.report import FileReport
from ..validate.runner import iter_reports
from .collect import review_directory
from .page import INLINE_THUMBNAILS, PRODUCTS_PER_PAGE, HtmlWriter, delivery_title, render_pages

__all__ = ["HtmlWriter", "ReviewResult", "write_review"]


@dataclass
class ReviewResult(CommandResult):
    """The page(s) written and what they show; `errors`, `warning_findings` and `info` count the
    findings by severity (the page lists them; the command tells no warning of its own)."""

    path: Path
    products: int
    outlines: int
    errors: int
    warning_findings: int
    info: int
    pages: list[Path] = field(default_factory=list)  # every page written, the first (`path`) first
    warnings: tuple[str, ...] = ()

    @property
    def files(self) -> tuple[Path, ...]:
        return tuple(self.pages)

    @property
    def summary_lines(self) -> tuple[str, ...]:
        lines = [f"REVIEW   {self.path}: {self.products} product(s), {self.outlines} footprint(s); "
                 f"{self.errors} error(s), {self.warning_findings} warning(s), {self.info} info"]
        if len(self.pages) > 1:
            lines.append(f"PAGES    {len(self.pages)}: {self.pages[0].name}, then {self.pages[1].name} ... "
                         f"{self.pages[-1].name} beside it")
        return tuple(lines)

    def details(self) -> dict[str, Any]:
        return {"path": str(self.path), "pages": [str(p) for p in self.pages], "products": self.products,
                "footprints": self.outlines,
                "finding_counts": finding_counts(self.errors, self.warning_findings, self.info)}


def write_review(directory: str | os.PathLike[str], page: str | os.PathLike[str] | None = None,
                 labels_only: bool = False, jobs: int = 1, shown_as: str | None = None,
                 inline_thumbnails: int = INLINE_THUMBNAILS, per_page: int | None = PRODUCTS_PER_PAGE,
                 labels: LabelCache | None = None) -> ReviewResult:
    """Check the products of `directory` (as `pdsgen validate` does, the delivery's index,
    inventories and manifest too) and write the review page (default DIRECTORY/REVIEW.html).

    labels_only: the checks read the labels and the delivery's own files, not the data (what
    `pdsgen deliver` does: its products were checked when they were made; `pdsgen review` opens
    the data). inline_thumbnails: how many products' thumbnails are in the HTML itself (the rest
    are built as their entries are scrolled near). per_page: products per page (more are reviewed in
    pages beside the first: REVIEW-2.html ...; None: one page). shown_as: the directory's name on the page (a
    delivery is reviewed before it is moved into place). The page is written under a temporary
    name and renamed when complete; pages of an earlier, larger review are removed.
    labels: the run's label cache (`pdsgen deliver` hands its own, so that the scan, the checks
    and the page read each label once with the delivery's own steps)."""
    root = Path(directory)
    if not root.is_dir():
        raise InputError(root, "not a directory of products")
    target = Path(page) if page is not None else root / REVIEW_PAGE
    if target.is_dir():
        raise OutputError(target, "is a directory; give the page's file name")
    if not target.parent.is_dir():
        raise OutputError(target, "its directory does not exist")
    labels = labels if labels is not None else LabelCache()  # the scan, the checks and the page share it
    found = scan(root, labels=labels, strict=False)  # a missing or outside file: shown by its finding
    if not found.products:
        raise InputError(root, "holds no data product (no PDS3 or PDS4 product label)")
    shown_findings = _ShownFindings()
    reports = [shown_findings.trim(report)
               for report in iter_reports([root], labels_only=labels_only, jobs=jobs, labels=labels,
                                          progress=_checked)]
    shown = shown_as or str(root)
    title = delivery_title(root, shown if shown_as else str(root.resolve()), labels)
    review = review_directory(root, found.products, found.previews, reports, target.parent, title, labels)
    review.source, review.labels_only = shown, labels_only
    for path in walk(root, strict=False):
        if not _is_page_of(path, target):
            review.files += 1
            review.total_bytes += path.stat().st_size
    counts = review.counts()
    for severity, hidden in shown_findings.hidden.items():
        counts[severity] = counts.get(severity, 0) + hidden
    review.verdict = (f"{len(reports)} file(s) checked: {counts['error']} error(s), {counts['warning']} "
                      f"warning(s), {counts['info']} info - {'FAILED' if counts['error'] else 'OK'}")
    pages = render_pages(review, target.name, inline_thumbnails, per_page)
    written = _write_pages(target.parent, pages)
    return ReviewResult(target, len(review.products), sum(p.outline is not None for p in review.products),
                        counts["error"], counts["warning"], counts["info"], written)


def _checked(done: int, total: int) -> None:
    """The count of files checked, drawn on a terminal by `pdsgen review` (pdsgen.progress: nothing
    for a library caller or under -q, --json or a pipe)."""
    advance(done, total, "file(s) checked")


# A label can hold any number of statements and so of findings (500,000 keywords no dictionary
# has); the page shows a file's first findings and says how many more there are - pdsgen
# validate lists them all - so that a page's memory and size stay bounded per label.
MAX_FINDINGS_SHOWN = 1000


@dataclass
class _ShownFindings:
    """Trims each file's findings to MAX_FINDINGS_SHOWN, counting those left out by severity
    (the verdict still counts every finding)."""

    hidden: Counter[str] = field(default_factory=Counter)

    def trim(self, report: FileReport) -> FileReport:
        if len(report.findings) <= MAX_FINDINGS_SHOWN:
            return report
        last, rest = report.findings[MAX_FINDINGS_SHOWN], report.findings[MAX_FINDINGS_SHOWN + 1:]
        self.hidden.update(f.severity for f in rest)
        note = replace(last, message=f"{last.message} (and {len(rest)} more finding(s) of this file, "
                                     "not shown here: pdsgen validate lists them all)")
        return FileReport(report.path, [*report.findings[:MAX_FINDINGS_SHOWN], note])


def _is_page_of(path: Path, target: Path) -> bool:
    """Whether `path` is one of the review's pages (target, or target-2 ... beside it)."""
    same_place = path.parent.resolve() == target.parent.resolve()
    return same_place and _page_pattern(target.name).fullmatch(path.name) is not None


def _page_pattern(first: str) -> re.Pattern[str]:
    stem, dot, suffix = first.rpartition(".")
    if not dot:
        stem, suffix = first, ""
    return re.compile(re.escape(stem) + r"(?:-[1-9][0-9]*)?" + re.escape(dot + suffix))


def _write_pages(directory: Path, pages: list[tuple[str, str]]) -> list[Path]:
    """Every page under a temporary name, then each renamed; later pages of an earlier review
    that this one no longer has are removed (their links would lead to old products)."""
    try:
        with staged_files() as stage:
            for name, text in pages:
                stage(directory / name, directory / f".{name}.partial").write_text(text, encoding="utf-8")
    except OSError as exc:
        raise OutputError(directory / pages[0][0], f"cannot write the page ({exc.strerror or exc})") from None
    written = [directory / name for name, _ in pages]
    pattern = _page_pattern(pages[0][0])
    for stale in directory.iterdir():
        if pattern.fullmatch(stale.name) and stale not in written and stale.is_file():
            stale.unlink()
    return written
