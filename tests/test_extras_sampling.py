"""Decimated reads: preview size, no-data kept out, and the 10**6-value statistics sample."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pdsgen.extras.decimate import (
    MIN_SAMPLE_VALUES,
    preview_grid,
    read_physical,
    statistics_sample,
)
from pdsgen.extras.product_source import open_product
from test_extras_helpers import write_geotiff


def test_sparse_product_gets_a_denser_sample_of_at_least_a_million_values(tmp_path: Path):
    size = 3000
    dn = np.full((size, size), -32768, dtype=np.int16)
    dn[:, : size // 4] = np.arange(size // 4, dtype=np.int16)[None, :]  # 25 % valid
    tif = write_geotiff(tmp_path / "sparse.tif", dn, nodata=-32768)
    src = open_product(tif, kind="dtm")
    grid = preview_grid(src, 256)
    browse = read_physical(src, grid, [1])
    assert browse.shape == (1, 256, 256)
    assert browse.count() < MIN_SAMPLE_VALUES
    sample = statistics_sample(src, browse, [1])
    assert sample.count() >= MIN_SAMPLE_VALUES
    assert sample.max() < size // 4 and sample.min() >= 0  # no-data never leaks in


def test_small_product_is_sampled_whole(tmp_path: Path):
    data = np.arange(400 * 300, dtype=np.float32).reshape(400, 300)
    tif = write_geotiff(tmp_path / "small.tif", data)
    src = open_product(tif, kind="dtm")
    grid = preview_grid(src, 1024)
    assert (grid.width, grid.height) == (300, 400)  # never enlarged
    browse = read_physical(src, grid, [1])
    sample = statistics_sample(src, browse, [1])
    assert sample.count() == 400 * 300
    assert float(sample.min()) == 0.0 and float(sample.max()) == 400 * 300 - 1


def test_averaging_leaves_no_data_out_of_each_preview_pixel(tmp_path: Path):
    data = np.full((100, 100), 7.0, dtype=np.float32)
    data[:, :53] = -3.4028226550889045e38
    tif = write_geotiff(tmp_path / "edge.tif", data, nodata=-3.4028226550889045e38)
    src = open_product(tif, kind="dtm")
    browse = read_physical(src, preview_grid(src, 10), [1])
    assert np.ma.getmaskarray(browse)[0, :, :5].all()
    assert np.allclose(browse[0, :, 6:].compressed(), 7.0)
    assert np.allclose(browse.compressed(), 7.0)  # the mixed column averages valid pixels only


def test_missing_constant_bit_pattern_and_plain_values(tmp_path: Path):
    from pdsgen.extras.product_source import _label_nodata

    pattern = {"SAMPLE_TYPE": "PC_REAL", "MISSING_CONSTANT": 0xFF7FFFFB}
    assert _label_nodata(pattern, "float32", None) == np.float32(-3.4028226550889045e38)
    plain = {"SAMPLE_TYPE": "PC_REAL", "MISSING_CONSTANT": -32768}
    assert _label_nodata(plain, "float32", None) == -32768.0
    core_null = {"SAMPLE_TYPE": "MSB_UNSIGNED_INTEGER", "CORE_NULL": 0}
    assert _label_nodata(core_null, "uint16", None) == 0.0
    assert _label_nodata({}, "int16", -32768.0) == -32768.0
