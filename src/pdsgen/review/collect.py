"""What the page shows, gathered: products (label facts, outline, files, previews, index row,
findings), other files' findings, and the summary.

Two sources feed it: a directory reviewed whole (`pdsgen review`, `pdsgen deliver`:
the delivery's own grouping of files into products, archive/scan.py) and the file
reports of a validation run (`pdsgen validate --format html`: each label a product).
"""

from __future__ import annotations

import os
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import quote

from ..archive import layout
from ..archive.scan import DataProduct, bundle_labels, is_preview, pointed_files
from ..extras.renderings import DTM_RENDERINGS, ORTHO_RENDERING
from ..label.read import LabelCache, LabelFile, read_pds3_label
from ..validate.model import SEVERITIES, Finding
from ..validate.report import PLACEHOLDER_RULES, FileReport
from .footprint import Outline, OutlineBatch
from .index_table import IndexTable
from .labels import label_view, read_facts

# The delivery checks the summary reports, by the validator's DLV rule ids.
DELIVERY_CHECKS = (
    ("index", ("DLV-001", "DLV-002", "DLV-003", "DLV-004", "DLV-005")),
    ("inventories", ("DLV-010", "DLV-011", "DLV-012", "DLV-013", "DLV-014", "DLV-015")),
    ("manifest", ("DLV-020", "DLV-021")),
)
_RENDERINGS = (*DTM_RENDERINGS, ORTHO_RENDERING)


@dataclass
class PreviewLink:
    thumb: str  # page-relative link
    browse: str | None  # the larger image, when there is one
    what: str


@dataclass
class ProductEntry:
    product_id: str
    anchor: str
    label: str  # shown path (relative to the reviewed directory)
    kind: str = "product"
    profile: str = "generic"
    target: str | None = None
    rows: list[tuple[str, str]] = field(default_factory=list)
    outline: Outline | None = None
    no_outline: str = ""
    files: list[tuple[str, str, int]] = field(default_factory=list)  # (shown path, link, bytes)
    previews: list[PreviewLink] = field(default_factory=list)
    index_row: str = ""  # the product's INDEX.TAB row, as the table holds it
    findings: list[Finding] = field(default_factory=list)
    inline: bool = True  # thumbnails in the HTML (else built by the script as the entry is scrolled near)
    page: str = ""  # the page holding the entry, when not the first (REVIEW-2.html ...)

    @property
    def link(self) -> str:
        """The entry's address from the first page (the map's links)."""
        return f"{self.page}#{self.anchor}"

    def count(self, severity: str) -> int:
        return sum(1 for f in self.findings if f.severity == severity)

    @property
    def worst(self) -> str:
        return next((s for s in SEVERITIES if self.count(s)), "clean")


@dataclass
class OtherFile:
    path: str
    findings: list[Finding]


@dataclass
class Review:
    """Everything the page shows."""

    title: str
    root: Path
    products: list[ProductEntry] = field(default_factory=list)
    others: list[OtherFile] = field(default_factory=list)
    files: int = 0
    total_bytes: int = 0
    checks: list[tuple[str, str]] = field(default_factory=list)  # (check, "pass" / "fail: n finding(s)")
    verdict: str = ""
    source: str = ""  # what the page says it shows (a directory, or the labels checked)
    labels_only: bool = False  # the checks did not open the data files
    index_header: str = ""  # INDEX.TAB's column names, each above its field

    def counts(self) -> dict[str, int]:
        found = Counter(f.severity for p in self.products for f in p.findings)
        found.update(f.severity for o in self.others for f in o.findings)
        return {s: found.get(s, 0) for s in SEVERITIES}

    def by_kind_and_profile(self) -> list[tuple[str, str, int]]:
        counted = Counter((p.kind, p.profile) for p in self.products)
        return [(kind, profile, n) for (kind, profile), n in sorted(counted.items())]

    def rules(self) -> list[str]:
        return sorted({f.rule for p in self.products for f in p.findings}
                      | {f.rule for o in self.others for f in o.findings})

    def placeholders(self) -> int:
        """Warnings that mark text or keywords still to be filled in (`is_placeholder`): while any
        remain the delivery is not ready, whatever the errors say."""
        findings = [f for p in self.products for f in p.findings] + [f for o in self.others for f in o.findings]
        return sum(1 for f in findings if is_placeholder(f))

    @property
    def state(self) -> str:
        """The summary's state: "failed" (errors), "incomplete" (placeholders left), or "ok"."""
        if self.counts()["error"]:
            return "failed"
        return "incomplete" if self.placeholders() else "ok"


