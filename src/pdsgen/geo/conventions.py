"""The PDS3 map-projection conventions, defined once for the writers.

PDS3 Standards Reference chapter 4 (pds3-products.md): SAMPLE/LINE_PROJECTION_OFFSET
are the sample and line of the projection origin counted from the centre of the
first pixel, so for a grid whose upper-left corner is (ULX, ULY) in projection
metres (from the natural origin) and MAP_SCALE s metres per pixel:

    SAMPLE_PROJECTION_OFFSET = -ULX / s - 0.5
    LINE_PROJECTION_OFFSET   =  ULY / s - 0.5

MAP_RESOLUTION (pixels per degree) is the number of pixels in one degree of a
great circle of the label's radius: (pi * R / 180) / s.

The validator checks labels with its own closed-form formulas (a check must not
share the computation it checks); HRSC's older one-pixel-apart convention is the
validator's to recognise.

Longitudes: the one place where they are wrapped and turned east-positive. pdsgen's labels,
CRSs and pages state longitudes east-positive (PROJ's sense; PDS3 labels written by pdsgen say
POSITIVE_LONGITUDE_DIRECTION = EAST). Labels read from archives may count them west-positive;
`east_positive` turns such a value round. Bounds and keywords are stated in [0, 360)
(`wrap_360`, docs section 4), a projection's central meridian in [-180, 180) as PROJ takes it
(`wrap_180`). The same functions take numpy arrays; an azimuth is wrapped to [0, 360) the same
way. The validator keeps its own wraps: a check must not share the arithmetic it checks.
"""

from __future__ import annotations

import math
from typing import Any, TypeVar

PIXEL_CENTRE = 0.5  # the offsets count from the centre of the first pixel, half a pixel in


def projection_offsets(ulx: float, uly: float, scale: float) -> tuple[float, float]:
    """(SAMPLE_PROJECTION_OFFSET, LINE_PROJECTION_OFFSET) of a grid's upper-left corner."""
    return -ulx / scale - PIXEL_CENTRE, uly / scale - PIXEL_CENTRE


def upper_left_corner(sample_offset: float, line_offset: float, scale: float) -> tuple[float, float]:
    """(ULX, ULY), projection metres of a grid's upper-left corner, from its offsets: the inverse
    of projection_offsets, for readers of labels and headers in the standard convention."""
    return -(sample_offset + PIXEL_CENTRE) * scale, (line_offset + PIXEL_CENTRE) * scale


def map_resolution(radius_m: float, scale: float) -> float:
    """MAP_RESOLUTION (pixels per degree) for a radius in metres and MAP_SCALE in metres per pixel."""
    return (math.pi * radius_m / 180.0) / scale


# -- longitudes ------------------------------------------------------------------------------
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
