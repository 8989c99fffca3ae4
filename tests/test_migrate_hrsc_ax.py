"""`pdsgen migrate` of HRSC-AX products made PDS3-only: Transverse Mercator labels.

The tiles are written by the tests' own VICAR writer (tests/hrsc_ax_tiles.py) as the HRSC-AX
image description defines the MAP group (Table B2), UTM zone 33 north with SCALE_FACTOR
0.9996. References from outside pdsgen: PROJ placing the corner and centre pixels straight
from the tile's header numbers, and GDAL's PDS4 driver reading the migrated cart: grid; the
shipped XSD and Schematron. The migrated cart: is also compared with the one pdsgen's own
`--label both` writes for the same tile (they must state the same grid).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pvl
import pytest
import rasterio
from affine import Affine
from lxml import etree
from rasterio.crs import CRS

from pdsgen.geo.label_georef import label_georeferencing, transverse_mercator_grid
from pdsgen.migrate import migrate_product
from pdsgen.validate import validate_paths
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.label_checks import validate_pds4
from test_hrsc_ax_offsets import _ground_m, _header_grid_positions, _make, _tiles

from hrsc_ax_tiles import K0

NS = {"cart": "http://pds.nasa.gov/pds4/cart/v1"}
KINDS = ("DEM", "PAN")
CART_NUMBERS = ("scale_factor_at_central_meridian", "longitude_of_central_meridian",
                "latitude_of_projection_origin", "pixel_resolution_x", "pixel_resolution_y",
                "upperleft_corner_x", "upperleft_corner_y", "a_axis_radius", "c_axis_radius",
                "west_bounding_coordinate", "east_bounding_coordinate",
                "north_bounding_coordinate", "south_bounding_coordinate")


@pytest.fixture(scope="module", params=KINDS)
def made(request, tmp_path_factory):
    """(kind, tile MAP group, PDS3-only product's label, its migrated PDS4 label, --label both's PDS4 label)."""
    kind = request.param
    root = tmp_path_factory.mktemp(f"hrsc_ax_{kind}")
    products = {}
    for dialect in ("pds3", "both"):
        (root / f"tiles_{dialect}").mkdir()
        paths, group = _tiles(root / f"tiles_{dialect}", kind, K0)
        products[dialect], _ = _make(paths, kind, root / dialect, dialect)
    pds3 = products["pds3"]
    label = pds3.path if kind == "DEM" else pds3.label_path
    migrated = migrate_product(label, root / "migrated", bundle_lid="urn:nasa:pds:pdsgen_migrate_test")
    return kind, group, label, migrated.label_path, products["both"].pds4_label_path


def _cart(label: Path) -> dict[str, float]:
    root = etree.parse(str(label)).getroot()
    return {name: float(root.findtext(f".//cart:{name}", namespaces=NS)) for name in CART_NUMBERS}


def _cart_grid(cart: dict[str, float]) -> tuple[CRS, Affine]:
    """The grid the cart: values state, built with PROJ from those values alone."""
    crs = CRS.from_proj4(f"+proj=tmerc +lat_0={cart['latitude_of_projection_origin']} "
                         f"+lon_0={cart['longitude_of_central_meridian']} "
                         f"+k={cart['scale_factor_at_central_meridian']} +x_0=0 +y_0=0 "
                         f"+a={cart['a_axis_radius']} +b={cart['c_axis_radius']} +units=m +no_defs")
    size = cart["pixel_resolution_x"]
    assert cart["pixel_resolution_y"] == size
    return crs, Affine(size, 0.0, cart["upperleft_corner_x"], 0.0, -size, cart["upperleft_corner_y"])


def _scale_factor(crs: CRS) -> float:
    params = crs.to_dict()
    return float(params.get("k", params.get("k_0", 1.0)))


def test_migrated_cart_places_corners_and_centre_where_proj_places_the_tile(made):
    kind, group, _, migrated, _ = made
    expected = _header_grid_positions(group)
    stated = _ground_m(*_cart_grid(_cart(migrated)))
    assert np.abs(stated - expected).max() < 0.01  # metres
    if kind == "PAN":  # GDAL 3.6's PDS4 driver opens no label whose array is in a JP2
        return
    with rasterio.open(migrated) as pds4:  # GDAL's PDS4 driver reads the cart: grid
        assert np.abs(_ground_m(pds4.crs, pds4.transform) - expected).max() < 0.01


def test_migrated_cart_states_the_true_grid_as_label_both_does(made):
    _, _, _, migrated, both = made
    ours, theirs = _cart(migrated), _cart(both)
    assert ours["scale_factor_at_central_meridian"] == K0
    for name in CART_NUMBERS:
        assert ours[name] == pytest.approx(theirs[name], rel=1e-12, abs=1e-9), name


@pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")
def test_migrated_label_is_schema_schematron_and_validator_clean(made):
    migrated = made[3]
    assert validate_pds4(migrated) == []
    report = validate_paths([migrated])
    assert [f for f in report.findings if f.severity in ("error", "warning")] == []


def test_label_alone_places_the_grid_folded_and_unfolded(made):
    """The Extras' reading (a pvl label, no text): scale factor 1 and the folded MAP_SCALE; with the
    label's text, the true grid pdsgen's writer states in its comment. Both on the same ground."""
    _, group, label, _, _ = made
    text = label.read_bytes().decode("latin-1")
    parsed = pvl.loads(text[: text.index("\r\nEND\r\n") + 7])
    expected = _header_grid_positions(group)
    folded = label_georeferencing(parsed)
    unfolded = label_georeferencing(parsed, text)
    assert folded is not None and unfolded is not None
    assert _scale_factor(folded[0]) == 1.0
    # unfolded: the tile's own UTM grid, its corner where the tile's name puts it (430 km E, 8,765 km N)
    assert unfolded[0].to_dict().get("proj") == "utm" or _scale_factor(unfolded[0]) == K0
    assert unfolded[1].a == pytest.approx(group["MAP_SCALE"] * 1000.0, rel=1e-12)
    assert (unfolded[1].c, unfolded[1].f) == pytest.approx((430000.0, 8765000.0), abs=1e-6)
    for crs, transform in (folded, unfolded):
        assert np.abs(_ground_m(crs, transform) - expected).max() < 0.01
    grid = transverse_mercator_grid(text)
    assert grid is not None and (grid.scale_factor, grid.false_easting, grid.false_northing) == (K0, 500000.0, 0.0)
