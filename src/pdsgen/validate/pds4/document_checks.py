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
from .label_tree import P, Pds4Hits, is_outside

_PDFA_MARK = b"pdfaid:part"
_READ_BYTES = 1 << 20


def check_pdf_a(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """Every PDF of a Document_File (of a Product_Document) identifies itself as PDF/A."""
    for area in tree.getroot().iter(f"{P}Document_File"):
        name = (area.findtext(f"{P}file_name") or "").strip()
        relative = os.path.join((area.findtext(f"{P}directory_path_name") or "").strip(), name)
        candidate = report.path.parent / relative
        path = candidate if name and not is_outside(report, relative, area) and candidate.is_file() else None
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
    """The data files the PDS4 labels of one run describe (every file_name of the label),
    which label named each first, and whether any named it as observational data (a
    File_Area_Observational or _Supplemental, or any file of a Product_Observational). It
    runs in the run's own process for every label of the run, over what `named_files` read
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
    joins across the run, read where the label is validated (facts.py). The label's text
    is scanned, not parsed again. An unreadable label names none (its own report says why)."""
    try:
        with open(label, "rb") as handle:
            text = handle.read()
    except OSError:
        return []
    directory = os.path.dirname(os.path.abspath(label))
    observational_product = _OBSERVATIONAL_ROOT.search(text) is not None
    areas = [(m.start(), m[1]) for m in _FILE_AREA.finditer(text)]
    named = []
    for block in _FILE_ELEMENT.finditer(text):
        match = _FILE_NAME_ELEMENT.search(block[0])
        if match is None:
            continue
        name = match[1].decode("utf-8", "replace").strip()
        folder = _DIRECTORY_ELEMENT.search(block[0])  # a Document_File's directory_path_name
        relative = os.path.join(folder[1].decode("utf-8", "replace").strip(), name) if folder else name
        area = next((tag for start, tag in reversed(areas) if start < block.start()), b"")
        named.append((relative, os.path.normpath(os.path.join(directory, relative)),
                      observational_product or area in _OBSERVATIONAL_AREAS,
                      text.count(b"\n", 0, block.start() + match.start()) + 1))
    return named


_OBSERVATIONAL_ROOT = re.compile(rb"<(?:[A-Za-z_][\w.-]*:)?Product_Observational[\s>]")
_FILE_AREA = re.compile(rb"<(?:[A-Za-z_][\w.-]*:)?(File_Area_\w+|Document_Edition)[\s>]")
_OBSERVATIONAL_AREAS = (b"File_Area_Observational", b"File_Area_Observational_Supplemental")
_FILE_ELEMENT = re.compile(rb"<((?:[A-Za-z_][\w.-]*:)?(?:File|Document_File))>.*?</\1>", re.DOTALL)
_FILE_NAME_ELEMENT = re.compile(rb"<(?:[A-Za-z_][\w.-]*:)?file_name>([^<]+)</")
_DIRECTORY_ELEMENT = re.compile(rb"<(?:[A-Za-z_][\w.-]*:)?directory_path_name>([^<]+)</")
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
