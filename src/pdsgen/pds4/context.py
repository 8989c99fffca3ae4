"""PDS4 context: the investigation, observing system and target a label names.

PDS4 labels point at registered context products by LID. The mission's part comes
from its module (`Mission.pds4`: bundle, investigation, host and instrument); the
target from the body the CRS names. An unknown target keeps its name without a
context reference rather than an invented LID.

PDS's registry of context products is read here (`registered`, `product`, `named`): the
snapshot NASA's validator ships (schemas/pds4/context_products.txt.xz: LIDVIDs with their
registered types and names; provenance in its first line and schemas/pds4/SOURCES.md),
and the IM's Target_Identification type values from the shipped core Schematron
(`target_types`). A body outside the table below takes its registered type and LID from it.
The validator's context checks (validate/pds4/context_registry) and migrate read the same.
"""

from __future__ import annotations

import lzma
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import cache

from lxml import etree

from ..missions import ContextReference, Mission
from ..params import ParamValue
from ..resources import schemas_dir

# Bodies pdsgen recognises from a CRS (geometry.target_name) -> (PDS4 name, type, context LID).
TARGETS = {
    "MERCURY": ("Mercury", "Planet", "urn:nasa:pds:context:target:planet.mercury"),
    "VENUS": ("Venus", "Planet", "urn:nasa:pds:context:target:planet.venus"),
    "EARTH": ("Earth", "Planet", "urn:nasa:pds:context:target:planet.earth"),
    "MOON": ("Moon", "Satellite", "urn:nasa:pds:context:target:satellite.earth.moon"),
    "MARS": ("Mars", "Planet", "urn:nasa:pds:context:target:planet.mars"),
    "PHOBOS": ("Phobos", "Satellite", "urn:nasa:pds:context:target:satellite.mars.phobos"),
    "DEIMOS": ("Deimos", "Satellite", "urn:nasa:pds:context:target:satellite.mars.deimos"),
    "CERES": ("(1) Ceres", "Dwarf Planet", "urn:nasa:pds:context:target:dwarf_planet.1_ceres"),
    "VESTA": ("(4) Vesta", "Asteroid", "urn:nasa:pds:context:target:asteroid.4_vesta"),
    "PLUTO": ("(134340) Pluto", "Dwarf Planet", "urn:nasa:pds:context:target:dwarf_planet.134340_pluto"),
}


# -- PDS's registry of context products ---------------------------------------------------------------------

@dataclass(frozen=True)
class ContextProduct:
    """One registered context product: its LID (lower case), the types and names PDS gives it."""

    lid: str
    types: tuple[str, ...]
    names: tuple[str, ...]

    @property
    def kind(self) -> str:
        """The LID's kind: target, investigation, instrument_host, instrument, ..."""
        parts = self.lid.split(":")
        return parts[4] if len(parts) > 4 else ""

    @property
    def label_name(self) -> str:
        """The name a PDS4 label gives it: the registry's first name that is not a NAIF ID or a LID."""
        usable = [n for n in self.names if not n.upper().startswith(("NAIF ID", "URN:"))]
        return (usable or [self.lid.rsplit(".", 1)[-1]])[0]


@cache
def _snapshot() -> tuple[dict[str, tuple[float, ...]], dict[str, ContextProduct]]:
    """Lower-case LID -> registered versions, and -> the product (types and names)."""
    path = schemas_dir() / "pds4" / "context_products.txt.xz"
    versions: dict[str, tuple[float, ...]] = {}
    products: dict[str, ContextProduct] = {}
    for line in lzma.decompress(path.read_bytes()).decode("utf-8").splitlines():
        if not line or line.startswith("#"):
            continue
        lid_version, _, facts = line.partition("\t")
        lid, _, version = lid_version.partition(" ")
        lid = lid.lower()
        kinds, _, names = facts.partition("\t")
        have = versions.setdefault(lid, ())
        if version:
            versions[lid] = (*have, float(version))
        known = products.get(lid)
        products[lid] = ContextProduct(lid, _merged(known.types if known else (), kinds.split("|")),
                                       _merged(known.names if known else (), names.split("|")))
    return versions, products


def _merged(have: tuple[str, ...], more: Iterable[str]) -> tuple[str, ...]:
    return tuple(dict.fromkeys((*have, *(m for m in more if m))))


def registered() -> dict[str, tuple[float, ...]]:
    """Lower-case LID -> the versions registered for it (empty when none is given)."""
    return _snapshot()[0]


def product(lid: str) -> ContextProduct | None:
    """The registered context product of a LID (or LIDVID), None when PDS has not registered it."""
    return _snapshot()[1].get(lid.strip().partition("::")[0].lower())


def normal_name(name: str) -> str:
    """A name as names are compared: upper case, quotes dropped, blanks folded."""
    return " ".join(name.replace('"', " ").upper().split())


@cache
def _by_name(kind: str) -> dict[str, tuple[ContextProduct, ...]]:
    """Registered products of one kind (target, investigation ...) by each of their names."""
    found: dict[str, tuple[ContextProduct, ...]] = {}
    for item in _snapshot()[1].values():
        if item.kind == kind:
            for name in {normal_name(n) for n in item.names}:
                found[name] = (*found.get(name, ()), item)
    return found


