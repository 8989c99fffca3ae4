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
"""

from __future__ import annotations

import math

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
