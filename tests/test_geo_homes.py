"""geo/'s one-home facts checked against PROJ's own definitions, not against pdsgen.

- geo/utm.py's scale factor, false origin and zone meridians against PROJ's `+proj=utm`;
- a VICAR MAP group (formats/vicar.py reads it, geo/label_georef.py places it) of a southern
  and a west-positive tile, ground positions against PROJ's UTM zone;
- geo/conventions.py's wraps at their edges.
"""

from __future__ import annotations

import numpy as np
import pytest
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen.formats.vicar import read_map_group
from pdsgen.geo import utm
from pdsgen.geo.conventions import east_positive, unwrap_near, wrap_180, wrap_360
from pdsgen.geo.label_georef import vicar_map_georeferencing

WGS84_LONLAT = CRS.from_proj4("+proj=longlat +ellps=WGS84 +no_defs")


@pytest.mark.parametrize("zone", [1, 17, 33, 60])
@pytest.mark.parametrize("south", [False, True])
def test_utm_constants_are_proj_utm(zone, south):
    ours = CRS.from_proj4(f"+proj=tmerc +lat_0=0 +lon_0={utm.zone_central_meridian(zone)!r} "
                          f"+k={utm.SCALE_FACTOR!r} +x_0={utm.FALSE_EASTING!r} "
                          f"+y_0={utm.false_northing(south)!r} +ellps=WGS84 +units=m +no_defs")
    proj = CRS.from_proj4(f"+proj=utm +zone={zone} {'+south ' if south else ''}+ellps=WGS84 +units=m +no_defs")
    lon0 = zone * 6 - 183
    lons = [lon0 - 2.5, lon0, lon0 + 2.9]
    lats = [-40.0, -1.0, -60.0] if south else [1.0, 45.0, 70.0]
    a = np.array(warp_transform(WGS84_LONLAT, ours, lons, lats))
    b = np.array(warp_transform(WGS84_LONLAT, proj, lons, lats))
    assert np.abs(a - b).max() < 1e-6
    assert utm.is_zone_central_meridian(utm.zone_central_meridian(zone))
    assert utm.is_utm(0.9996, 0.0, utm.zone_central_meridian(zone))
    assert not utm.is_zone_central_meridian(utm.zone_central_meridian(zone) + 1.0)


def _group(east_m, north_m, pixel_m, lon0, direction="EAST"):
    """A MAP group written from the PDS3 standard convention's definition (docs section 4), on
    the WGS84 ellipsoid, UTM scale factor, no false origin stated."""
    return {
        "A_AXIS_RADIUS": 6378.137, "C_AXIS_RADIUS": 6356.752314245179,
        "CENTER_LATITUDE": 0.0, "CENTER_LONGITUDE": lon0, "POSITIVE_LONGITUDE_DIRECTION": direction,
        "LINE_PROJECTION_OFFSET": north_m / pixel_m - 0.5,
        "SAMPLE_PROJECTION_OFFSET": -(east_m - 500000.0) / pixel_m - 0.5,
        "MAP_PROJECTION_TYPE": "TRANSVERSE_MERCATOR", "MAP_SCALE": pixel_m / 1000.0, "SCALE_FACTOR": 0.9996,
    }


@pytest.mark.parametrize(("north_m", "lon0", "direction", "proj"), [
    (-200000.0, 15.0, "EAST", "+proj=utm +zone=33 +south"),  # south of the equator: the southern grid
    (5200000.0, 345.0, "WEST", "+proj=utm +zone=33"),  # 345 W is 15 E
    (5200000.0, -75.0, "EAST", "+proj=utm +zone=18"),
])
def test_vicar_map_group_lands_where_proj_utm_puts_it(tmp_path, north_m, lon0, direction, proj):
    east_m, pixel_m = 430000.0, 2.0
    crs, transform = vicar_map_georeferencing(read_map_group(_group(east_m, north_m, pixel_m, lon0, direction),
                                                             tmp_path / "tile.dsm"))
    reference = CRS.from_proj4(f"{proj} +ellps=WGS84 +units=m +no_defs")
    y_grid = north_m if north_m > 0 else north_m + 10000000.0
    cols, rows = np.array([0.5, 99.5, 0.5, 99.5]), np.array([0.5, 0.5, 99.5, 99.5])
    xs, ys = transform.c + cols * transform.a, transform.f + rows * transform.e
    lon, lat = warp_transform(crs, WGS84_LONLAT, list(xs), list(ys))
    ex, ey = warp_transform(WGS84_LONLAT, reference, lon, lat)
    assert np.hypot(np.array(ex) - (east_m + cols * pixel_m), np.array(ey) - (y_grid - rows * pixel_m)).max() < 1e-3


def test_longitude_wraps_at_their_edges():
    assert [wrap_360(v) for v in (-0.5, 0.0, 359.5, 360.0, 725.0)] == [359.5, 0.0, 359.5, 0.0, 5.0]
    assert [wrap_180(v) for v in (-180.0, 180.0, 190.0, -190.0, 540.0)] == [-180.0, -180.0, -170.0, 170.0, -180.0]
    assert np.array_equal(wrap_180(np.array([350.0, 10.0])), np.array([-10.0, 10.0]))
    assert unwrap_near(np.array([359.0, 1.0]), 0.0).tolist() == [-1.0, 1.0]
    assert east_positive(10.0, "WEST") == -10.0 and east_positive(10.0, " west ") == -10.0
    assert east_positive(10.0, "EAST") == 10.0 and east_positive(10.0, None) == 10.0
