"""Identification_Area and Observation_Area of a migrated product, from its PDS3 keywords.

A LID is `<bundle LID>:<collection>:<product>`, each part in the characters a LID allows
(lower-case letters, digits, '-', '.', '_'); the PDS3 PRODUCT_ID and DATA_SET_ID are kept
as aliases. The mission context comes from pdsgen's mission modules when one recognises
the label (HiRISE, HRSC); otherwise from the label's own names.
"""

from __future__ import annotations

import re
from datetime import datetime, timedelta

from .. import __version__
from ..errors import ParamsError, param
from ..label.grammar import PLACEHOLDERS
from ..label.tree import Block, first_text
from ..missions import ContextReference, LabelFacts, detect_mission, get_mission
from ..pds4.context import TARGETS, source_products
from ..validate.pds4.context_registry import is_registered
from .mapping import PROCESSING_LEVELS

_LID_PART = re.compile(r"[^a-z0-9._-]+")
_LID = re.compile(r"urn:[a-z]+:[a-z]+(?::[a-z0-9._-]+)+")
_PDS3_TIME = re.compile(r"(\d{4})-(?:(\d{3})|(\d{2})-(\d{2}))(?:T(\d{2}):(\d{2})(?::(\d{2})(\.\d+)?)?)?Z?")


def lid_part(text: str) -> str:
    """`text` in a LID's characters: lower case, other runs of characters as '_'."""
    return _LID_PART.sub("_", text.strip().lower()).strip("_") or "product"


def check_bundle_lid(bundle_lid: str) -> str:
    if not _LID.fullmatch(bundle_lid) or bundle_lid.count(":") != 3:
        raise ParamsError(None, f"{param('bundle_lid')} {bundle_lid!r} is not a bundle LID "
                                "(urn:<agency>:<authority>:<bundle>, lower case)")
    return bundle_lid


def check_product_lid(lid: str) -> str:
    if not _LID.fullmatch(lid) or lid.count(":") != 5:
        raise ParamsError(None, f"the product LID {lid!r} is not one "
                                "(urn:<agency>:<authority>:<bundle>:<collection>:<product>, lower case)")
    return lid


def text(root: Block, key: str) -> str | None:
    """A keyword's text at the root or in the first block that has it (label/tree.first_text),
    its blanks folded; placeholders (and an empty text) as None."""
    value = first_text(root, key)
    if value is None:
        return None
    value = " ".join(value.split())
    return None if value.upper() in PLACEHOLDERS or not value else value


def product_id(root: Block, fallback: str) -> tuple[str, str | None]:
    """The product's PDS3 identifier and the keyword that gave it (None: the file name's stem)."""
    for keyword in ("PRODUCT_ID", "IMAGE_ID"):
        value = text(root, keyword)
        if value:
            return value, keyword
    return fallback, None


def default_bundle_lid(root: Block) -> str:
    """Without --bundle-lid: a bundle named after the PDS3 data set."""
    return f"urn:nasa:pds:{lid_part(text(root, 'DATA_SET_ID') or 'pds3_migrated')}"


def identification(root: Block, bundle_lid: str, collection: str, pid: str, keyword: str | None
                   ) -> dict[str, object]:
    aliases = [(pid, f"PDS3 {keyword}")] if keyword else []
    data_set = text(root, "DATA_SET_ID")
    if data_set:
        aliases.append((data_set, "PDS3 DATA_SET_ID"))
    what = text(root, "DATA_SET_NAME") or data_set or "a PDS3 data set"
    return {
        "lid": f"{bundle_lid}:{lid_part(collection)}:{lid_part(pid)}",
        "version_id": "1.0",
        "title": f"{pid}: PDS3 product of {what}, described in PDS4",
        "aliases": aliases,
    }


def utc_time(value: str | None) -> str | None:
    """A PDS3 time (CCYY-MM-DDThh:mm:ss[.f] or CCYY-DDDT...) as PDS4's UTC form, or None."""
    m = _PDS3_TIME.fullmatch(value or "")
    if m is None:
        return None
    year, doy, month, day, hour, minute, second, fraction = m.groups()
    try:
        date = datetime(int(year), 1, 1) + timedelta(days=int(doy) - 1) if doy else \
            datetime(int(year), int(month), int(day))
    except ValueError:
        return None
    if hour is None:
        return f"{date:%Y-%m-%d}Z"
    return f"{date:%Y-%m-%d}T{hour}:{minute}:{second or '00'}{fraction or ''}Z"


def _title(name: str) -> str:
    return " ".join(word.capitalize() for word in name.split())


def _known_mission(root: Block, label_name: str) -> str | None:
    """The mission profile that recognises the label, if one does."""
    return detect_mission(LabelFacts(instrument_id=(text(root, "INSTRUMENT_ID") or "").upper(),
                                     data_set_id=(text(root, "DATA_SET_ID") or "").upper(),
                                     group_names=frozenset(b.name.upper() for b in root.walk() if b is not root),
                                     file_name=label_name))


def sources(root: Block, label_name: str) -> dict[str, object] | None:
    """The Reference_List's source products, from SOURCE_PRODUCT_ID (a value or a sequence;
    N/A: none), curated where the recognised mission's products are (else PDS)."""
    statement = next((s for b in root.walk() if (s := b.get("SOURCE_PRODUCT_ID")) is not None), None)
    if statement is None:
        return None
    known = _known_mission(root, label_name)
    facility = get_mission(known or "generic").pds4.curating_facility
    return source_products((str(v.py) for v in statement.value.scalars()), facility)


def observation(root: Block, label_name: str) -> dict[str, object]:
    """Observation_Area values: times, level, investigation, observing system, target."""
    known = _known_mission(root, label_name)
    host = text(root, "INSTRUMENT_HOST_NAME") or text(root, "SPACECRAFT_NAME")
    mission = text(root, "MISSION_NAME") or host
    investigation: ContextReference | dict[str, str]
    components: list[ContextReference | dict[str, str | None]]
    if known is not None and get_mission(known).pds4.observing_system:
        pds4 = get_mission(known).pds4
        investigation, components = pds4.investigation, list(pds4.observing_system)
    else:
        investigation = get_mission("generic").pds4.investigation
        mission_lid = f"urn:nasa:pds:context:investigation:mission.{lid_part(mission)}" if mission else ""
        if mission and is_registered(mission_lid):  # a LID PDS has not registered would not resolve
            investigation = {"name": _title(mission), "type": "Mission", "lid": mission_lid,
                             "reference_type": "data_to_investigation"}
        components = []
        if host:
            components.append({"name": _title(host), "type": "Host", "lid": None, "reference_type": None})
        instrument = text(root, "INSTRUMENT_NAME") or text(root, "INSTRUMENT_ID")
        components.append({"name": _title(instrument) if instrument else "Unknown", "type": "Instrument",
                           "lid": None, "reference_type": None})
    target = text(root, "TARGET_NAME") or ""
    name, kind, lid = TARGETS.get(target.upper(), (_title(target) if target else "Unknown", "Planet", None))
    level = PROCESSING_LEVELS.get(((text(root, "DATA_SET_ID") or "").split("-") + [""] * 4)[3])
    return {
        "summary": f"A PDS3 product described unchanged in PDS4 by pdsgen {__version__} (pdsgen migrate).",
        "investigation": investigation,
        "components": components,
        "target_name": name,
        "target_type": kind,
        "target_lid": lid,
        "start_date_time": utc_time(text(root, "START_TIME")),
        "stop_date_time": utc_time(text(root, "STOP_TIME")),
        "processing_level": level or "Derived",
    }
