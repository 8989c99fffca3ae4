"""The label's MINIMUM/MAXIMUM_LATITUDE, WESTERNMOST/EASTERNMOST_LONGITUDE against the grid's own
extent (issue 39): longitudes compare as angles (-180..180 and 0..360 alike, a grid across the
prime meridian), in the label's positive direction; half a pixel is the tolerance; where they
disagree, a warning names each bound and cart:Bounding_Coordinates states the grid's extent.

The labels are made here (each a one-pixel-per-degree equirectangular grid of Mars, 20 x 10
pixels from 10 W to 10 E and 5 S to 5 N); the grid's extent the cart: must state is computed
here from the label's own offsets, not by pdsgen."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from lxml import etree

from pdsgen.migrate.product import migrate_products

CART = {"cart": "http://pds.nasa.gov/pds4/cart/v1"}
SAMPLE_OFFSET, LINE_OFFSET, PIXELS_PER_DEGREE = 9.5, 4.5, 1.0
# The grid's edges: the offsets count from the first pixel's centre (PDS3 standard convention).
GRID_WEST = -(SAMPLE_OFFSET + 0.5) / PIXELS_PER_DEGREE % 360.0  # 350
GRID_EAST = (20 - SAMPLE_OFFSET - 0.5) / PIXELS_PER_DEGREE  # 10
GRID_NORTH = (LINE_OFFSET + 0.5) / PIXELS_PER_DEGREE  # 5
GRID_SOUTH = GRID_NORTH - 10 / PIXELS_PER_DEGREE  # -5


def _label(west: float, east: float, direction: str = "EAST", south: float = -5.0) -> str:
    return f"""PDS_VERSION_ID = PDS3
RECORD_TYPE = FIXED_LENGTH
RECORD_BYTES = 20
FILE_RECORDS = 10
^IMAGE = "grid.img"
PRODUCT_ID = "GRID"
TARGET_NAME = MARS
OBJECT = IMAGE
  LINES = 10
  LINE_SAMPLES = 20
  SAMPLE_TYPE = UNSIGNED_INTEGER
  SAMPLE_BITS = 8
END_OBJECT = IMAGE
OBJECT = IMAGE_MAP_PROJECTION
  MAP_PROJECTION_TYPE = "SIMPLE CYLINDRICAL"
  A_AXIS_RADIUS = 3396.0 <KM>
  B_AXIS_RADIUS = 3396.0 <KM>
  C_AXIS_RADIUS = 3376.2 <KM>
  POSITIVE_LONGITUDE_DIRECTION = {direction}
  CENTER_LATITUDE = 0.0 <DEG>
  CENTER_LONGITUDE = 0.0 <DEG>
  MAP_SCALE = {math.pi * 3396.0 / 180.0 / PIXELS_PER_DEGREE!r} <KM/PIXEL>
  MAP_RESOLUTION = {PIXELS_PER_DEGREE} <PIX/DEG>
  LINE_PROJECTION_OFFSET = {LINE_OFFSET} <PIXEL>
  SAMPLE_PROJECTION_OFFSET = {SAMPLE_OFFSET} <PIXEL>
  MINIMUM_LATITUDE = {south} <DEG>
  MAXIMUM_LATITUDE = 5.0 <DEG>
  WESTERNMOST_LONGITUDE = {west} <DEG>
  EASTERNMOST_LONGITUDE = {east} <DEG>
END_OBJECT = IMAGE_MAP_PROJECTION
END
"""


def _migrate(tmp_path: Path, text: str):
    (tmp_path / "grid.lbl").write_text(text)
    (tmp_path / "grid.img").write_bytes(bytes(200))
    run = migrate_products([tmp_path / "grid.lbl"], tmp_path / "out", bundle_lid="urn:nasa:pds:bounds_test")
    assert not run.refused, run.refused
    root = etree.parse(str(tmp_path / "out" / "grid.xml"))
    bounds = tuple(float(root.findtext(f".//cart:{side}_bounding_coordinate", namespaces=CART))
                   for side in ("west", "east", "north", "south"))
    assert bounds == pytest.approx((GRID_WEST, GRID_EAST, GRID_NORTH, GRID_SOUTH), abs=1e-9)
    return run.warnings


@pytest.mark.parametrize(("west", "east", "direction"), [
    (-10.0, 10.0, "EAST"),  # -180..180
    (350.0, 10.0, "EAST"),  # 0..360
    (350.4, 10.4, "EAST"),  # within half a pixel
    (10.0, 350.0, "WEST"),  # west-positive: the westernmost is 10 W
    (10.0, -10.0, "WEST"),
])
def test_bounds_that_agree_with_the_grid_in_any_form_are_no_warning(tmp_path, west, east, direction):
    assert _migrate(tmp_path, _label(west, east, direction)) == ()


def test_a_bound_more_than_half_a_pixel_off_is_a_warning(tmp_path):
    (warning,) = _migrate(tmp_path, _label(340.0, 10.0, south=-5.6))
    assert warning == (f"{tmp_path / 'grid.lbl'}: OBJECT = IMAGE_MAP_PROJECTION: the label's bounds disagree with "
                       "the grid's extent by more than half a pixel (MINIMUM_LATITUDE = -5.6 (grid: -5); "
                       "WESTERNMOST_LONGITUDE = 340.0 (340 east; grid: 350 east)): "
                       "cart:Bounding_Coordinates follows the grid")


def test_west_positive_bounds_given_the_other_way_round_are_said_so(tmp_path):
    (warning,) = _migrate(tmp_path, _label(350.0, 10.0, "WEST"))
    assert ("WESTERNMOST_LONGITUDE = 350.0 (10 east; grid: 350 east); EASTERNMOST_LONGITUDE = 10.0 (350 east; "
            "grid: 10 east); the two longitudes are the grid's edges swapped: WESTERNMOST_LONGITUDE is its eastern "
            "edge (west longitudes given as minimum and maximum)") in warning


def test_a_radius_the_label_does_not_state_is_said_to_be_the_grids_sphere(tmp_path):
    text = _label(350.0, 10.0).replace("  C_AXIS_RADIUS = 3376.2 <KM>\n", "")
    (warning,) = _migrate(tmp_path, text)
    assert warning == (f"{tmp_path / 'grid.lbl'}: OBJECT = IMAGE_MAP_PROJECTION states no usable C_AXIS_RADIUS: "
                       "cart:c_axis_radius is that of the sphere its grid is computed on (A_AXIS_RADIUS, "
                       "C_AXIS_RADIUS for polar stereographic)")
    radius = etree.parse(str(tmp_path / "out" / "grid.xml")).findtext(".//cart:c_axis_radius", namespaces=CART)
    assert float(radius) == 3396000.0


def test_radii_the_label_states_are_written(tmp_path):
    assert _migrate(tmp_path, _label(350.0, 10.0)) == ()
    root = etree.parse(str(tmp_path / "out" / "grid.xml"))
    assert [float(root.findtext(f".//cart:{axis}_axis_radius", namespaces=CART)) for axis in "abc"] == \
        [3396000.0, 3396000.0, 3376200.0]
