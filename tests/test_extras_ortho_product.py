"""Extras of orthoimage products written by pdsgen.products.ortho (lossless JP2 + detached label)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from pdsgen.extras import make_extras
from test_extras_helpers import write_geotiff

ortho = pytest.importorskip("pdsgen.products.ortho", reason="the orthoimage writer is not merged yet")


def scene(bands: int) -> np.ndarray:
    rows, cols = np.mgrid[0:600, 0:480].astype(np.float32)
    layers = [0.10 + 0.04 * np.sin(cols / (20.0 + 9 * b)) * np.cos(rows / 31.0) + 0.01 * b
              for b in range(bands)]
    data = np.stack(layers).astype(np.float32)
    data[:, :, :60] = np.nan  # outside the footprint
    return data if bands > 1 else data[0]


@pytest.mark.parametrize("bands", [1, 3])
def test_extras_of_a_pdsgen_orthoimage_from_its_label_and_from_its_jp2(tmp_path: Path, bands):
    tif = write_geotiff(tmp_path / f"ortho{bands}.tif", scene(bands), nodata=float("nan"))
    product = ortho.write_ortho(tif, tmp_path / "products", product_id=f"TEST_ORTHO_{bands}")
    for entry in (product.label_path, product.jp2_path):
        out = tmp_path / f"extras_{entry.suffix[1:]}"
        written = make_extras([entry], out, browse_width=240)
        assert sorted(p.name for p in written) == sorted(
            [f"TEST_ORTHO_{bands}.{c}.jpg" for c in ("browse", "abrowse", "thumb")]
            + [f"TEST_ORTHO_{bands}.QLOOK.JP2", "README.TXT"])
        with Image.open(out / f"TEST_ORTHO_{bands}.browse.jpg") as im:
            assert im.format == "JPEG" and im.width == 240
            assert im.mode == ("RGB" if bands == 3 else "L")
            data = np.asarray(im.convert("RGB")).astype(int)
        assert data[:, :25].max() <= 10            # outside the footprint: black
        inside = data[:, 40:]
        assert inside.min() <= 15 and inside.max() >= 240  # stretched to the full range
        if bands == 3:
            assert np.percentile(inside.max(axis=-1) - inside.min(axis=-1), 75) > 30
        text = (out / "README.TXT").read_text()
        assert f"TEST_ORTHO_{bands}.abrowse.jpg" in text and "I/F = DN *" in text
