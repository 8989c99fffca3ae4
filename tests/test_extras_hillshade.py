"""Shaded relief: lighting direction, flat-ground value and holes without fake cliffs."""

from __future__ import annotations

import math

import numpy as np

from pdsgen.extras.hillshade import hillshade


def plane(slope_east: float, slope_north: float, n: int = 32) -> np.ma.MaskedArray:
    rows, cols = np.mgrid[0:n, 0:n].astype(np.float32)
    # rows grow southwards, so height rising north means falling with row number
    return np.ma.MaskedArray(slope_east * cols - slope_north * rows)


def test_plane_tilted_towards_the_light_is_brighter_than_one_tilted_away():
    # Light from the north-west (azimuth 315): a surface facing north-west rises to
    # the south-east; the opposite plane faces away from the light.
    towards = hillshade(plane(0.5, -0.5), 1.0, 1.0, azimuth=315.0, altitude=45.0)
    away = hillshade(plane(-0.5, 0.5), 1.0, 1.0, azimuth=315.0, altitude=45.0)
    assert towards[16, 16] > math.sin(math.radians(45.0)) > away[16, 16]
    assert float(towards.mean()) > float(away.mean()) + 0.3


def test_lighting_follows_the_azimuth_option():
    facing_east = plane(-0.5, 0.0)  # falls towards the east: faces east
    lit_from_east = hillshade(facing_east, 1.0, 1.0, azimuth=90.0, altitude=45.0)
    lit_from_west = hillshade(facing_east, 1.0, 1.0, azimuth=270.0, altitude=45.0)
    assert lit_from_east[5, 5] > lit_from_west[5, 5]


def test_flat_ground_has_the_sine_of_the_light_altitude():
    shade = hillshade(plane(0.0, 0.0), 1.0, 1.0, altitude=30.0)
    assert np.allclose(shade, 0.5, atol=1e-6)


def test_ground_spacing_acts_as_the_z_factor():
    steep = hillshade(plane(-1.0, 0.0), 1.0, 1.0, azimuth=270.0)
    gentle = hillshade(plane(-1.0, 0.0), 10.0, 10.0, azimuth=270.0)
    flat = math.sin(math.radians(45.0))
    assert abs(float(gentle[8, 8]) - flat) < abs(float(steep[8, 8]) - flat)


def test_missing_data_casts_no_cliff_and_stays_masked():
    z = np.full((40, 40), -4000.0, dtype=np.float32)
    z[15:25, 15:25] = -3.4028226550889045e38  # the ISIS NULL, as a DTM holds it
    dem = np.ma.MaskedArray(z, mask=z < -1e30)
    shade = hillshade(dem, 1.0, 1.0)
    flat = math.sin(math.radians(45.0))
    assert np.ma.getmaskarray(shade)[15:25, 15:25].all()
    assert np.allclose(shade.compressed(), flat, atol=1e-6)  # the rim is as flat as the plain
