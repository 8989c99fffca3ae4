"""The credit line of an annotated browse: whose data the picture shows.

A credit names the people behind the data, so it must come from the product, not
from a default that is right for one mission only. In order: the `--credit`
option, the params' CREDIT, the credit of an explicitly chosen profile, the
credit of the mission the product's label (or HRSC file name) names, and
otherwise what the label itself says - the mission or spacecraft and the
PRODUCER_INSTITUTION_NAME, as written (e.g. "MARS GLOBAL SURVEYOR / GODDARD
SPACE FLIGHT CENTER"). A product that says nothing gets no credit line rather
than someone else's.
"""

from __future__ import annotations

from collections.abc import Mapping

from ..errors import PdsgenError
from ..missions import get_mission, mission_names
from ..params import ParamValue
from .product_source import ProductSource

_MISSION_KEYS = ("MISSION_NAME", "INSTRUMENT_HOST_NAME", "SPACECRAFT_NAME")
_UNKNOWN = ("", "N/A", "UNK", "NULL", "NONE")


def product_credit(src: ProductSource, credit: str | None, keywords: Mapping[str, ParamValue],
                   profile: str | None) -> str:
    """The credit line for SRC (ASCII, one line; may be empty)."""
    if credit is not None:
        text = credit
    elif "CREDIT" in keywords:
        text = str(keywords["CREDIT"])
    else:
        text = _profile_credit(profile) or _profile_credit(src.mission) or label_credit(src.label)
    if not text.isascii():
        raise PdsgenError(None, f"credit line {text!r} must be ASCII text")
    return " ".join(text.split())


def label_credit(label: Mapping[str, object]) -> str:
    """Mission (or spacecraft) and producing institution, as the label writes them."""
    parts = [_text(label, key) for key in _MISSION_KEYS]
    mission = next((p for p in parts if p), "")
    institution = _text(label, "PRODUCER_INSTITUTION_NAME")
    return " / ".join(p for p in (mission, institution) if p)


def _profile_credit(name: str | None) -> str:
    return get_mission(name).credit if name and name in mission_names() else ""


def _text(label: Mapping[str, object], key: str) -> str:
    value = label.get(key)
    if isinstance(value, (list, tuple, set)):
        value = next(iter(value), None)
    text = " ".join(str(value or "").split())
    return "" if text.upper() in _UNKNOWN else text
