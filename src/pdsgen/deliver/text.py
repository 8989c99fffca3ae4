"""The words of a delivery only a person can write: its title, description, authors, README
text and keywords, from a delivery text file (`[delivery]` table of a TOML file) and from the
delivery being brought up to date.

Why both: a re-run of `pdsgen deliver` rebuilds every file of the delivery, so text a user
typed into AAREADME.TXT, VOLDESC.CAT or the bundle label would be lost with the old files.
The rule: what the text file gives wins; any field it does not give is read back from the
previous delivery's files where it is not a [TO BE WRITTEN: ...] placeholder; what neither
holds stays a placeholder (and `pdsgen validate` reports it).
"""

from __future__ import annotations

import os
import re
import textwrap
from dataclasses import dataclass, fields, replace
from pathlib import Path

from ..archive import layout
from ..archive.scan import bundle_label
from ..errors import InputError

# Keys of the [delivery] table: the first five are what every delivery's text needs; the rest
# fill the PDS3 volume's own keywords (VOLDESC.CAT) where their defaults do not fit.
TEXT_KEYS = {
    "title": "the volume's and bundle's title (VOLUME_NAME, the bundle's title)",
    "description": "what the products are and what they are for (VOLDESC.CAT DESCRIPTION, the bundle's "
                   "description and citation)",
    "authors": 'the people to cite, as a list of "Last, F." strings (PDS4 List_Author, AAREADME.TXT)',
    "readme": "AAREADME.TXT's own paragraphs: what the volume holds and why",
    "keywords": "optional list of keywords (PDS4 Citation_Information keyword)",
    "contact": "who answers questions about the delivery [default: the authors]",
    "address": "how to reach the contact (VOLDESC.CAT ADDRESS_TEXT) [default: N/A]",
    "institution": "the producing institution [default: the products' PRODUCER_INSTITUTION_NAME]",
    "facility": "the producing facility (VOLDESC.CAT FACILITY_NAME) [default: N/A]",
    "volume_series_name": "PDS3 VOLUME_SERIES_NAME [default: the title]",
    "volume_set_name": "PDS3 VOLUME_SET_NAME [default: the title; a one-volume set]",
    "volume_set_id": "PDS3 VOLUME_SET_ID [default: the VOLUME_ID; a one-volume set]",
}
_LISTS = ("authors", "keywords")
TABLE = "delivery"


@dataclass(frozen=True)
class DeliveryText:
    """Every field None when not known (then the file keeps its placeholder)."""

    title: str | None = None
    description: str | None = None
    authors: tuple[str, ...] | None = None
    readme: str | None = None
    keywords: tuple[str, ...] | None = None
    contact: str | None = None
    address: str | None = None
    institution: str | None = None
    facility: str | None = None
    volume_series_name: str | None = None
    volume_set_name: str | None = None
    volume_set_id: str | None = None

    def over(self, older: DeliveryText) -> DeliveryText:
        """This text, with each field it lacks taken from `older`."""
        return replace(older, **{f.name: getattr(self, f.name) for f in fields(self)
                                 if getattr(self, f.name) is not None})

    def contact_text(self) -> str | None:
        """Who to ask: the contact given, else the authors."""
        return self.contact or ("; ".join(self.authors) if self.authors else None)


def load_text(path: str | os.PathLike[str]) -> DeliveryText:
    """The [delivery] table of a TOML file; InputError naming the file and the key for anything
    it cannot take (an unknown key, a wrong kind of value, text a PDS3 label cannot hold)."""
    from ..bounded import load_toml

    path = Path(path)
    data = load_toml(path, what="delivery text file")
    for key in data:
        if key != TABLE:
            raise InputError(path, f"unknown key {key!r}: the delivery text is the [{TABLE}] table")
    table = data.get(TABLE)
    if not isinstance(table, dict) or not table:
        raise InputError(path, f"has no [{TABLE}] table (keys: {', '.join(TEXT_KEYS)})")
    values: dict[str, object] = {}
    for key, value in table.items():
        if key not in TEXT_KEYS:
            raise InputError(path, f"unknown key {key!r} in [{TABLE}]; known keys: {', '.join(TEXT_KEYS)}")
        values[key] = _checked(path, key, value)
    return DeliveryText(**values)  # type: ignore[arg-type]


