"""PDS4 context: the investigation, observing system and target a label names.

PDS4 labels point at registered context products by LID. The mission's part comes
from its module (`Mission.pds4`: bundle, investigation, host and instrument); the
target from the body the CRS names. An unknown target keeps its name without a
context reference rather than an invented LID.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from ..missions import ContextReference, Mission
from ..params import ParamValue

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
