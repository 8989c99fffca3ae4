"""The PDS4 side of a delivery: LIDs and versions, inventories, and the labels pdsgen writes
around the products (Product_Bundle, Product_Collection, Product_Browse, Product_Document).

LIDs derive from the bundle's: urn:nasa:pds:<bundle>:<collection>:<product>. A product
keeps its version while its files are unchanged; a changed product, a collection whose
inventory changed and a bundle whose collections changed get the next major version.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..encode import EncodeError, xml_finalize
from ..label.render import named_refusal, template_environment
from ..pds4.model import CURRENT_IM
from ..resources import templates_dir

if TYPE_CHECKING:
    import jinja2

_LID = re.compile(r"(<logical_identifier>)\s*[^<]*?\s*(</logical_identifier>)")
_VERSION = re.compile(r"(<version_id>)\s*[^<]*?\s*(</version_id>)")
_AREA_END = "</Identification_Area>"

# Encoded_Image encoding_standard_id by file name ending
ENCODINGS = ((".qlook.jp2", "JP2"), (".jpg", "JPEG"), (".jpeg", "JPEG"))


def encoding_of(name: str) -> str:
    lower = name.lower()
    return next(code for end, code in ENCODINGS if lower.endswith(end))


def next_version(version: str | None) -> str:
    """1.0 for a new product, else the next major version (2.0 after 1.0 or 1.3)."""
    if not version:
        return "1.0"
    major = version.split(".", 1)[0]
    return f"{int(major) + 1}.0" if major.isdigit() else "1.0"


def set_identification(text: str, lid: str, version: str) -> str:
    """A product label with its Identification_Area's logical_identifier and version_id replaced
    (the rest of the label byte for byte)."""
    end = text.find(_AREA_END)
    if end < 0:
        return text
    head = _LID.sub(lambda m: f"{m.group(1)}{lid}{m.group(2)}", text[:end], count=1)
    head = _VERSION.sub(lambda m: f"{m.group(1)}{version}{m.group(2)}", head, count=1)
    return head + text[end:]


def identification_free(text: str) -> str:
    """A label with its LID and version blanked: what tells whether its content changed."""
    return set_identification(text, "", "")


@cache
def _environment() -> jinja2.Environment:
    import jinja2

    env = template_environment().overlay(loader=jinja2.FileSystemLoader(str(templates_dir() / "deliver")),
                                         autoescape=True, finalize=xml_finalize)
    return env


def render(template: str, context: Mapping[str, Any]) -> str:
    try:
        return _environment().get_template(template).render(im=CURRENT_IM, pds=CURRENT_IM.namespace("pds"), **context)
    except EncodeError as exc:
        raise named_refusal(exc, context) from None


@dataclass(frozen=True)
class FileFacts:
    name: str
    size: int
    md5: str


def read_inventory(path: Path) -> dict[str, str]:
    """LID -> version of the members a previous run's inventory lists (empty when there is none)."""
    members: dict[str, str] = {}
    try:
        text = path.read_text(encoding="ascii", errors="replace")
    except OSError:
        return members
    for line in text.splitlines():
        status, _, lidvid = line.partition(",")
        lid, sep, version = lidvid.strip().partition("::")
        if sep:
            members[lid] = version
    return members


def read_version(path: Path) -> str | None:
    """The version_id of a label a previous run wrote (None when there is none)."""
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    match = _VERSION.search(text[: max(text.find(_AREA_END), 0)])
    return re.sub(r"<[^>]+>", "", match.group(0)).strip() if match else None


def inventory_text(lidvids: list[str]) -> str:
    return "".join(f"P,{lidvid}\r\n" for lidvid in sorted(lidvids))