def is_placeholder(finding: Finding) -> bool:
    """A warning of something still to be written: a rule the validator counts as a placeholder
    (validate/report.PLACEHOLDER_RULES: a `[TO BE WRITTEN: ...]` text, an identification keyword
    left UNK), or a warning whose message names one."""
    if finding.severity != "warning":
        return False
    return finding.rule in PLACEHOLDER_RULES or any(word.lower() in finding.message.lower()
                                                     for word in PLACEHOLDER_WORDS)


PLACEHOLDER_WORDS = ("[TO BE WRITTEN", "placeholder")


def anchor_of(product_id: str, taken: set[str]) -> str:
    base = "p-" + "".join(c if c.isalnum() or c in "-_." else "_" for c in product_id)
    anchor, n = base, 1
    while anchor in taken:
        n += 1
        anchor = f"{base}-{n}"
    taken.add(anchor)
    return anchor


class Linker:
    """Links from the page to files (relative to the page's directory, URL-quoted), and the
    paths shown (relative to the reviewed directory)."""

    def __init__(self, root: Path, page_dir: Path) -> None:
        self.root = os.path.abspath(root)
        self.page_dir = os.path.abspath(page_dir)

    def shown(self, path: Path) -> str:
        relative = os.path.relpath(os.path.abspath(path), self.root)
        return str(path) if relative.startswith("..") else relative.replace(os.sep, "/")

    def link(self, path: Path) -> str:
        # the name's own bytes, percent-encoded: a Latin-1 name links to its file, never a traceback
        return quote(os.fsencode(os.path.relpath(os.path.abspath(path), self.page_dir).replace(os.sep, "/")))


def previews_by_product(paths: Iterable[Path]) -> dict[str, list[Path]]:
    """Extras images by the product id that starts their name (the delivery's rule)."""
    found: dict[str, list[Path]] = {}
    for path in paths:
        if is_preview(path.name):
            found.setdefault(path.name.split(".", 1)[0].upper(), []).append(path)
    return found


def _previews(images: list[Path], linker: Linker) -> list[PreviewLink]:
    """Each rendering's thumbnail with its browse image (larger, on demand)."""
    by_name = {p.name.lower(): p for p in images}
    shown = []
    for path in sorted(images):
        lower = path.name.lower()
        for rendering in _RENDERINGS:
            if lower.endswith(f".{rendering.thumb}.jpg"):
                browse = by_name.get(lower[: -len(f"{rendering.thumb}.jpg")] + f"{rendering.browse}.jpg")
                shown.append(PreviewLink(linker.link(path), linker.link(browse) if browse else None,
                                     rendering.description))
    return shown


def product_entry(product_id: str, label: Path | None, files: list[Path], linker: Linker,
                  taken: set[str], outlines: OutlineBatch, labels: LabelCache | None = None) -> ProductEntry:
    """One product's entry from its PDS3 label (facts; its outline queued in `outlines`) and
    files (sizes)."""
    entry = ProductEntry(product_id, anchor_of(product_id, taken), linker.shown(label or files[0]))
    found = read_pds3_label(label, labels) if label is not None else None
    if found is not None and label is not None:
        _fill_from_label(entry, found, outlines)
    elif label is None:
        entry.no_outline = "a PDS4 label only (facts and outline are read from PDS3 labels)"
    for path in files:
        try:
            size = path.stat().st_size
        except OSError:
            size = -1
        entry.files.append((linker.shown(path), linker.link(path), size))
    return entry


def _fill_from_label(entry: ProductEntry, label: LabelFile, outlines: OutlineBatch) -> None:
    facts = read_facts(label)
    entry.product_id = facts.product_id if entry.product_id == label.path.stem else entry.product_id
    entry.kind, entry.profile, entry.target = facts.kind, facts.profile, facts.target
    entry.rows = facts.rows

    def done(outline: Outline | None, why_not: str) -> None:
        entry.outline, entry.no_outline = outline, why_not

    outlines.add(label_view(label.root), facts.lines, facts.samples, done)


def attach_findings(entries: list[ProductEntry], reports: Iterable[FileReport], linker: Linker) -> list[OtherFile]:
    """Each finding to the product one of whose files it names; the rest by file."""
    owner: dict[str, ProductEntry] = {}
    for entry in entries:
        for shown, _, _ in entry.files:
            owner[shown] = entry
    others: dict[str, list[Finding]] = {}
    for report in reports:
        for finding in report.findings:
            shown = linker.shown(Path(finding.file))
            finding.file = shown
            if shown in owner:
                owner[shown].findings.append(finding)
            else:
                others.setdefault(shown, []).append(finding)
    return [OtherFile(path, findings) for path, findings in sorted(others.items())]


