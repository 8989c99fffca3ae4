"""True ground scale and north from the CRS, checked against the projection formulas."""

from __future__ import annotations

import math

import pytest
from rasterio.crs import CRS
from rasterio.transform import from_origin

from pdsgen.extras.ground_scale import ground_scale_at
from test_extras_helpers import MARS_EQC, MARS_NORTH_POLAR

R_EQ = 3396190.0


def equirectangular(standard_parallel: float) -> CRS:
    return CRS.from_wkt(MARS_EQC.replace('"standard_parallel_1",0',
                                         f'"standard_parallel_1",{standard_parallel}'))


@pytest.mark.parametrize("lat_ts, lat", [(0.0, 0.0), (0.0, 60.0), (-5.0, -9.5), (30.0, 10.0)])
def test_equirectangular_east_west_scale_is_map_scale_times_cos_ratio(lat_ts, lat):
    crs = equirectangular(lat_ts)
    s = 25.0
    y_centre = R_EQ * math.radians(lat)
    transform = from_origin(0.0, y_centre + 50 * s, s, s)
    scale = ground_scale_at(crs, transform, 50.0, 50.0)
    expected = s * math.cos(math.radians(lat)) / math.cos(math.radians(lat_ts))
    assert scale.metres_per_column == pytest.approx(expected, rel=1e-6)
    assert scale.metres_per_row == pytest.approx(s, rel=1e-6)
    assert scale.north_deg == pytest.approx(0.0, abs=1e-6)
    assert scale.latitude == pytest.approx(lat, abs=1e-6)


def test_polar_stereographic_north_points_to_the_pole_not_up():
    crs = CRS.from_wkt(MARS_NORTH_POLAR)
    # A tile east of the pole (x > 0, y = 0 at its centre): the pole lies to the left.
    transform = from_origin(200000.0 - 50 * 10.0, 50 * 10.0, 10.0, 10.0)
    scale = ground_scale_at(crs, transform, 50.0, 50.0)
    assert scale.north_deg == pytest.approx(270.0, abs=1e-3)
    # South of the pole in the image (below it): north is up; above it: north is down.
    below = from_origin(-500.0, -200000.0 + 500.0, 10.0, 10.0)
    above = from_origin(-500.0, 200000.0 + 500.0, 10.0, 10.0)
    assert ground_scale_at(crs, below, 50.0, 50.0).north_deg == pytest.approx(0.0, abs=1e-3)
    assert ground_scale_at(crs, above, 50.0, 50.0).north_deg == pytest.approx(180.0, abs=1e-3)


def test_polar_stereographic_scale_grows_away_from_the_pole():
    crs = CRS.from_wkt(MARS_NORTH_POLAR)
    r = 3376200.0
    rho = 1000000.0
    transform = from_origin(rho - 500.0, 500.0, 10.0, 10.0)
    scale = ground_scale_at(crs, transform, 50.0, 50.0)
    # Scale factor of the polar stereographic sphere at distance rho: 1 + (rho/2R)^2.
    k = 1.0 + (rho / (2 * r)) ** 2
    assert scale.metres_per_column == pytest.approx(10.0 / k, rel=1e-4)
    assert scale.metres_per_row == pytest.approx(10.0 / k, rel=1e-4)


def test_geographic_degrees_grid():
    crs = CRS.from_proj4("+proj=longlat +a=3396190 +b=3396190 +no_defs +type=crs")
    transform = from_origin(10.0, 46.0, 0.01, 0.01)  # centre at latitude 45.5 deg
    scale = ground_scale_at(crs, transform, 50.0, 50.0)
    one_degree = R_EQ * math.pi / 180.0
    assert scale.metres_per_row == pytest.approx(0.01 * one_degree, rel=1e-6)
    assert scale.metres_per_column == pytest.approx(
        0.01 * one_degree * math.cos(math.radians(45.5)), rel=1e-5)
