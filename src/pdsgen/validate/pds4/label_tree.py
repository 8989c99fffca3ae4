"""What the PDS4 checks share: the hits they add (by rule id), and reading label values.

Values are read in the units the checks compute in (metres, metres per pixel,
degrees), whatever unit attribute the label gives.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

from lxml import etree

from ...pds4.model import CART_NS, PDS_NS
from ..model import Hit

P = f"{{{PDS_NS}}}"
C = f"{{{CART_NS}}}"


class Pds4Hits:
    """What the checks of one PDS4 label found, by rule id. A check finds problems of
    several rules at once; the validator's registry gives each rule its severity (the
    PDS4 family in validate/families/pds4_rules.py), as for every other family."""

    def __init__(self, path: Path, tree: Path | None = None) -> None:
        self.path = path
        self.tree = tree  # the trusted tree the label's files must stay in (--root); its directory unless told
        self.by_rule: dict[str, list[Hit]] = {}

    def add(self, rule: str, message: str, line: int | None = None, keyword: str | None = None,
            severity: str | None = None) -> None:
        """A problem of `rule`; `severity` only where this case departs from the rule's own."""
        self.by_rule.setdefault(rule, []).append(Hit(message, line, keyword, severity=severity))


def file_areas(tree: etree._ElementTree) -> Iterator[etree._Element]:
    for area in tree.getroot():
        if isinstance(area.tag, str) and area.tag.startswith(f"{P}File_Area"):
            yield area


# Units a label may state, to metres, metres per pixel, degrees (the PDS4 unit classes we read).
_UNITS = {"m": 1.0, "km": 1000.0, "cm": 0.01, "mm": 0.001, "m/pixel": 1.0, "km/pixel": 1000.0,
          "mm/pixel": 0.001, "deg": 1.0, "rad": 180.0 / math.pi, "mrad": 0.18 / math.pi}


def number(element: etree._Element | None, path: str) -> float | None:
    """A numeric element's value in metres / metres per pixel / degrees (per its unit attribute);
    None when it is not a finite number (1e400 is infinity to float(), which no count or offset
    can be: the XML Schema check reports the value)."""
    found = element.find(path) if element is not None else None
    if found is None or found.text is None:
        return None
    try:
        value = float(found.text)
    except ValueError:
        return None
    return value * _UNITS.get(found.get("unit", ""), 1.0) if math.isfinite(value) else None


def data_path(report: Pds4Hits, area: etree._Element, report_missing: bool = True) -> Path | None:
    file = area.find(f"{P}File")
    name = file.findtext(f"{P}file_name") if file is not None else None
    if not name:
        return None
    path = named_file(report, name, file, report_missing)
    if path is None and report_missing and not is_outside(report, name, file, tell=False):
        report.add("PDS4-010", f"data file {name} not found beside the label", file.sourceline, "file_name")
    return path


def named_file(report: Pds4Hits, name: str, element: etree._Element, tell: bool = True) -> Path | None:
    """The regular file NAME (from the label, relative to its directory) is, or None: outside
    the tree (PDS4-064 when `tell`), missing, not a regular file (a FIFO is never opened), or a
    name the file system refuses (a segment over 255 bytes, a NUL: not an OSError escaping a
    check). The one way a PDS4 label's file name becomes a path the checks open."""
    if is_outside(report, name, element, tell):
        return None
    path = report.path.parent / name
    try:
        return path if path.is_file() else None
    except (OSError, ValueError):
        return None


def is_outside(report: Pds4Hits, name: str, element: etree._Element, tell: bool = True) -> bool:
    """Whether a file the label names lies outside the label's directory (../x, /x, a link
    leading out): such a file is never read, and (when `tell`) PDS4-064 says so."""
    from ...label.beside import outside_tree  # the one containment rule, for PDS3 and PDS4 alike

    if outside_tree(report.path.parent, name, report.tree) is None:
        return False
    if tell:
        where = f"the tree {report.tree}" if report.tree is not None else f"the label's directory {report.path.parent}"
        report.add("PDS4-064", f"file_name {name} lies outside {where}; it is not read (--root DIR widens the tree "
                               "to a bundle or volume holding it)", element.sourceline, "file_name")
    return True