def delivery_checks(root: Path, findings: Iterable[Finding]) -> list[tuple[str, str]]:
    """Whether the index, the inventories and the manifest check, for those the delivery has."""
    present = {
        "index": (root / layout.INDEX_DIR / layout.INDEX_LABEL).is_file(),
        "inventories": bool(bundle_labels(root)),  # a Product_Bundle root, whatever its name (bundle.xml)
        "manifest": (root / layout.MANIFEST).is_file(),
    }
    failed = Counter(f.rule for f in findings if f.severity == "error")
    result = []
    for name, rule_ids in DELIVERY_CHECKS:
        if not present[name]:
            continue
        errors = sum(failed[r] for r in rule_ids)
        result.append((name, "pass" if not errors else f"fail: {errors} error(s)"))
    return result


def add_index_rows(entries: list[ProductEntry], root: Path, labels: LabelCache | None = None) -> str:
    """Each product's row of INDEX/INDEX.TAB, matched by label path or PRODUCT_ID; returns the
    columns' names placed over a row (empty without an index)."""
    table = IndexTable.read(root / layout.INDEX_DIR / layout.INDEX_LABEL, labels)
    if table is None:
        return ""
    for entry in entries:
        row = table.row_for(entry.label, entry.product_id)
        if row is not None:
            entry.index_row = row
    return table.header


def review_directory(root: Path, products: list[DataProduct], previews: list[Path],
                     reports: list[FileReport], page_dir: Path, title: str, labels: LabelCache | None = None) -> Review:
    """The review of a directory of products (a delivery or not); `labels`: the run's label cache."""
    linker = Linker(root, page_dir)
    taken: set[str] = set()
    by_id = previews_by_product(previews)
    entries = []
    outlines = OutlineBatch()
    for product in products:
        entry = product_entry(product.product_id, product.pds3_label, product.files, linker, taken, outlines, labels)
        entry.previews = _previews(by_id.get(product.product_id.upper(), []), linker)
        entries.append(entry)
    outlines.run()
    header = add_index_rows(entries, root, labels)
    review = Review(title, root, entries, index_header=header)
    review.others = attach_findings(entries, reports, linker)
    review.checks = delivery_checks(root, (f for r in reports for f in r.findings))
    return review


def review_reports(reports: list[FileReport], page_dir: Path, title: str) -> Review:
    """The review of a validation run: each PDS3 label with a PRODUCT_ID is a product."""
    paths = [Path(r.path) for r in reports]
    root = Path(os.path.commonpath([str(p.resolve().parent) for p in paths])) if paths else page_dir
    linker = Linker(root, page_dir)
    taken: set[str] = set()
    entries = []
    outlines = OutlineBatch()
    extras: dict[Path, dict[str, list[Path]]] = {}  # each directory's previews, listed once
    for path in paths:
        label = read_pds3_label(path) if path.is_file() else None
        product_id = label.first("PRODUCT_ID") if label is not None else None
        if label is None or product_id is None:
            continue
        files = [path] + [path.parent / n for n in pointed_files(label.root, path.parent) if path.parent / n != path]
        entry = product_entry(product_id, path, files, linker, taken, outlines)
        entry.previews = _previews(_nearby_previews(path, product_id, extras), linker)
        entries.append(entry)
    outlines.run()
    review = Review(title, root, entries, source=f"{len(reports)} file(s) under {root}")
    review.others = attach_findings(entries, reports, linker)
    return review


def _nearby_previews(label: Path, product_id: str, extras: dict[Path, dict[str, list[Path]]]) -> list[Path]:
    """Extras beside a label, in an extras/ (or EXTRAS/) directory beside it or one level up.

    `extras` keeps each directory's previews by product id, so a directory of N labels is
    listed once, not once per label (N x N names)."""
    found = []
    for directory in (label.parent, label.parent / "extras", label.parent / layout.EXTRAS_DIR,
                      label.parent.parent / layout.EXTRAS_DIR):
        if directory not in extras:
            extras[directory] = previews_by_product(directory.iterdir()) if directory.is_dir() else {}
        found += extras[directory].get(product_id.upper(), [])
    return found