def named(kind: str, name: str) -> tuple[ContextProduct, ...]:
    """The registered products of `kind` that carry `name` among their names (case and blanks aside)."""
    return _by_name(kind).get(normal_name(name), ())


_PERIODIC_COMET = re.compile(r"(\d+)P/")


def numbered_comet(name: str) -> tuple[ContextProduct, ...]:
    """The registered comet of a periodic-comet number ("67P/CHURYUMOV-GERASIMENKO 1 (1969 R1)":
    67P): the IAU numbers periodic comets uniquely, so the number alone names one."""
    m = _PERIODIC_COMET.match(normal_name(name))
    if m is None:
        return ()
    prefix = f"comet.{m.group(1)}p_"
    return tuple(item for item in _snapshot()[1].values()
                 if item.kind == "target" and item.lid.rsplit(":", 1)[-1].startswith(prefix))


# The IM the enumeration is read from: the core schema pdsgen ships (schemas/pds4/SOURCES.md).
CORE_SCHEMATRON = ("1O00", "PDS4_PDS_1O00.sch")
_QUOTED = re.compile(r"'([^']*)'")


@cache
def target_types() -> tuple[frozenset[str], frozenset[str]]:
    """The IM's Target_Identification/type values and those of them it deprecates, as the shipped
    core Schematron states them (the rule on pds:Target_Identification/pds:type; the warnings
    `pds:type != '...'` on pds:Target_Identification)."""
    root = etree.parse(str(schemas_dir() / "pds4" / CORE_SCHEMATRON[0] / CORE_SCHEMATRON[1])).getroot()
    allowed: set[str] = set()
    deprecated: set[str] = set()
    for rule in root.iter("{http://purl.oclc.org/dsdl/schematron}rule"):
        context = rule.get("context", "")
        for test in (a.get("test", "") for a in rule.iter("{http://purl.oclc.org/dsdl/schematron}assert")):
            if context == "pds:Target_Identification/pds:type" and test.startswith(". = ("):
                allowed.update(_QUOTED.findall(test))
            elif context == "pds:Target_Identification" and test.startswith("pds:type != "):
                deprecated.update(_QUOTED.findall(test))
    return frozenset(allowed), frozenset(deprecated)


def observation(mission: Mission, target: str | None, summary: str,
                keywords: Mapping[str, ParamValue]) -> dict[str, object]:
    """The Observation_Area values (besides cartography) for a product of `mission`."""
    facts = mission.pds4
    name, kind, lid = TARGETS.get((target or "").upper()) or registered_target(target or "Unknown")
    components: list[ContextReference | dict[str, str | None]] = list(facts.observing_system)
    if not components:  # PDS4 needs one; without a registered instrument, name the one given
        instrument = str(keywords.get("INSTRUMENT_NAME", "UNK"))
        components = [{"name": instrument if instrument != "UNK" else "Unknown", "type": "Instrument",
                       "lid": None, "reference_type": None}]
    return {
        "summary": summary,
        "investigation": facts.investigation,
        "components": components,
        "target_name": name,
        "target_type": kind,
        "target_lid": lid,
    }


def registered_target(name: str) -> tuple[str, str, str | None]:
    """(name, type, LID) of a body outside TARGETS from the registry (TITAN: Titan, Satellite,
    satellite.saturn.titan); a body it does not hold keeps its name and the type of PDS's
    registered unknown target, without a LID."""
    found = {p.lid: p for p in named("target", name)}
    allowed, deprecated = target_types()
    if len(found) == 1:
        (item,) = found.values()
        kinds = [t for t in item.types if t in allowed and t not in deprecated]
        if kinds:
            spelled = next((n for n in item.names if normal_name(n) == normal_name(name)), name.title())
            return spelled, kinds[0], item.lid
    unknown = {p.lid: p for p in named("target", "Unknown")}
    kind = next((t for p in unknown.values() for t in p.types if t in allowed), "Calibrator")
    return name.title(), kind, None


def logical_identifier(mission: Mission, collection: str, product_id: str) -> str:
    """<authority>:<bundle>:<collection>:<product>, e.g. urn:nasa:pds:mro_hirise:data_dtm:... (lower case)."""
    return f"{mission.pds4.authority}:{mission.pds4.bundle}:{collection}:{product_id.lower()}"


# What pdsgen's sources are: the PDS3 SOURCE_PRODUCT_ID of a map-projected DTM or orthoimage
# names the products it was made from (a mosaic's strips, an orthoimage's DTM, a stereo pair),
# whose processing level the label does not state; PDS4 has no "unknown" level, and
# derived is the level of the products these are (processing_level Derived).
SOURCE_REFERENCE_TYPE = "data_to_derived_source_product"
NOT_A_SOURCE = frozenset({"", "N/A", "NULL", "UNK", "NONE"})


def source_products(identifiers: Iterable[object], curating_facility: str) -> dict[str, object] | None:
    """The Reference_List's Source_Product_External for the PDS3 SOURCE_PRODUCT_ID values
    `identifiers` (N/A and empty ones dropped, repeats once); None when none is left."""
    kept = list(dict.fromkeys(s for s in (str(i).strip() for i in identifiers) if s.upper() not in NOT_A_SOURCE))
    if not kept:
        return None
    return {"identifiers": kept, "reference_type": SOURCE_REFERENCE_TYPE, "curating_facility": curating_facility,
            "description": "The products named by the PDS3 label's SOURCE_PRODUCT_ID."}
