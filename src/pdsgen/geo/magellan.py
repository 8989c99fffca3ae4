"""Magellan: what the Mosaicked Image Data Records' (MIDR) own map-projection catalog
defines and their framelet labels do not say.

The framelets' IMAGE_MAP_PROJECTION_CATALOG gives A_AXIS_RADIUS = 6051.92 km, but the data
set's catalog (DSMAPF.LBL for F-MIDRs, DSMAPC1.LBL for C1-MIDRs, same equations) defines the
sinusoidal grid as

    line   = SPECLINE - lat * SCALE + 1
    sample = PROJSAMP + (lon - PROJ_LON) * SCALE * cos(lat) + 0.5
    SCALE  = (2 * PI * 6051000) / (PIXSIZ * 360)        pixels per degree

with integral lines and samples at pixel centres (SPECLINE, PROJSAMP: the label's
X/Y_AXIS_PROJECTION_OFFSET). So the grid is on a sphere of 6051.0 km, and a sample centre
lies half a pixel further from the origin than the PDS3 standard convention puts it (lines
follow the standard). Read with the label's radius, an F-MIDR framelet 17 degrees from
the equator lands 3.5 pixels north of its label's own MINIMUM/MAXIMUM_LATITUDE; with the
catalog's equations the bounds of FF01 (F-MIDR.20S145) agree to 0.01 px in longitude and
0.34 px in latitude (tests/test_migrate.py).

Here in geo/, beside the offset conventions it departs from, and not in missions/: it is a
source data set's grid, no profile pdsgen writes (no Mission is registered for it), and its one
reader is label_georef.py, which missions/ (importing geo for MapGeometry and the projection
names) must not be imported by.
"""

from __future__ import annotations

MIDR_DATA_SET_PREFIX = "MGN-V-RDRS-5-MIDR"
MIDR_PROJECTION = "SINUSOIDAL"
MIDR_PROJECTION_RADIUS_M = 6051000.0  # the SCALE equation's radius, not A_AXIS_RADIUS
MIDR_SAMPLE_SHIFT = 0.5  # PROJSAMP minus the standard SAMPLE_PROJECTION_OFFSET, pixels


def is_midr_grid(data_set_id: str, projection_type: str) -> bool:
    """A Magellan MIDR's sinusoidal framelet grid, defined by the catalog equations above."""
    return (data_set_id.strip().upper().startswith(MIDR_DATA_SET_PREFIX)
            and projection_type.strip().upper() == MIDR_PROJECTION)
