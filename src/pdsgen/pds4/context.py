"""PDS4 context: the investigation, observing system and target a label names.

PDS4 labels point at registered context products by LID. The mission's part comes
from its module (`Mission.pds4`: bundle, investigation, host and instrument); the
target from the body the CRS names. An unknown target keeps its name without a
context reference rather than an invented LID.
"""

from __future__ import annotations

from collections.abc import Mapping

from ..missions import ContextReference, Mission
from ..products.params import ParamValue

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


def observation(mission: Mission, target: str | None, summary: str,
                keywords: Mapping[str, ParamValue]) -> dict[str, object]:
    """The Observation_Area values (besides cartography) for a product of `mission`."""
    facts = mission.pds4
    name, kind, lid = TARGETS.get((target or "").upper(), ((target or "Unknown").title(), "Planet", None))
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


def logical_identifier(mission: Mission, collection: str, product_id: str) -> str:
    """<authority>:<bundle>:<collection>:<product>, e.g. urn:nasa:pds:mro_hirise:data_dtm:... (lower case)."""
    return f"{mission.pds4.authority}:{mission.pds4.bundle}:{collection}:{product_id.lower()}"
