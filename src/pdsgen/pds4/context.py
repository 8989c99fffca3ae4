"""PDS4 context facts: the investigation, observing system and target a label names.

PDS4 labels point at registered context products by LID. The mission parts come
from the mission profile (`PDS4_MISSIONS`, keyed like `profiles.PROFILES`); the
target from the body the CRS names. Unknown targets keep their name without a
context reference rather than inventing a LID.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from ..params import ParamValue


@dataclass(frozen=True)
class Component:
    name: str
    type: str  # Host, Instrument, ...
    lid: str | None
    reference_type: str


@dataclass(frozen=True)
class Pds4Mission:
    """What a mission contributes to a PDS4 label."""

    bundle: str  # LID bundle part
    investigation_name: str
    investigation_type: str
    investigation_lid: str
    components: tuple[Component, ...]


_NO_INVESTIGATION = Pds4Mission(
    bundle="pdsgen",
    investigation_name="No Specific Investigation",
    investigation_type="Individual Investigation",
    investigation_lid="urn:nasa:pds:context:investigation:individual.none",
    components=(),
)

PDS4_MISSIONS = {
    "hirise": Pds4Mission(
        bundle="mro_hirise",
        investigation_name="Mars Reconnaissance Orbiter",
        investigation_type="Mission",
        investigation_lid="urn:nasa:pds:context:investigation:mission.mars_reconnaissance_orbiter",
        components=(
            Component("Mars Reconnaissance Orbiter", "Host",
                      "urn:nasa:pds:context:instrument_host:spacecraft.mro", "is_instrument_host"),
            Component("High Resolution Imaging Science Experiment", "Instrument",
                      "urn:nasa:pds:context:instrument:mro.hirise", "is_instrument"),
        ),
    ),
    "hrsc": Pds4Mission(
        bundle="mex_hrsc",
        investigation_name="Mars Express",
        investigation_type="Mission",
        investigation_lid="urn:nasa:pds:context:investigation:mission.mars_express",
        components=(
            Component("Mars Express", "Host", "urn:nasa:pds:context:instrument_host:spacecraft.mex",
                      "is_instrument_host"),
            Component("High Resolution Stereo Camera", "Instrument",
                      "urn:nasa:pds:context:instrument:mex.hrsc", "is_instrument"),
        ),
    ),
    "generic": _NO_INVESTIGATION,
}

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


def pds4_mission(profile: str) -> Pds4Mission:
    return PDS4_MISSIONS.get(profile, _NO_INVESTIGATION)


def observation(profile: str, target: str | None, summary: str,
                keywords: Mapping[str, ParamValue]) -> dict[str, object]:
    """The Observation_Area values (besides cartography) for a product of `profile`."""
    mission = pds4_mission(profile)
    name, kind, lid = TARGETS.get((target or "").upper(), ((target or "Unknown").title(), "Planet", None))
    components = list(mission.components)
    if not components:
        instrument = str(keywords.get("INSTRUMENT_NAME", "UNK"))
        components = [Component(instrument if instrument != "UNK" else "Unknown", "Instrument", None, "")]
    return {
        "summary": summary,
        "investigation_name": mission.investigation_name,
        "investigation_type": mission.investigation_type,
        "investigation_lid": mission.investigation_lid,
        "components": components,
        "target_name": name,
        "target_type": kind,
        "target_lid": lid,
    }


def logical_identifier(profile: str, collection: str, product_id: str) -> str:
    """urn:nasa:pds:<bundle>:<collection>:<product> (LIDs are lower case)."""
    return f"urn:nasa:pds:{pds4_mission(profile).bundle}:{collection}:{product_id.lower()}"
