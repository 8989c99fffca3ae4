"""Longitudes: the one place where they are wrapped and turned east-positive.

pdsgen's labels, CRSs and pages state longitudes east-positive (PROJ's sense; PDS3
labels written by pdsgen say POSITIVE_LONGITUDE_DIRECTION = EAST). Labels read from
archives may count them west-positive; `east_positive` turns such a value round.
Bounds and keywords are stated in [0, 360) (`wrap_360`, docs section 4), a projection's
central meridian in [-180, 180) as PROJ takes it (`wrap_180`). The same functions take
numpy arrays. An azimuth is wrapped to [0, 360) the same way.

The validator keeps its own wraps: a check must not share the arithmetic it checks.
"""

from __future__ import annotations

from typing import Any, TypeVar

Angle = TypeVar("Angle", float, Any)  # a float or a numpy array of degrees

EAST = "EAST"
WEST = "WEST"
FULL_TURN = 360.0
HALF_TURN = 180.0


def wrap_360(degrees: Angle) -> Angle:
    """A longitude (or azimuth) into [0, 360)."""
    return degrees % FULL_TURN


def wrap_180(degrees: Angle) -> Angle:
    """A longitude, or a difference of two, into [-180, 180)."""
    return (degrees + HALF_TURN) % FULL_TURN - HALF_TURN


def unwrap_near(degrees: Angle, reference: float) -> Angle:
    """Longitudes moved by whole turns to lie within half a turn of `reference`."""
    return reference + (degrees - reference + HALF_TURN) % FULL_TURN - HALF_TURN


def is_positive_west(direction: object) -> bool:
    """True when a label's POSITIVE_LONGITUDE_DIRECTION says WEST (EAST when absent)."""
    return str(direction if direction is not None else EAST).strip().upper() == WEST


def east_positive(longitude: Angle, direction: object) -> Angle:
    """A label's longitude in the east-positive sense, given its POSITIVE_LONGITUDE_DIRECTION."""
    return -longitude if is_positive_west(direction) else longitude
