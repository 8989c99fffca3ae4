"""Compiled label templates are kept between runs (~/.cache/pdsgen/templates), and the cache
never changes a product nor stops one being made."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from affine import Affine

from helpers import write_raster

MARS_EQC = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs"


@pytest.fixture(scope="module")
def dtm_input(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("cache_in") / "small.tif"
    heights = np.linspace(-4000.0, -3000.0, 32 * 48, dtype=np.float32).reshape(32, 48)
    write_raster(path, heights, MARS_EQC, Affine(2.0, 0.0, 1000.0, 0.0, -2.0, 5000.0))
    return path


def _make(dtm_input: Path, out: Path, cache_home: Path) -> bytes:
    env = {**os.environ, "XDG_CACHE_HOME": str(cache_home)}
    result = subprocess.run([sys.executable, "-m", "pdsgen", "dtm", str(dtm_input), "-o", str(out),
                             "--product-id", "CACHE_TEST"], env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return (out / "CACHE_TEST.IMG").read_bytes()


def test_second_run_reads_the_compiled_templates_and_writes_the_same_product(dtm_input, tmp_path):
    cache_home = tmp_path / "cache"
    first = _make(dtm_input, tmp_path / "one", cache_home)
    entries = sorted((cache_home / "pdsgen" / "templates").iterdir())
    assert entries, "the first run keeps its compiled templates"
    stamps = [entry.stat().st_mtime_ns for entry in entries]
    assert _make(dtm_input, tmp_path / "two", cache_home) == first
    assert [entry.stat().st_mtime_ns for entry in entries] == stamps  # read, not compiled again


def test_a_cache_that_cannot_be_written_or_is_damaged_changes_nothing(dtm_input, tmp_path):
    reference = _make(dtm_input, tmp_path / "ref", tmp_path / "cache")
    not_a_directory = tmp_path / "file"
    not_a_directory.write_text("a file where the cache directory would go")
    assert _make(dtm_input, tmp_path / "blocked", not_a_directory) == reference
    for entry in (tmp_path / "cache" / "pdsgen" / "templates").iterdir():
        entry.write_bytes(b"not jinja2 bytecode")
    assert _make(dtm_input, tmp_path / "damaged", tmp_path / "cache") == reference