def _checked(path: Path, key: str, value: object) -> str | tuple[str, ...]:
    if key in _LISTS:
        items = value if isinstance(value, list) else None
        if not items or not all(isinstance(item, str) and item.strip() for item in items):
            raise InputError(path, f"[{TABLE}] {key} must be a list of strings, e.g. {key} = [\"Last, F.\"]")
        if key == "authors" and not all("," in item.strip(", ") for item in items):
            raise InputError(path, f"[{TABLE}] authors: each is \"Last, F.\" (family name, comma, given names)")
        return tuple(_plain(path, key, item) for item in items)
    if not isinstance(value, str) or not value.strip():
        raise InputError(path, f"[{TABLE}] {key} must be a (non-empty) string")
    return _plain(path, key, value) if key != "readme" else _plain(path, key, value, keep_lines=True)


def _plain(path: Path, key: str, text: str, keep_lines: bool = False) -> str:
    """Text a PDS3 label and an ASCII file can hold: 7-bit, no double quote, no control
    character (label.values' PVL rule, refused naming the key), no placeholder."""
    from ..encode import check_pvl_string

    check_pvl_string(text, f"[{TABLE}] {key}", path)
    if layout.PLACEHOLDER_PATTERN.search(text):
        raise InputError(path, f"[{TABLE}] {key} still holds a [TO BE WRITTEN: ...] placeholder")
    return text.strip() if keep_lines else " ".join(text.split())


# --- the previous delivery's text ---------------------------------------------------------------

def _written(value: str | None) -> str | None:
    """A value a person wrote: not empty, not a placeholder, not pdsgen's "UNK"/"N/A"."""
    if value is None:
        return None
    text = " ".join(str(value).split())
    if not text or layout.PLACEHOLDER_PATTERN.search(text) or text.upper() in ("UNK", "N/A", "NULL"):
        return None
    return text


def previous_text(root: Path, volume_id: str | None) -> DeliveryText:
    """What a person wrote into the delivery at `root` (its VOLDESC.CAT, AAREADME.TXT and bundle
    label), each field only where it is not a placeholder."""
    found = DeliveryText()
    for reader, source in ((_from_bundle, root / "bundle_*.xml"), (_from_aareadme, root / layout.AAREADME),
                           (_from_voldesc, root / layout.VOLDESC)):
        found = _carried(reader(root, volume_id), source).over(found)
    return _without_defaults(found)


def _carried(text: DeliveryText, source: Path) -> DeliveryText:
    """`text` read back from a previous delivery's file, each field checked as a new delivery
    text's are: a character reference in an old bundle title (`&#34;`) must not become a
    quote that ends a VOLDESC.CAT string and opens a statement of its own."""
    from ..encode import check_pvl_string

    for item in fields(text):
        value = getattr(text, item.name)
        for one in (value if isinstance(value, tuple) else (value,)):
            if one is not None:
                check_pvl_string(one, item.name, source)
    return text


def _without_defaults(text: DeliveryText) -> DeliveryText:
    """Values pdsgen derived from others (the contact from the authors, the set's name from the
    title ...) are not kept as given: a later change of the authors or title carries over."""
    derived = {"contact": text.contact == ("; ".join(text.authors) if text.authors else None),
               "volume_series_name": text.volume_series_name == text.title,
               "volume_set_name": text.volume_set_name == text.title}
    return replace(text, institution=None, **{name: None for name, same in derived.items() if same})


