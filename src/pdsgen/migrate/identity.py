"""Identification_Area and Observation_Area of a migrated product, from its PDS3 keywords.

A LID is `<bundle LID>:<collection>:<product>`, each part in the characters a LID allows
(lower-case letters, digits, '-', '.', '_'); the PDS3 PRODUCT_ID and DATA_SET_ID are kept
as aliases. The mission context comes from pdsgen's mission modules when one recognises
the label (HiRISE, HRSC); otherwise from the label's own names, looked up in PDS's registry
of context products (pds4/context: the snapshot NASA's validator ships):

- target: the registered target the TARGET_NAME names (one of its registered names, or a
  periodic comet's number), with its registered type(s) and LID. A name PDS has not
  registered gets the type the label states (TARGET_TYPE, where a PDS3 value means one IM
  value) or its IAU designation makes certain (a comet's "C/1995 O1", a satellite's
  "S/2004 S 12"); otherwise a warning says the type is not known.
- investigation, host and instrument: the registered ones MISSION_NAME,
  INSTRUMENT_HOST_NAME and INSTRUMENT_NAME/INSTRUMENT_ID name, with their LIDs; "No
  Specific Investigation" only when no registered investigation matches.

Every fact that could not be stated for sure comes back as a warning (`observation(...)
["warnings"]`), which the migration reports.
"""

from __future__ import annotations

import re
from datetime import datetime, timedelta
from typing import Any

from .. import __version__
from ..errors import ParamsError, param
from ..label.grammar import PLACEHOLDERS
from ..label.tree import Block, first_text
from ..missions import ContextReference, LabelFacts, detect_mission, get_mission
from ..pds4.context import (
    ContextProduct,
    named,
    normal_name,
    numbered_comet,
    product,
    source_products,
    target_types,
)
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
    """Observation_Area values: times, level, investigation, observing system, target(s), and
    the warnings of what could not be stated for sure."""
    warnings: list[str] = []
    known = _known_mission(root, label_name)
    investigation: ContextReference | dict[str, str]
    components: list[ContextReference | dict[str, str | None]]
    if known is not None and get_mission(known).pds4.observing_system:
        pds4 = get_mission(known).pds4
        investigation, components = pds4.investigation, list(pds4.observing_system)
    else:
        investigation, components = _registered_context(root)
    targets = [target_identification(name, text(root, "TARGET_TYPE"), warnings) for name in _target_names(root)]
    level = PROCESSING_LEVELS.get(((text(root, "DATA_SET_ID") or "").split("-") + [""] * 4)[3])
    return {
        "summary": f"A PDS3 product described unchanged in PDS4 by pdsgen {__version__} (pdsgen migrate).",
        "investigation": investigation,
        "components": components,
        "targets": targets,
        "target_name": targets[0]["name"],
        "target_type": targets[0]["types"][0],
        "target_lid": targets[0]["lid"],
        "start_date_time": utc_time(text(root, "START_TIME")),
        "stop_date_time": utc_time(text(root, "STOP_TIME")),
        "processing_level": level or "Derived",
        "warnings": warnings,
    }


# -- investigation and observing system -----------------------------------------------------------------

def _registered_context(root: Block) -> tuple[dict[str, str], list[ContextReference | dict[str, str | None]]]:
    """The investigation and observing system the label's names denote in PDS's registry; a name
    the registry does not hold keeps its own words (no LID), and the investigation is PDS's
    "No Specific Investigation" only when no registered one matches."""
    host_name = text(root, "INSTRUMENT_HOST_NAME") or text(root, "SPACECRAFT_NAME")
    mission = text(root, "MISSION_NAME") or host_name
    found = _one(named("investigation", mission or "")) or _one(named("investigation", host_name or ""))
    investigation: dict[str, str]
    if found is not None:
        investigation = {"name": _spelling(found, mission or host_name or ""), "type": _investigation_type(found),
                         "lid": found.lid, "reference_type": "data_to_investigation"}
    else:
        generic = get_mission("generic").pds4.investigation
        investigation = {"name": generic.name, "type": generic.type, "lid": generic.lid,
                         "reference_type": generic.reference_type}
        mission_lid = f"urn:nasa:pds:context:investigation:mission.{lid_part(mission)}" if mission else ""
        if mission and is_registered(mission_lid):  # a LID PDS has not registered would not resolve
            investigation = {"name": _title(mission), "type": "Mission", "lid": mission_lid,
                             "reference_type": "data_to_investigation"}
    components: list[ContextReference | dict[str, str | None]] = []
    host = _registered_host(root, host_name)
    if found is None and host is not None and investigation["lid"] == get_mission("generic").pds4.investigation.lid:
        by_host = _investigation_of_host(host)  # a label naming its spacecraft by SPACECRAFT_ID alone (CRISM)
        if by_host is not None:
            investigation = {"name": by_host.label_name, "type": _investigation_type(by_host), "lid": by_host.lid,
                             "reference_type": "data_to_investigation"}
    if host is not None:
        components.append({"name": _title(host_name) if host_name else host.label_name, "type": "Host", "lid": host.lid,
                           "reference_type": "is_instrument_host"})
    elif host_name:
        components.append({"name": _title(host_name), "type": "Host", "lid": None, "reference_type": None})
    instrument_name = text(root, "INSTRUMENT_NAME") or text(root, "INSTRUMENT_ID")
    instrument = _registered_instrument(root, host, instrument_name)
    components.append({"name": _title(instrument_name) if instrument_name else "Unknown", "type": "Instrument",
                       "lid": instrument.lid if instrument else None,
                       "reference_type": "is_instrument" if instrument else None})
    return investigation, components


