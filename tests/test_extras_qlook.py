"""QLOOK.JP2: full-scale, lossy, stretched like the browse, georeferenced like the product."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio

from pdsgen.extras import make_extras
from pdsgen.extras.product_source import open_product
from pdsgen.extras.qlook import write_qlook
from pdsgen.extras.stretch import Stretch
from pdsgen.products import ortho
from test_extras_helpers import write_geotiff


def scene(bands: int, lines: int = 700, samples: int = 900) -> np.ndarray:
    """Textured I/F (so a lossless code stream cannot shrink it much), NaN outside."""
    rng = np.random.default_rng(7)
    rows, cols = np.mgrid[0:lines, 0:samples]
    layers = [0.05 + 0.04 * (b + 1) * (1 + np.sin(cols / (17.0 + 9 * b)) * np.cos(rows / 23.0))
              + rng.normal(0, 0.004, (lines, samples)) for b in range(bands)]
    data = np.stack(layers).astype(np.float32)
    data[:, :, :50] = np.nan
    return data if bands > 1 else data[0]


@pytest.mark.parametrize("bands", [1, 3])
def test_qlook_of_a_pdsgen_orthoimage(tmp_path: Path, bands: int):
    tif = write_geotiff(tmp_path / "in.tif", scene(bands), nodata=float("nan"))
    product = ortho.write_ortho(tif, tmp_path / "p", product_id=f"QL_{bands}")
    out = tmp_path / "extras"
    make_extras([product.label_path], out, browse_width=300)
    qlook = out / f"QL_{bands}.QLOOK.JP2"
    with rasterio.open(product.jp2_path) as full, rasterio.open(qlook) as ql:
        assert ql.driver == "JP2OpenJPEG" and ql.dtypes[0] == "uint8"
        assert (ql.width, ql.height, ql.count) == (full.width, full.height, bands)
        assert ql.crs == full.crs and ql.transform.almost_equals(full.transform)
        data = ql.read()
    assert qlook.stat().st_size < 0.25 * product.jp2_path.stat().st_size
    assert data[:, :, :45].max() <= 25                        # no data: black (lossy edge)
    inside = data[:, :, 80:]
    for band in inside:                                       # each band stretched on its own
        assert np.percentile(band, 1) < 60 and np.percentile(band, 99) > 190
    # The same stretch as the browse: reduced, the quick look matches it.
    with rasterio.open(out / f"QL_{bands}.browse.jpg") as browse:
        shown = browse.read().astype(float)
    with rasterio.open(qlook) as ql:
        reduced = ql.read(out_shape=shown.shape, resampling=rasterio.enums.Resampling.average)
    interior = (slice(None), slice(5, -5), slice(25, -5))
    assert np.abs(reduced[interior] - shown[interior]).mean() < 6


def test_qlook_memory_does_not_hold_the_image(tmp_path: Path, monkeypatch):
    """Tiles are read as windows of at most one tile: never the whole raster."""
    data = (np.arange(1100 * 1300) % 251).reshape(1100, 1300).astype(np.uint8) + 1
    tif = write_geotiff(tmp_path / "big.tif", data, nodata=0)
    src = open_product(tif)
    shapes = []
    from pdsgen.extras import qlook

    real = qlook._stretched

    def spy(ds, src, bands, stretches, window):
        shapes.append((window.height, window.width))
        return real(ds, src, bands, stretches, window)

    monkeypatch.setattr(qlook, "_stretched", spy)
    write_qlook(src, [Stretch(1.0, 251.0)], tmp_path / "q.jp2")
    assert max(h * w for h, w in shapes) <= 512 * 512 and len(shapes) == 3 * 3
    with rasterio.open(tmp_path / "q.jp2") as ds:
        assert ds.crs == src.crs and (ds.width, ds.height) == (1300, 1100)


def test_jpylyzer_finds_the_qlook_valid_and_lossy(tmp_path: Path):
    """An independent validator (not OpenJPEG) checks the boxes around the inserted GeoJP2."""
    jpylyzer = pytest.importorskip("jpylyzer.jpylyzer")
    data = (np.arange(600 * 700) % 251).reshape(600, 700).astype(np.uint8) + 1
    src = open_product(write_geotiff(tmp_path / "img.tif", data, nodata=0))
    write_qlook(src, [Stretch(1.0, 251.0)], tmp_path / "q.jp2")
    result = jpylyzer.checkOneFile(str(tmp_path / "q.jp2"))
    failed = [n.tag for n in result.find("tests").iter() if n.text == "False"]
    assert result.find("isValid").text == "True", failed
    cod = result.find("properties/contiguousCodestreamBox/cod")
    assert cod.find("transformation").text == "9-7 irreversible"