def _from_voldesc(root: Path, volume_id: str | None) -> DeliveryText:
    from ..label.read import read_pds3_label

    path = root / layout.VOLDESC
    label = read_pds3_label(path) if path.is_file() else None
    if label is None:
        return DeliveryText()

    def value(keyword: str) -> str | None:
        return _written(label.first(keyword))

    title = value("VOLUME_NAME")
    set_id = value("VOLUME_SET_ID")
    return DeliveryText(
        title=title, description=_written(own_description(label.first("DESCRIPTION") or "")),
        address=value("ADDRESS_TEXT"), facility=value("FACILITY_NAME"),  # the institution: the products'
        contact=value("FULL_NAME"),
        volume_series_name=value("VOLUME_SERIES_NAME"), volume_set_name=value("VOLUME_SET_NAME"),
        volume_set_id=set_id if set_id != volume_id else None)


def own_description(description: str) -> str:
    """VOLDESC.CAT's DESCRIPTION without the sentence pdsgen writes first (the counts)."""
    text = " ".join(description.split())
    marker = f"of the data products in {layout.INDEX_DIR}/."
    return text.split(marker, 1)[1].strip() if marker in text else text


_AAREADME_OWN = re.compile(r"\r?\n\r?\n(.*?)\r?\n\r?\nData sets:", re.S)
AUTHORS_PREFIX = "Authors: "  # the line of AAREADME.TXT naming the authors


def _from_aareadme(root: Path, volume_id: str | None) -> DeliveryText:
    try:
        text = (root / layout.AAREADME).read_text(encoding="ascii", errors="replace")
    except OSError:
        return DeliveryText()
    text = text.replace("\r\n", "\n")
    body = text[text.find("\nVolume "):] if "\nVolume " in text else text  # the text after the attached label
    own = _AAREADME_OWN.search(body)
    readme = own.group(1) if own else None
    authors = None
    if readme is not None:
        paragraphs = readme.split("\n\n")
        if paragraphs and paragraphs[-1].startswith(AUTHORS_PREFIX):
            authors = tuple(a.strip() for a in " ".join(paragraphs.pop().split())[len(AUTHORS_PREFIX):].split(";")
                            if a.strip())
        readme = "\n\n".join(" ".join(p.split()) for p in paragraphs if p.strip())
    return DeliveryText(readme=_written_paragraphs(readme), authors=authors or None)


def _written_paragraphs(text: str | None) -> str | None:
    return text if text and _written(text) is not None else None


def _from_bundle(root: Path, volume_id: str | None) -> DeliveryText:
    label = bundle_label(root)  # by its root element, whatever its name
    if label is None:
        return DeliveryText()
    try:
        text = label.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return DeliveryText()
    import html

    def element(name: str, within: str = text) -> str | None:
        match = re.search(rf"<{name}>(.*?)</{name}>", within, re.S)
        return _written(html.unescape(match.group(1))) if match else None

    bundle_part = re.search(r"<Bundle>(.*?)</Bundle>", text, re.S)
    title = element("title")
    authors = tuple(html.unescape(a).strip() for a in re.findall(r"<display_full_name>(.*?)</display_full_name>",
                                                                   text, re.S))
    keywords = tuple(html.unescape(k).strip() for k in re.findall(r"<keyword>(.*?)</keyword>", text, re.S))
    description = element("description", bundle_part.group(1)) if bundle_part else None
    return DeliveryText(
        title=title if title and not title.startswith("Bundle ") else None,
        description=description if description and not description.endswith("made by pdsgen.") else None,
        authors=authors or None,
        keywords=keywords or None)


# --- writing ------------------------------------------------------------------------------------

def paragraphs(text: str, width: int = 78) -> list[str]:
    """`text`'s paragraphs (blank-line separated) wrapped to `width`, a blank line between them."""
    lines: list[str] = []
    for paragraph in re.split(r"\n\s*\n", text.strip()):
        if lines:
            lines.append("")
        lines += textwrap.wrap(" ".join(paragraph.split()), width) or [""]
    return lines
