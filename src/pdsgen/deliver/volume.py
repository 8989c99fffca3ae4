"""PDS3 volume skeletons: VOLDESC.CAT and AAREADME.TXT with the facts pdsgen knows.

What only a person can say (the volume's name, series and set, who to contact, what the
data are for) is a named placeholder (layout.PLACEHOLDER); `pdsgen validate` reports any
left in, so a volume cannot go out with them unnoticed.
"""

from __future__ import annotations

import datetime as dt
import textwrap
from dataclasses import dataclass, field

from ..archive import layout
from ..encode import ascii_text, check_pvl_string
from ..label.values import format_string, format_value
from .text import AUTHORS_PREFIX, DeliveryText, paragraphs


def _todo(what: str) -> str:
    return layout.PLACEHOLDER.format(what=what)


@dataclass(frozen=True)
class VolumeFacts:
    volume_id: str
    version: int  # VOLUME_VERSION_ID's number: 1, then one more per re-delivery that changed it
    publication_date: str  # YYYY-MM-DD
    data_set_ids: tuple[str, ...]
    institution: str | None
    products: int
    previews: int
    text: DeliveryText = field(default_factory=DeliveryText)  # what a person wrote (deliver/text.py)


def _string(keyword: str, value: str, indent: str = "  ") -> list[str]:
    """`KEYWORD = "value"`, the value wrapped under its start so lines stay within 78 characters;
    its `=` in column 24, as the file's other statements have it."""
    head = f"{indent}{keyword:<{22 - len(indent)}} = "
    width = 78 - len(head) - 2
    parts = textwrap.wrap(check_pvl_string(value, keyword, layout.VOLDESC), width) or [""]
    lines = [f'{head}"{parts[0]}']
    lines += [" " * (len(head) + 1) + part for part in parts[1:]]
    lines[-1] += '"'
    return lines


def voldesc_text(facts: VolumeFacts) -> str:
    text = facts.text
    data_sets = [format_string(d, "DATA_SET_ID", layout.VOLDESC) for d in facts.data_set_ids] \
        or [format_string(layout.NOT_APPLICABLE)]
    data_set = data_sets[0] if len(data_sets) == 1 else "(" + ",\r\n                         ".join(data_sets) + ")"
    institution = text.institution or _known(facts.institution)
    lines = ["PDS_VERSION_ID         = PDS3", "RECORD_TYPE            = STREAM", "",
             "OBJECT                 = VOLUME"]
    lines += _string("VOLUME_SERIES_NAME", text.volume_series_name or text.title or _todo("VOLUME_SERIES_NAME"))
    lines += _string("VOLUME_SET_NAME", text.volume_set_name or text.title or _todo("VOLUME_SET_NAME"))
    lines += _string("VOLUME_SET_ID", text.volume_set_id or (facts.volume_id if text.title else None)
                     or _todo("VOLUME_SET_ID"))
    lines += ["  VOLUMES              = 1"]
    lines += _string("VOLUME_NAME", text.title or _todo("VOLUME_NAME"))
    lines += [f"  VOLUME_ID            = {format_string(facts.volume_id, 'VOLUME_ID', layout.VOLDESC)}",
              f'  VOLUME_VERSION_ID    = "VERSION {int(facts.version)}"',
              f"  PUBLICATION_DATE     = {_date(facts.publication_date)}",
              f"  DATA_SET_ID          = {data_set}",
              '  MEDIUM_TYPE          = "ELECTRONIC"']
    lines += _string("DESCRIPTION", f"This volume holds {facts.products} data product(s) in {layout.DATA_DIR}/, "
                                    f"{facts.previews} preview image(s) in {layout.EXTRAS_DIR}/ and the index "
                                    f"of the data products in {layout.INDEX_DIR}/. "
                                    + (text.description or _todo("what the products are and what they are for")))
    lines += ["", "  OBJECT               = DATA_PRODUCER"]
    lines += _string("INSTITUTION_NAME", institution or _todo("INSTITUTION_NAME"), "    ")
    lines += _string("FACILITY_NAME", text.facility or _optional(text, "FACILITY_NAME"), "    ")
    lines += _string("FULL_NAME", text.contact_text() or _todo("FULL_NAME of the contact"), "    ")
    lines += _string("ADDRESS_TEXT", text.address or _optional(text, "ADDRESS_TEXT of the contact"), "    ")
    lines += ["  END_OBJECT           = DATA_PRODUCER", "END_OBJECT             = VOLUME", "", "END"]
    return "\r\n".join(lines) + "\r\n"


def _date(value: str) -> str:
    """PUBLICATION_DATE, written bare: refused unless it is a date (YYYY-MM-DD)."""
    return format_value(dt.date.fromisoformat(value))


def _optional(text: DeliveryText, what: str) -> str:
    """A producer detail the delivery text may leave out: "N/A" (PDS3's not applicable) once a
    person has written the delivery's text (its title given), a placeholder before."""
    return layout.NOT_APPLICABLE if text.title else _todo(what)


def _known(value: str | None) -> str | None:
    """A label's value, unless it is the "UNK" a product made without --params carries."""
    return value if value and value.strip().upper() not in ("UNK", "N/A") else None


def aareadme_text(facts: VolumeFacts) -> str:
    """The volume's introduction: an attached label (OBJECT = TEXT) and the text."""
    label = ["PDS_VERSION_ID         = PDS3", "RECORD_TYPE            = STREAM", "",
             "OBJECT                 = TEXT",
             f"  PUBLICATION_DATE     = {_date(facts.publication_date)}",
             f"  NOTE                 = {format_string(f'Introduction to volume {facts.volume_id}', 'NOTE')}",
             "END_OBJECT             = TEXT", "", "END", ""]
    data_sets = ", ".join(facts.data_set_ids) or layout.NOT_APPLICABLE
    text = [
        f"Volume {facts.volume_id}, version {facts.version}, published {facts.publication_date}",
        "",
        *paragraphs(facts.text.readme or _todo("what this volume holds and why, in a paragraph for its readers")),
        *(["", *textwrap.wrap(AUTHORS_PREFIX + "; ".join(facts.text.authors), 78)] if facts.text.authors else []),
        "",
        f"Data sets: {data_sets}",
        "",
        "Contents",
        f"  {layout.AAREADME:<14}this file",
        f"  {layout.VOLDESC:<14}the volume's description",
        f"  {layout.DATA_DIR + '/':<14}{facts.products} data product(s), each with its PDS3 label",
        f"  {layout.EXTRAS_DIR + '/':<14}{facts.previews} preview image(s) and README.TXT describing them",
        f"  {layout.INDEX_DIR + '/':<14}{layout.INDEX_TABLE}, one row per data product; "
        f"{layout.INDEX_LABEL} describes it",
        f"  {layout.MANIFEST:<14}the MD5 checksum of every file (check with: md5sum -c {layout.MANIFEST})",
        "",
        "Contact",
        *paragraphs(_contact(facts.text) or _todo("who answers questions about this volume, and how to reach them")),
    ]
    return "\r\n".join(label + [ascii_text(line) for line in text]) + "\r\n"  # the text: 7-bit, escaped


def _contact(text: DeliveryText) -> str | None:
    """AAREADME.TXT's contact paragraph: the contact (or the authors) and the address, as given."""
    who = text.contact_text()
    if who is None:
        return None
    return f"{who}, {text.address}" if text.address else who