def _investigation_of_host(host: ContextProduct) -> ContextProduct | None:
    """The one registered investigation bearing a name of the registered host (the Mars
    Reconnaissance Orbiter mission for the spacecraft of that name): the inference the
    validator's PDS4-066 makes, so a migrated label never draws that note."""
    return _one(tuple({p.lid: p for name in host.names for p in named("investigation", name)}.values()))


_INVESTIGATION_TYPES = ("Field Campaign", "Individual Investigation", "Mission", "Observing Campaign",
                        "Other Investigation")  # the IM's Investigation_Area/type values


def _investigation_type(found: ContextProduct) -> str:
    return next((t for t in found.types if t in _INVESTIGATION_TYPES), "Mission")


def _registered_host(root: Block, host_name: str | None) -> ContextProduct | None:
    """The registered instrument host INSTRUMENT_HOST_NAME names, else the one whose LID is
    INSTRUMENT_HOST_ID's (spacecraft.<id>, as PDS's host LIDs are made)."""
    found = _one(named("instrument_host", host_name or ""))
    if found is not None:
        return found
    host_id = lid_part(text(root, "INSTRUMENT_HOST_ID") or text(root, "SPACECRAFT_ID") or "")
    if host_id == "product":
        return None
    found_by_id = (product(f"urn:{authority}:context:instrument_host:spacecraft.{host_id}")
                   for authority in _AUTHORITIES)
    return _one(tuple(p for p in found_by_id if p is not None))


_AUTHORITIES = ("nasa:pds", "esa:psa", "jaxa:darts", "isro:isda")  # the agencies whose context products PDS registers


def _registered_instrument(root: Block, host: ContextProduct | None, name: str | None) -> ContextProduct | None:
    """The registered instrument of `host` the label names: PDS's instrument LIDs join the
    instrument's and the host's short names (msi.near, ro.osiwac), so INSTRUMENT_ID with the
    host's short name, else INSTRUMENT_NAME among the names of that host's instruments."""
    if host is None:
        return None
    short = host.lid.rsplit(":", 1)[-1].split(".", 1)[-1]
    authority = host.lid.rsplit(":context:", 1)[0]
    instrument_id = lid_part(text(root, "INSTRUMENT_ID") or "")
    for tail in (f"{instrument_id}.{short}", f"{short}.{instrument_id}"):
        found = product(f"{authority}:context:instrument:{tail}")
        if found is not None and instrument_id != "product":
            return found
    if not name:
        return None
    return _one(tuple(p for p in named("instrument", name)
                      if short in p.lid.rsplit(":", 1)[-1].split(".")))


def _one(found: tuple[ContextProduct, ...]) -> ContextProduct | None:
    """The one registered product of several names, None when there is none or several."""
    lids = {p.lid for p in found}
    return found[0] if len(lids) == 1 else None


def _spelling(found: ContextProduct, name: str) -> str:
    """The registry's own spelling of the name the label gave (PHOBOS -> Phobos), else the label's."""
    wanted = normal_name(name)
    return next((n for n in found.names if normal_name(n) == wanted), None) or found.label_name


# -- target ---------------------------------------------------------------------------------------------

