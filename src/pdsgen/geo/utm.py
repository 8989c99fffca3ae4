"""Universal Transverse Mercator: the grid's constants and zone arithmetic, defined once.

UTM is Transverse Mercator with scale factor 0.9996 on the central meridian of one of 60
zones 6 degrees wide (zone 1 centred on 177 W), false easting 500 km and, for the southern
hemisphere's grids, false northing 10,000 km (EPSG 16001-16060 north, 16101-16160 south).
"""

from __future__ import annotations

SCALE_FACTOR = 0.9996
FALSE_EASTING = 500000.0  # metres
FALSE_NORTHING_SOUTH = 10000000.0  # metres; the northern grids have none
ZONE_WIDTH = 6.0  # degrees of longitude
_FIRST_ZONE_WEST = -180.0  # zone 1 starts at 180 degrees west


def zone_central_meridian(zone: int) -> float:
    """Central meridian (degrees east, -177 .. 177) of a UTM zone 1 .. 60."""
    return zone * ZONE_WIDTH - (ZONE_WIDTH / 2.0 - _FIRST_ZONE_WEST)


def false_northing(south: bool) -> float:
    """False northing (metres) of a zone's northern or southern grid."""
    return FALSE_NORTHING_SOUTH if south else 0.0


def is_zone_central_meridian(longitude: float) -> bool:
    """A longitude (degrees east, -180 .. 180) on which some UTM zone is centred."""
    return (longitude - _FIRST_ZONE_WEST) % ZONE_WIDTH == ZONE_WIDTH / 2.0


def is_utm(scale_factor: float, center_latitude: float, center_longitude: float) -> bool:
    """A Transverse Mercator that is a UTM zone: scale 0.9996, origin on the equator, on a
    zone's central meridian."""
    return (abs(scale_factor - SCALE_FACTOR) < 1e-12 and center_latitude == 0.0
            and is_zone_central_meridian(center_longitude))
