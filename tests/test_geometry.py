"""Map keywords from CRS + geotransform, checked against the sphere formulas."""

from __future__ import annotations

import math

import pytest
from affine import Affine
from rasterio.crs import CRS

from pdsgen.errors import PdsgenError
from pdsgen.geo.geometry import describe_geometry

R = 3396190.0


def _polar(lat0: float) -> CRS:
    return CRS.from_proj4(f"+proj=stere +lat_0={lat0} +lon_0=0 +k=1 +R={R} +units=m")


def test_south_polar_product_containing_the_pole():
    geometry = describe_geometry(_polar(-90), Affine(10.0, 0, -5000.0, 0, -10.0, 5000.0), 1000, 1000)
    assert geometry.minimum_latitude == -90.0
    assert (geometry.westernmost_longitude, geometry.easternmost_longitude) == (0.0, 360.0)
    corner_rho = math.hypot(5000.0, 5000.0)
    assert geometry.maximum_latitude == pytest.approx(-90 + 2 * math.degrees(math.atan(corner_rho / (2 * R))),
                                                      abs=1e-9)
    assert geometry.center_latitude == -90.0
    assert geometry.map_resolution == pytest.approx(math.pi * R / 180 / 10.0, rel=1e-14)


def test_north_azimuth_points_to_the_pole_in_the_north_and_away_in_the_south():
    # Image centred on the +x axis (longitude 90 E): the pole lies to the left (west in image terms).
    transform = Affine(1.0, 0, 100000.0, 0, -1.0, 50.0)
    north = describe_geometry(_polar(90), transform, 100, 100)
    south = describe_geometry(_polar(-90), transform, 100, 100)
    assert north.north_azimuth == pytest.approx(180.0, abs=0.1)  # toward the pole: image left
    assert south.north_azimuth == pytest.approx(0.0, abs=0.1) or south.north_azimuth == pytest.approx(360.0, abs=0.1)


def test_longitudes_across_the_prime_meridian_wrap_into_0_360():
    crs = CRS.from_proj4(f"+proj=eqc +lat_ts=0 +lon_0=0 +R={R} +units=m")
    geometry = describe_geometry(crs, Affine(100.0, 0, -50000.0, 0, -100.0, 0.0), 1000, 10)
    assert geometry.westernmost_longitude == pytest.approx(360 - math.degrees(50000.0 / R), abs=1e-9)
    assert geometry.easternmost_longitude == pytest.approx(math.degrees(50000.0 / R), abs=1e-9)


def test_ellipsoid_radii_and_planetocentric_bounds():
    a, b = 3396190.0, 3376200.0
    crs = CRS.from_proj4(f"+proj=eqc +lat_ts=0 +lon_0=0 +a={a} +b={b} +units=m")
    geometry = describe_geometry(crs, Affine(100.0, 0, 0.0, 0, -100.0, 2000000.0), 10, 10)
    assert (geometry.a_axis_km, geometry.b_axis_km, geometry.c_axis_km) == (3396.19, 3396.19, 3376.2)
    assert not geometry.is_sphere


@pytest.mark.parametrize(
    ("transform", "message"),
    [
        (Affine(1.0, 0.1, 0, 0, -1.0, 0), "rotated"),
        (Affine(1.0, 0, 0, 0, 1.0, 0), "north-up"),
        (Affine(1.0, 0, 0, 0, -2.0, 0), "not square"),
    ],
)
def test_unrepresentable_grids_are_refused(transform, message):
    crs = CRS.from_proj4(f"+proj=eqc +lat_ts=0 +lon_0=0 +R={R} +units=m")
    with pytest.raises(PdsgenError, match=message):
        describe_geometry(crs, transform, 10, 10)


def test_polar_stereographic_true_scale_away_from_pole_is_refused():
    crs = CRS.from_proj4(f"+proj=stere +lat_0=-90 +lat_ts=-71 +lon_0=0 +R={R} +units=m")
    with pytest.raises(PdsgenError, match="true scale away from the pole"):
        describe_geometry(crs, Affine(1.0, 0, 0, 0, -1.0, 0), 10, 10)


def test_target_name_from_the_crs():
    iau = CRS.from_user_input("IAU_2015:49910")
    assert describe_geometry(iau, Affine(1.0, 0, 0, 0, -1.0, 0), 10, 10).target_name == "MARS"
    plain = CRS.from_proj4(f"+proj=eqc +R={R} +units=m")
    assert describe_geometry(plain, Affine(1.0, 0, 0, 0, -1.0, 0), 10, 10).target_name == "MARS"
    earth_ellipsoid = CRS.from_proj4("+proj=eqc +a=6378140 +b=6356750 +units=m")  # HRSC-AX
    assert describe_geometry(earth_ellipsoid, Affine(1.0, 0, 0, 0, -1.0, 0), 10, 10).target_name == "EARTH"
    nothing = CRS.from_proj4("+proj=eqc +R=100000 +units=m")
    assert describe_geometry(nothing, Affine(1.0, 0, 0, 0, -1.0, 0), 10, 10).target_name is None
