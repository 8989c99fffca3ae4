"""The validator's Transverse Mercator: its own ellipsoidal formulas (Snyder 1987) against PROJ,
and the map rules on HRSC-AX DEM labels (offsets against bounds, scale factor folded in)."""

from __future__ import annotations

import re

import numpy as np
import pytest
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen import write_dtm
from pdsgen.validate import validate_paths
from pdsgen.validate.projection import TransverseMercator

from hrsc_ax_tiles import GEODETIC, dtm_group, map_group, tile_name, write_vicar

A, C = 6378140.0, 6356750.0


@pytest.mark.parametrize("lon0, lats, lons", [
    (15.0, [78.94, 78.0, 79.5, 60.0], [11.73, 12.0, 17.9, 14.0]),
    (9.0, [-33.0, 0.5, 48.0, 52.3], [7.0, 11.5, 9.0, 6.1]),
])
def test_formulas_agree_with_proj_within_a_millimetre(lon0, lats, lons):
    tm = TransverseMercator(A, C, 0.0, lon0)
    proj = CRS.from_proj4(f"+proj=tmerc +lat_0=0 +lon_0={lon0} +k=1 +x_0=0 +y_0=0 +a={A} +b={C} +units=m")
    x, y = tm.forward(lats, lons)
    px, py = warp_transform(CRS.from_proj4(GEODETIC), proj, lons, lats)
    assert np.abs(x - px).max() < 1e-3 and np.abs(y - py).max() < 1e-3
    lat, lon = tm.inverse(px, py)
    metres_per_degree = 111_000.0
    assert np.abs(lat - lats).max() * metres_per_degree < 1e-3
    assert (np.abs(lon - lons) * np.cos(np.radians(lats))).max() * metres_per_degree < 1e-3


def _dem(tmp_path):
    stored = np.arange(30 * 40, dtype=np.float32).reshape(30, 40)
    path = write_vicar(tmp_path / f"{tile_name(430, 8765, 30, 0.5)}.dsm", stored,
                       {"MAP": map_group(430000.0, 8765000.0, 0.5),
                        "DIGITAL_TERRAIN_MODEL": dtm_group(0.0, 1.0, 0.0, 2000.0)})
    return write_dtm(path, tmp_path / "out", profile="hrsc-ax").path


def _rules(path):
    return {(f.rule, f.severity) for f in validate_paths([path]).findings}


def test_hrsc_ax_dem_offsets_agree_with_its_bounds(tmp_path):
    rules = _rules(_dem(tmp_path))
    assert ("MAP-004", "info") in rules  # standard convention detected: the bounds were checked
    assert not {r for r, s in rules if s == "error"}
    assert ("MAP-009", "info") not in rules


@pytest.mark.parametrize("keys, shift, rule", [
    (("SAMPLE", "LINE"), 1.0, "MAP-005"),  # DLR's one-pixel-apart convention
    (("SAMPLE",), 7.0, "MAP-003"),  # offsets that place the image elsewhere than its bounds
])
def test_wrong_offsets_are_found(tmp_path, keys, shift, rule):
    path = _dem(tmp_path)
    data = path.read_bytes()
    for key in keys:
        head = data[:6000].decode("ascii", "replace")
        old = re.search(rf"{key}_PROJECTION_OFFSET\s+= (\d+\.\d+)", head).group(1)
        new = f"{float(old) + shift:.1f}"
        assert len(new) == len(old)
        data = data.replace(f"= {old} <PIXEL>".encode(), f"= {new} <PIXEL>".encode(), 1)
    path.write_bytes(data)
    assert rule in {r for r, _ in _rules(path)}
