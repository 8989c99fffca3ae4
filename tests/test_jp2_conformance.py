"""An independent JP2 validator's view of what the encoder writes.

GDAL, glymur and Pillow all decode with OpenJPEG, the library that encoded the
tiles; jpylyzer (the digital-preservation JP2 validator, pure Python) checks the
box structure and code stream markers - SIZ, COD, QCD, TLM, tile-part lengths -
against JPEG 2000 Part 1 without OpenJPEG, so an assembly error in the tile-parts
the encoder splices together cannot pass by being read back by its own library.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pdsgen.formats.jp2 import choose_settings, write_jp2

jpylyzer = pytest.importorskip("jpylyzer.jpylyzer")


def _failed_tests(element) -> list[str]:
    """Names of the tests jpylyzer reports as failed (it lists only failures under <tests>)."""
    return [node.tag for node in element.find("tests").iter() if node.text == "False"]


@pytest.mark.parametrize(("shape", "bands", "bits"), [((150, 203), 1, 10), ((97, 130), 3, 8), ((64, 64), 1, 16)])
def test_jpylyzer_finds_the_jp2_valid(tmp_path, shape, bands, bits):
    rng = np.random.default_rng(3)
    full = shape if bands == 1 else (*shape, bands)
    data = rng.integers(0, 1 << bits, size=full).astype(np.uint8 if bits <= 8 else np.uint16)
    settings = dataclasses.replace(choose_settings(*shape), tile_shape=(32, 32))
    path = tmp_path / "t.jp2"
    write_jp2(path, shape[0], shape[1], bands, bits, lambda first, n: data[first:first + n].copy(), settings=settings)
    result = jpylyzer.checkOneFile(str(path))
    assert result.find("isValid").text == "True", _failed_tests(result)
    properties = result.find("properties")
    siz = properties.find("contiguousCodestreamBox/siz")
    assert int(siz.find("xsiz").text) == shape[1] and int(siz.find("ysiz").text) == shape[0]
    assert int(siz.find("csiz").text) == bands
    assert int(siz.find("xTsiz").text) == 32
    cod = properties.find("contiguousCodestreamBox/cod")
    assert cod.find("transformation").text == "5-3 reversible"
