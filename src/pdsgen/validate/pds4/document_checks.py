"""PDS4 checks beyond one table or array: document files, and data files shared by labels.

- A PDF in a document product must be PDF/A (PDS's archiving standard). Full PDF/A
  conformance takes a PDF/A validator (NASA's tool embeds veraPDF); what is checked
  here is the identification every PDF/A file carries, `pdfaid:part` in its XMP metadata
  (which PDF/A forbids compressing), so a plain PDF is caught, a broken PDF/A is not.
- File names use the characters PDS4 allows, and directory paths are relative.
- No two labels of one run may describe the same file of observational data (NASA's
  validator reports it for the run): `DataFileRegister` sees every PDS4 report of a run,
  in the parent process. Other files may be shared, as NASA's validator lets them be: two
  editions of a document (two Product_Document labels) naming the same figures, a browse
  image two products point at.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from lxml import etree

from .. import facts
from ..model import Hit
from .label_tree import P, Pds4Hits, named_file

_PDFA_MARK = b"pdfaid:part"
_READ_BYTES = 1 << 20


def check_pdf_a(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """Every PDF of a Document_File (of a Product_Document) identifies itself as PDF/A."""
    for area in tree.getroot().iter(f"{P}Document_File"):
        name = (area.findtext(f"{P}file_name") or "").strip()
        relative = os.path.join((area.findtext(f"{P}directory_path_name") or "").strip(), name)
        path = named_file(report, relative, area) if name else None
        standard = (area.findtext(f"{P}document_standard_id") or "").strip()
        if path is None or not (standard.startswith("PDF") or name.lower().endswith(".pdf")):
            continue
        if not _is_pdf(path):
            problem = "is not a PDF at all (it does not start with %PDF-)"
        elif not marked_pdf_a(path):
            problem = "is a PDF without PDF/A identification (no pdfaid:part in its XMP metadata)"
        else:
            continue
        element = area.find(f"{P}file_name")
        report.add("PDS4-061", f"{path.name} {problem}: PDS archives documents as PDF/A",
                   element.sourceline if element is not None else area.sourceline, "file_name")


def _is_pdf(path: Path) -> bool:
    with open(path, "rb") as handle:
        return handle.read(5) == b"%PDF-"


def marked_pdf_a(path: Path) -> bool:
    """Whether the file holds `pdfaid:part`, read in overlapping chunks (memory stays flat)."""
    tail = b""
    with open(path, "rb") as handle:
        while block := handle.read(_READ_BYTES):
            if _PDFA_MARK in tail + block:
                return True
            tail = block[-len(_PDFA_MARK):]
    return False


class DataFileRegister:
    """The data files the PDS4 labels of one run describe (every file_name of a File or
    Document_File), which label named each first, and whether any named it as observational
    data (a File_Area_Observational or _Supplemental, or any file of a Product_Observational).
    It runs in the run's own process for every label of the run, over what `named_files` read
    of each (in the workers, when there are workers)."""

    def __init__(self) -> None:
        self.first: dict[str, str] = {}
        self.observational: dict[str, bool] = {}

    def add(self, label: str) -> list[Hit]:
        """PDS4-060: the label's data files another label of the run named (the PDS4
        family's run check; the runner makes them findings of the label)."""
        findings = []
        for relative, data, observational, line in facts.of(named_files, Path(label)):
            first = self.first.setdefault(data, label)
            observational = self.observational[data] = self.observational.get(data, False) or observational
            if first != label and observational:
                findings.append(Hit(f"{relative} is also described by {first}", line, "file_name"))
        return findings


@facts.fact("pds4")
def named_files(label: Path) -> list[tuple[str, str, bool, int]]:
    """(the name as the label writes it, the file's normalised path, whether it is named as
    observational data, the line) of each file a PDS4 label names - what DataFileRegister
    joins across the run, read where the label is validated (facts.py). Read from the label's
    parsed tree, as every other check reads it: a file_name inside an XML comment is no element
    (NASA's github1408 product keeps a commented-out File_Area), one in a CDATA section is text.
    An unreadable label names none (its own report says why: PDS4-001)."""
    root = _parsed_root(label)
    if root is None:
        return []
    directory = os.path.dirname(os.path.abspath(label))
    observational_product = _local(root) == "Product_Observational"
    named = []
    for file in root.iter():
        if _local(file) not in ("File", "Document_File"):
            continue
        name_element = next((child for child in file if _local(child) == "file_name"), None)
        if name_element is None or not (name := (name_element.text or "").strip()):
            continue
        folder = next((child for child in file if _local(child) == "directory_path_name"), None)
        relative = os.path.join((folder.text or "").strip(), name) if folder is not None else name
        area = next((_local(a) for a in file.iterancestors() if _local(a).startswith("File_Area_")
                     or _local(a) == "Document_Edition"), "")
        named.append((relative, os.path.normpath(os.path.join(directory, relative)),
                      observational_product or area in _OBSERVATIONAL_AREAS, name_element.sourceline or 0))
    return named


def _parsed_root(label: str | Path) -> etree._Element | None:
    """The label's root element (entities not resolved, nothing fetched), or None."""
    try:
        return etree.parse(str(label), etree.XMLParser(no_network=True, resolve_entities=False)).getroot()
    except (OSError, etree.XMLSyntaxError):
        return None


def _local(element: etree._Element) -> str:
    """An element's name without its namespace ('' for a comment or processing instruction)."""
    tag = element.tag
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


_OBSERVATIONAL_AREAS = ("File_Area_Observational", "File_Area_Observational_Supplemental")
_FILE_NAME = re.compile(r"[A-Za-z0-9._-][A-Za-z0-9._/-]*\Z")  # a relative path, as genuine labels give


def check_file_names(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """File names a label gives use only the characters PDS4 allows (letters, digits, '-',
    '_', '.'; no spaces), and directory paths are relative to the label (label only)."""
    for name in tree.getroot().iter(f"{P}file_name"):
        text = (name.text or "").strip()
        if text and not _FILE_NAME.match(text):
            bad = "".join(sorted({c for c in text if not _FILE_NAME.match(c)})) or text[0]
            report.add("PDS4-062", f"file_name {text!r} holds characters PDS4 does not allow in file names "
                                   f"({bad!r})", name.sourceline, "file_name")
    for path in tree.getroot().iter(f"{P}directory_path_name"):
        text = (path.text or "").strip()
        if text.startswith(("/", "\\")) or ":" in text:  # '../x/' is relative, and accepted
            report.add("PDS4-062", f"directory_path_name {text!r} is not a path relative to the label",
                       path.sourceline, "directory_path_name")
