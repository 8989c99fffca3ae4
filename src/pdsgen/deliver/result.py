"""What `make_delivery` made, as every command's result says it (`CommandResult`).

Importing it loads no builder: `pdsgen deliver` prints it, `deliver/build.py` fills it in.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..archive.layout import MANIFEST, MANIFEST_LABEL, REVIEW_PAGE, is_review_page
from ..dialect import Dialect
from ..results import CommandResult


@dataclass
class Delivery(CommandResult):
    """What `make_delivery` made: where, how many of each, and what it left out."""

    path: Path
    dialect: Dialect
    products: int = 0
    previews: int = 0
    documents: int = 0
    file_count: int = 0  # files MD5SUMS.TXT covers, itself included
    changed: list[str] = field(default_factory=list)  # PDS4 LIDVIDs new or re-versioned by this run
    # Source files no label names and no Extras rule claims: not delivered, or (in place) left
    # where they are; each is reported, never placed silently.
    skipped: list[Path] = field(default_factory=list)
    # (label, the identifier given) of each PDS3 label stating no PRODUCT_ID, which the delivery
    # names after its file: a delivery never invents an identifier without saying so.
    named_by_file: list[tuple[Path, str]] = field(default_factory=list)
    in_place: bool = False
    volume_id: str | None = None
    bundle_lid: str | None = None
    bundle_version: str | None = None
    # [TO BE WRITTEN: ...] placeholders left in the delivery's own text (VOLDESC.CAT, AAREADME.TXT,
    # bundle and collection labels): what a delivery text file still has to give.
    placeholders: int = 0

    @property
    def files(self) -> tuple[Path, ...]:
        """Every file of the delivery: those MD5SUMS.TXT lists, MD5SUMS.TXT, the review page(s).
        Read from the manifest (a delivery of many products lists many files: asked only by --json)."""
        manifest = self.path / MANIFEST
        listed = [self.path / line.split("  ", 1)[1]
                  for line in manifest.read_text(encoding="utf-8").splitlines() if "  " in line]
        pages = sorted((path for path in self.path.iterdir() if is_review_page(path.name)),
                       key=lambda path: (len(path.name), path.name))  # REVIEW.html, REVIEW-2.html ... REVIEW-10.html
        label = [self.path / MANIFEST_LABEL] if (self.path / MANIFEST_LABEL).is_file() else []
        return (*listed, manifest, *label, *pages)

    @property
    def warnings(self) -> tuple[str, ...]:
        """Each source file left out, and each product named after its file, in one line: a delivery
        places nothing and invents no identifier silently."""
        where = "left where it is, outside the layout" if self.in_place else "not delivered"
        named = [f"{label}: no PRODUCT_ID in the label; the delivery names the product {product_id} after its file "
                 "name (its index row and identifiers); state PRODUCT_ID in the label to choose it"
                 for label, product_id in self.named_by_file]
        return (*named, *(f"{path}: no label names it and no Extras rule claims it; {where}" for path in self.skipped))

    @property
    def summary_lines(self) -> tuple[str, ...]:
        lines = [f"DELIVERY {self.path}: {self.products} data product(s), {self.previews} preview(s), "
                 f"{self.documents} document(s), {self.file_count} file(s) in {self.path / MANIFEST}"]
        # a --volume-id or --bundle-lid given for a form the delivery does not make names nothing made
        if self.volume_id and self.dialect.pds3:
            lines.append(f"PDS3     volume {self.volume_id}: INDEX/INDEX.TAB + INDEX.LBL, VOLDESC.CAT, AAREADME.TXT")
        if self.bundle_lid and self.dialect.pds4:
            lines.append(f"PDS4     bundle {self.bundle_lid}::{self.bundle_version}, "
                         f"{len(self.changed)} product(s) new or with a new version")
        if self.placeholders:
            lines.append(f"TEXT     {self.placeholders} [TO BE WRITTEN: ...] placeholder(s) left: give the delivery's "
                         "text in a TOML file's [delivery] table and run pdsgen deliver again with it")
        lines.append(f"CHECK    pdsgen validate {self.path}")
        lines.append(f"REVIEW   {self.path / REVIEW_PAGE} (open it in a browser; not in the manifest)")
        return tuple(lines)

    def details(self) -> dict[str, Any]:
        return {"path": str(self.path), "dialect": str(self.dialect), "products": self.products,
                "previews": self.previews, "documents": self.documents, "file_count": self.file_count,
                "volume_id": self.volume_id if self.dialect.pds3 else None,
                "bundle_lid": self.bundle_lid if self.dialect.pds4 else None, "bundle_version": self.bundle_version,
                "changed": self.changed, "skipped": [str(p) for p in self.skipped],
                "placeholders": self.placeholders}


__all__ = ["Delivery"]