# PDS3 TARGET_TYPE standard values (PDS3 data dictionary) whose meaning is one IM Target_Identification
# type; CALIBRATION is not here: PDS4 parts it into Calibrator and Calibration Field.
PDS3_TARGET_TYPES = {
    "ASTEROID": "Asteroid", "COMET": "Comet", "DUST": "Dust", "GALAXY": "Galaxy", "GLOBULAR CLUSTER": "Star Cluster",
    "METEOROID": "Meteoroid", "METEOROID STREAM": "Meteoroid Stream", "METEOROID_STREAM": "Meteoroid Stream",
    "NEBULA": "Nebula", "OPEN CLUSTER": "Star Cluster", "PLANET": "Planet", "PLANETARY NEBULA": "Planetary Nebula",
    "PLANETARY SYSTEM": "Planetary System", "PLANETARY_SYSTEM": "Planetary System", "PLASMA CLOUD": "Plasma Cloud",
    "RING": "Ring", "SATELLITE": "Satellite", "STAR": "Star", "STAR CLUSTER": "Star Cluster", "SUN": "Star",
    "TRANS-NEPTUNIAN OBJ": "Trans-Neptunian Object", "TRANS-NEPTUNIAN OBJECT": "Trans-Neptunian Object",
    "DWARF PLANET": "Dwarf Planet", "CENTAUR": "Centaur", "SKY": "Sky",
}
# IAU designations that say what a body is: comets (C/1995 O1, P/2010 A2, 67P/..., D/1993 F2),
# provisional satellites (S/2004 S 12).
_DESIGNATED = ((re.compile(r"(?:\d+[PD]|[PCDX])/"), "Comet"), (re.compile(r"S/\d{4} "), "Satellite"))
UNKNOWN_TARGET = "Unknown"  # the name PDS registers its unknown target under (calibrator.unk)


def _target_names(root: Block) -> list[str]:
    """TARGET_NAME's names (a value or a set/sequence of them); "Unknown" when it names none."""
    statement = next((s for b in root.walk() if (s := b.get("TARGET_NAME")) is not None), None)
    names = [] if statement is None else [" ".join(str(v.py).split()) for v in statement.value.scalars()]
    kept = [n for n in dict.fromkeys(names) if n and n.upper() not in PLACEHOLDERS]
    return kept or [UNKNOWN_TARGET]


def target_identification(name: str, stated_type: str | None, warnings: list[str]) -> dict[str, Any]:
    """Target_Identification of one PDS3 target name: name, type(s) and LID from PDS's registry,
    else the type that can be known for sure; what cannot is added to `warnings`."""
    candidates = named("target", name) or numbered_comet(name)
    lids = sorted({c.lid for c in candidates})
    allowed, deprecated = target_types()
    if len(lids) == 1:
        found = candidates[0]
        types = [t for t in found.types if t in allowed and t not in deprecated]
        if types:
            _compare_stated(name, stated_type, types, warnings)
            return {"name": _spelling(found, name), "types": types, "lid": found.lid}
    kinds = sorted({t for c in candidates for t in c.types if t in allowed and t not in deprecated})
    if len(lids) > 1 and len(kinds) == 1:
        warnings.append(f"TARGET_NAME {name!r} names {len(lids)} registered targets ({', '.join(lids)}): "
                        f"typed {kinds[0]}, as all of them are, without a context reference")
        return {"name": _spelling(candidates[0], name), "types": kinds, "lid": None}
    known = _certain_type(name, stated_type)
    if known is not None:
        if name != UNKNOWN_TARGET:
            warnings.append(f"TARGET_NAME {name!r} is not one target in PDS's registry of context products: "
                            f"typed {known[0]} ({known[1]}), without a context reference")
        return {"name": _title(name), "types": [known[0]], "lid": None}
    fallback = _one(named("target", UNKNOWN_TARGET))
    kind = next((t for t in fallback.types if t in allowed), "Calibrator") if fallback else "Calibrator"
    what = "the label names no target" if name == UNKNOWN_TARGET else \
        f"TARGET_NAME {name!r} is not in PDS's registry of context products and nothing in the label states its type"
    warnings.append(f"{what}: Target_Identification/type written as {kind}, the type PDS registers its unknown "
                    "target with; state the true type")
    return {"name": _title(name), "types": [kind], "lid": fallback.lid if fallback and name == UNKNOWN_TARGET
            else None}


def _certain_type(name: str, stated_type: str | None) -> tuple[str, str] | None:
    """(type, where it comes from) of a target the registry does not settle, when it is certain."""
    stated = PDS3_TARGET_TYPES.get(normal_name(stated_type or ""))
    if stated is not None:
        return stated, f"the label's TARGET_TYPE = {stated_type}"
    for pattern, kind in _DESIGNATED:
        if pattern.match(normal_name(name)):
            return kind, "its IAU designation"
    return None


def _compare_stated(name: str, stated_type: str | None, types: list[str], warnings: list[str]) -> None:
    """A TARGET_TYPE that means another type than the registered one: said (the registry's is written)."""
    stated = PDS3_TARGET_TYPES.get(normal_name(stated_type or ""))
    if stated is not None and stated not in types:
        warnings.append(f"TARGET_NAME {name!r}: the label's TARGET_TYPE = {stated_type} ({stated}) is not the type "
                        f"PDS registers ({', '.join(types)}); the registered type is written")
