"""Profile names and HiRISE naming helpers under their former import path.

The facts live in `pdsgen.missions` (one module per mission); this module only
re-exports the names callers already use.
"""

from __future__ import annotations

from .geo.geometry import MapGeometry
from .missions import ProductIdRequest, get_mission, mission_names
from .missions.base import Mission
from .missions.generic import check_product_id, generic_product_id
from .missions.hirise import SCALE_LETTERS as HIRISE_SCALE_LETTERS
from .missions.hirise import dtm_product_id as _hirise_dtm_product_id
from .missions.hirise import observation_code as hirise_observation_code
from .missions.hirise import ortho_id as hirise_ortho_product_id
from .missions.hirise import scale_letter as hirise_scale_letter
from .missions.hirise import version_code as hirise_version_code

Profile = Mission
get_profile = get_mission


def profile_names() -> list[str]:
    """The registered profile names, sorted (the CLI's --profile choices)."""
    return sorted(mission_names())


def hirise_dtm_product_id(
    geometry: MapGeometry, source_ids: list[str], institution: str | None, version: str
) -> str:
    """The HiRISE DTM product ID (see `pdsgen.missions.hirise.dtm_product_id`)."""
    return _hirise_dtm_product_id(ProductIdRequest("", geometry, source_ids, institution, version))


__all__ = [
    "HIRISE_SCALE_LETTERS",
    "Profile",
    "check_product_id",
    "generic_product_id",
    "get_profile",
    "hirise_dtm_product_id",
    "hirise_observation_code",
    "hirise_ortho_product_id",
    "hirise_scale_letter",
    "hirise_version_code",
    "profile_names",
]
