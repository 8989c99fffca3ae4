"""A checksum manifest as a PDS4 product: a Product_Ancillary whose File_Area_Ancillary holds a
Checksum_Manifest (parsing_standard_id "MD5Deep 4.n": one `md5  relative/path` line per file,
what `md5sum -c` and md5deep read).

A manifest cannot list itself, nor the label that gives its own MD5: as NAIF's SPICE bundles do
(naif-pds4-bundler's checksum product, miscellaneous/checksum/checksum_vNNN.tab), the manifest
lists every other file of the bundle, and its label carries the manifest's MD5 and size. The
label belongs in a Miscellaneous collection (collection_type "Miscellaneous", reference
bundle_has_miscellaneous_collection): the PDS4 collection type for bundle-support products that
are neither data, browse nor documents - a Document collection holds Product_Document only.

One interface for every writer of a bundle (pdsgen deliver; migrate's volume bundles):
`manifest_label(manifest_path, lid, vid, title=...) -> XML text`, and `manifest_facts` for a
writer that needs the numbers alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..formats.checksum import file_md5

PARSING_STANDARD = "MD5Deep 4.n"


@dataclass(frozen=True)
class ManifestFacts:
    """What the label states of the manifest file."""

    name: str
    size: int
    md5: str
    records: int
    delimiter: str  # "Line-Feed" or "Carriage-Return Line-Feed", as the file's first line ends


def manifest_facts(manifest_path: Path) -> ManifestFacts:
    """Size, MD5, line count and record delimiter of a manifest file, read in blocks."""
    records = 0
    crlf = None
    with open(manifest_path, "rb") as stream:
        for line in stream:
            records += 1
            if crlf is None and line.endswith(b"\n"):
                crlf = line.endswith(b"\r\n")
    return ManifestFacts(manifest_path.name, manifest_path.stat().st_size, file_md5(manifest_path), records,
                         "Carriage-Return Line-Feed" if crlf else "Line-Feed")


def manifest_label(manifest_path: str | Path, lid: str, vid: str, title: str | None = None) -> str:
    """The Product_Ancillary label (UTF-8 XML text) of the checksum manifest at `manifest_path`,
    with logical identifier `lid` and version `vid`. Write it beside the manifest (its File names
    the manifest by its file name); the manifest must not list this label."""
    from .label import render_pds4  # the templates (and rasterio) load on first use
    from .model import CURRENT_IM

    path = Path(manifest_path)
    facts = manifest_facts(path)
    return render_pds4("checksum_manifest.xml.j2", {
        "product_class": "Product_Ancillary", "lid": lid, "version_id": vid,
        "title": title or f"Checksum manifest {facts.name}: the MD5 of every other file of the bundle",
        "aliases": (), "citation": None, "pds": CURRENT_IM.namespace("pds"), "file": facts,
        "description": (f"One line per file: its MD5, two spaces and its path from the bundle's root "
                        f"({PARSING_STANDARD}, as md5sum writes). It lists every file of the bundle but "
                        f"{facts.name} itself and this label, which gives {facts.name}'s MD5."),
    })
