"""What a DTM's numbers are heights above: the datum the legends and README.TXT state.

A height means nothing without its reference surface, and archives use several:
HiRISE DTMs give heights above the Mars 2000 areoid, HRSC DT4 above the 3396.0 km
sphere, HRSC DA4 above the areoid, MOLA MEGDR topography above the areoid. Some
products store planetary radii instead: a LOLA LDEM label says
`radius = DN * SCALING_FACTOR + OFFSET` with OFFSET the body's reference radius
(1737400 m, equal to A_AXIS_RADIUS). Shown as they are, those would read
"Elevation 1,740,000 m"; when OFFSET equals the label's radius the Extras leave it
out and show heights above that sphere, and say so.

The datum is found, in this order: the radius rule above; the datum the user states
(`vertical_datum`); the label's own words (its IMAGE or product NOTE/DESCRIPTION saying
"above the ... areoid|geoid|sphere|ellipsoid"), in the mission's wording where the mission fixes
one of that kind (HiRISE: "the Mars 2000 areoid"); otherwise the legends say the label names
none. A mission recognised from a DATA_SET_ID alone never states a datum the label does not:
a generic product borrowing a HiRISE data set ID is not thereby above the Mars 2000 areoid.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..geo.label_georef import projection_object
from ..missions import get_mission, mission_names

# A radius OFFSET and A_AXIS_RADIUS agree when within this many metres (labels
# round the radius to 0.1 km or better; heights are never that close to it).
RADIUS_MATCH_M = 1.0
NOT_STATED = "a reference surface the label does not name"
_AREOID_WORDS = re.compile(r"\bAREOID\b")
_GEOID_WORDS = re.compile(r"\b(GEOID|EQUIPOTENTIAL)\b")
# "above the 3396.0 km sphere", "above the Mars 2000 areoid": the surface as the label names it
_ABOVE_SURFACE = re.compile(r"\bABOVE (THE [A-Z0-9 .,-]{0,40}?\b(AREOID|GEOID|SPHERE|ELLIPSOID))\b")


@dataclass(frozen=True)
class HeightReference:
    """The surface heights are measured from, and the radius removed to get there.

    `datum` completes "metres above ..."; `radius_removed_m` is the label's
    OFFSET (metres) when the product stores radii and the Extras subtract it.
    """

    datum: str
    radius_removed_m: float | None = None

    @property
    def phrase(self) -> str:
        return f"m above {self.datum}"


def radius_offset_m(label: Mapping[str, Any], offset_m: float) -> float | None:
    """The OFFSET (metres) when it equals the body radius of the label's map projection."""
    block = projection_object(label)
    if block is None or "A_AXIS_RADIUS" not in block or offset_m == 0.0:
        return None
    radius = block["A_AXIS_RADIUS"]
    value = getattr(radius, "value", radius)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    unit = str(getattr(radius, "units", "") or "KM").strip().upper()
    metres = float(value) * (1.0 if unit in ("M", "METER", "METERS", "METRE", "METRES") else 1000.0)
    return offset_m if math.isclose(offset_m, metres, rel_tol=0.0, abs_tol=RADIUS_MATCH_M) else None


def height_reference(label: Mapping[str, Any], image: Mapping[str, Any],
                     mission_datum: str | None, radius_removed_m: float | None,
                     given: str | None = None) -> HeightReference:
    """The datum of a DTM's heights (see the module docstring for the order). `given`: what the
    user says the heights are above (the Extras' vertical_datum)."""
    if radius_removed_m is not None:
        return HeightReference(f"the {radius_removed_m / 1000.0:g} km reference sphere",
                               radius_removed_m)
    if given:
        return HeightReference(given)
    words = " ".join(" ".join(str(source.get(k, "")).split()) for source in (image, label)
                     for k in ("DESCRIPTION", "NOTE")).upper()
    above = _ABOVE_SURFACE.search(words)
    if above is not None:
        surface = above.group(2)
        if mission_datum and surface in mission_datum.upper():  # the mission's wording of what the label says
            return HeightReference(mission_datum)
        if surface == "SPHERE" and re.search(r"\d", above.group(1)):  # "the 3396.0 km sphere"
            return HeightReference(above.group(1).lower())
    if mission_datum and any(word in words for word in _surface_words(mission_datum)):
        return HeightReference(mission_datum)
    if _AREOID_WORDS.search(words):
        return HeightReference(f"the {_target(label)} areoid".replace("the  ", "the "))
    if _GEOID_WORDS.search(words):
        return HeightReference("the geoid")
    return HeightReference(NOT_STATED)


def _surface_words(datum: str) -> tuple[str, ...]:
    """The kind of surface a mission's datum names (areoid, sphere, ellipsoid ...), as label words."""
    return tuple(word for word in ("AREOID", "GEOID", "SPHERE", "ELLIPSOID") if word in datum.upper())


def _target(label: Mapping[str, Any]) -> str:
    target = str(label.get("TARGET_NAME", "") or "").strip().title()
    return target if target and target.upper() not in ("N/A", "UNK") else ""



def mission_datum(mission: str, name: str) -> str | None:
    """The height datum the mission fixes for its DTM named NAME (missions/), if any."""
    if mission not in mission_names():
        return None
    datum = get_mission(mission).dtm_height_datum
    return datum(name) if datum is not None else None
