"""What a DTM's numbers are heights above: the datum the legends and README.TXT state.

A height means nothing without its reference surface, and archives use several:
HiRISE DTMs give heights above the Mars 2000 areoid, HRSC DT4 above the 3396.0 km
sphere, HRSC DA4 above the areoid, MOLA MEGDR topography above the areoid. Some
products store planetary radii instead: a LOLA LDEM label says
`radius = DN * SCALING_FACTOR + OFFSET` with OFFSET the body's reference radius
(1737400 m, equal to A_AXIS_RADIUS). Shown as they are, those would read
"Elevation 1,740,000 m"; when OFFSET equals the label's radius the Extras leave it
out and show heights above that sphere, and say so.

The datum is found, in this order: the radius rule above; the mission's convention
(from the mission module); words of the label's IMAGE description or note
("areoid", "geoid", "sphere"); otherwise the legends say the label names none.
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
                     mission_datum: str | None, radius_removed_m: float | None) -> HeightReference:
    """The datum of a DTM's heights (see the module docstring for the order)."""
    if radius_removed_m is not None:
        return HeightReference(f"the {radius_removed_m / 1000.0:g} km reference sphere",
                               radius_removed_m)
    if mission_datum:
        return HeightReference(mission_datum)
    words = " ".join(str(source.get(k, "")) for source in (image, label)
                     for k in ("DESCRIPTION", "NOTE")).upper()
    if _AREOID_WORDS.search(words):
        return HeightReference(f"the {_target(label)} areoid".replace("the  ", "the "))
    if _GEOID_WORDS.search(words):
        return HeightReference("the geoid")
    return HeightReference(NOT_STATED)


def _target(label: Mapping[str, Any]) -> str:
    target = str(label.get("TARGET_NAME", "") or "").strip().title()
    return target if target and target.upper() not in ("N/A", "UNK") else ""



def mission_datum(mission: str, name: str) -> str | None:
    """The height datum the mission fixes for its DTM named NAME (missions/), if any."""
    if mission not in mission_names():
        return None
    datum = get_mission(mission).dtm_height_datum
    return datum(name) if datum is not None else None
