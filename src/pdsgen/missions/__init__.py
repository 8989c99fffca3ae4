"""Missions: every fact about a mission in one module, and the registry of profiles.

`generic`, `hirise`, `hrsc`, `imars` and `hrsc-ax` are registered here; `register_mission`
adds another (see README "Adding a mission"). Writers, Extras and the validator
import mission facts from these modules and nowhere else.
"""

from __future__ import annotations

from . import generic, hirise, hrsc, hrsc_ax, imars
from .base import (
    DEFAULT_PROFILE,
    PRODUCT_KINDS,
    STANDARD_OPTIONS,
    ContextReference,
    LabelFacts,
    Mission,
    OptionUse,
    Pds4Facts,
    ProductIdRequest,
    ProductKind,
    detect_mission,
    get_mission,
    mission_names,
    register_mission,
    unregister_mission,
)

for _module in (generic, hirise, hrsc, imars, hrsc_ax):
    register_mission(_module.MISSION)

__all__ = [
    "DEFAULT_PROFILE",
    "PRODUCT_KINDS",
    "STANDARD_OPTIONS",
    "ContextReference",
    "LabelFacts",
    "Mission",
    "OptionUse",
    "Pds4Facts",
    "ProductIdRequest",
    "ProductKind",
    "detect_mission",
    "get_mission",
    "mission_names",
    "register_mission",
    "unregister_mission",
]
