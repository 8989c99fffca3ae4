"""The iMars DTM mosaic without its statistics pass: where the strips' own sample type and scaling
decide the 16-bit encoding (strips of one release), the mosaic is written at once, and it is byte
for byte the mosaic the pass makes (products.imars.TRUST_SOURCE_RANGE off forces the pass); a
refusal of the pass is the same refusal; the GeoTIFF's blocks compressed on several threads are
the bytes of one thread."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest
import rasterio
from affine import Affine

from pdsgen.errors import PdsgenError
from pdsgen.mosaic import write_mosaic
from pdsgen.products import imars
from pdsgen.products.dtm import write_dtm
from pdsgen.products.int16_heights import Int16Encoding
from pdsgen.products.opening import ProductInput

from helpers import CRS_SOUTH_POLAR, write_raster

PIXEL = 50.0


def strips(folder: Path, count: int = 4, scale: float | None = None, flat: bool = False,
           nodata: int = -32768) -> list[Path]:
    """Overlapping int16 strips with ragged edges and a hole; `scale`: stored as DN * scale."""
    rng = np.random.default_rng(11)
    paths = []
    for index in range(count):
        lines, samples = 300 + 7 * index, 280 - 3 * index
        data = (rng.integers(5, 9, (lines, samples)) if flat else
                -3000 + np.cumsum(rng.integers(-20, 21, (lines, samples)), axis=1)).astype(np.int16)
        for row in range(lines):
            data[row, : rng.integers(0, 6)] = nodata
            data[row, samples - rng.integers(0, 6):] = nodata
        data[80:120, 100:160] = nodata
        transform = Affine(PIXEL, 0, -200000.0 + PIXEL * 60 * index, 0, -PIXEL, 150000.0 - PIXEL * 40 * index)
        path = write_raster(folder / f"h{1000 + index}_0000.tif", data, CRS_SOUTH_POLAR, transform, nodata=nodata)
        if scale is not None:
            with rasterio.open(path, "r+") as dataset:
                dataset.scales = (scale,)
        paths.append(path)
    return paths


def contents(folder: Path) -> dict[str, bytes]:
    return {path.name: path.read_bytes() for path in sorted(folder.iterdir())}


@pytest.fixture(autouse=True)
def one_day(monkeypatch):
    """Both mosaics of a test made on the same day (the processing date is in the PVL and tags)."""
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")


def both_ways(tmp_path: Path, monkeypatch, inputs: list[Path], **options) -> tuple[dict, dict, int]:
    """The mosaic written with the shortcut and with the statistics pass forced; the number of
    statistics passes the first took."""
    passes = []
    scan = ProductInput.scan
    monkeypatch.setattr(ProductInput, "scan", lambda self, adjust=None: passes.append(1) or scan(self, adjust))
    write_mosaic(inputs, tmp_path / "short", profile="imars", product_id="m", kind="dtm", **options)
    taken = len(passes)
    monkeypatch.setattr(imars, "TRUST_SOURCE_RANGE", False)
    write_mosaic(inputs, tmp_path / "pass", profile="imars", product_id="m", kind="dtm", **options)
    assert len(passes) == taken + 1  # forced: the pass ran
    return contents(tmp_path / "short"), contents(tmp_path / "pass"), taken


@pytest.mark.parametrize("scale", [None, 0.5, 0.1])
def test_strips_of_one_release_mosaic_without_a_pass_to_the_same_bytes(tmp_path, monkeypatch, scale):
    short, full, passes = both_ways(tmp_path, monkeypatch, strips(tmp_path, scale=scale))
    assert passes == 0  # the strips' int16 range at their own scale decided the encoding
    assert short.keys() == full.keys() and "m_dtm.tif" in short
    assert short == full


def test_a_precision_the_range_does_not_fit_takes_the_pass(tmp_path, monkeypatch):
    """At 0.05 m per step, int16 strips of 1 m could hold heights beyond 16 bits from 0: the
    bounds decide nothing, so the pass runs (and finds the offset the heights need)."""
    short, full, passes = both_ways(tmp_path, monkeypatch, strips(tmp_path), precision=0.05)
    assert passes == 1 and short == full


def test_a_wrong_guess_is_written_again_with_the_pass_s_choice(tmp_path, monkeypatch):
    """Should the encoding known before the write ever differ from what the write's own
    statistics choose, the file is written again with their choice: the same bytes."""
    wrong = Int16Encoding(1.0, 1000.0)
    monkeypatch.setattr(imars, "_known_encoding",
                        lambda mosaic, precision, adjust: wrong if imars.TRUST_SOURCE_RANGE else None)
    short, full, _ = both_ways(tmp_path, monkeypatch, strips(tmp_path))
    assert short == full


@pytest.mark.parametrize("case", ["flat", "empty"])
def test_a_refusal_judged_during_the_write_is_the_pass_s_and_leaves_nothing(tmp_path, monkeypatch, case):
    """Strips of fewer than 16 height levels, or of no data at all: the same refusal as the pass
    gives before anything is written, and no output directory left behind."""
    inputs = strips(tmp_path, flat=True)
    if case == "empty":
        for path in inputs:
            with rasterio.open(path, "r+") as dataset:
                dataset.write(np.full((dataset.height, dataset.width), -32768, np.int16), 1)
    messages = []
    for trust in (True, False):
        monkeypatch.setattr(imars, "TRUST_SOURCE_RANGE", trust)
        out = tmp_path / f"out{trust}"
        with pytest.raises(PdsgenError) as refused:
            write_mosaic(inputs, out, profile="imars", product_id="m", kind="dtm")
        messages.append(str(refused.value))
        assert not out.exists()
    assert messages[0] == messages[1]
    assert ("too coarse" if case == "flat" else "no valid pixels") in messages[0]


def test_compression_threads_give_the_bytes_of_one_thread(tmp_path):
    """GDAL compresses the GeoTIFF's blocks on every core unless GDAL_NUM_THREADS says otherwise;
    it writes them in order, so the product's checksum is the one-thread product's."""
    rng = np.random.default_rng(3)
    heights = (-3000 + np.cumsum(rng.normal(0, 3, (1100, 900)), axis=1)).astype(np.float32)
    source = write_raster(tmp_path / "in.tif", heights, CRS_SOUTH_POLAR,
                          Affine(PIXEL, 0, -20000.0, 0, -PIXEL, 150000.0), nodata=-32768)
    assert imars._compression_threads() == "ALL_CPUS"
    sums = []
    for threads in (None, "1", "3"):
        with rasterio.Env(**({"GDAL_NUM_THREADS": threads} if threads else {})):
            assert imars._compression_threads() == (threads or "ALL_CPUS")
            product = write_dtm(source, tmp_path / f"out{threads}", profile="imars", product_id="h0022_0000",
                                precision=0.1)
        sums.append(hashlib.sha256(product.tiff_path.read_bytes()).hexdigest())
    assert sums[0] == sums[1] == sums[2]


def test_a_strip_encoded_in_parts_is_the_strip_encoded_whole(tmp_path, monkeypatch):
    """The writer converts and encodes a strip a few lines at a time (products.imars.PART_PIXELS):
    the DTM and the orthoimage mosaics are the bytes of the whole strip at once."""
    dtm_strips = strips(tmp_path, scale=0.5)
    rng = np.random.default_rng(5)
    images = []
    for index, path in enumerate(dtm_strips):
        with rasterio.open(path) as dataset:
            image = rng.integers(1, 256, (dataset.height, dataset.width)).astype(np.uint8)
            image[dataset.read(1) == -32768] = 0
            images.append(write_raster(tmp_path / f"h{1000 + index}_0000_nd4.tif", image, CRS_SOUTH_POLAR,
                                       dataset.transform, nodata=0))
    made = []
    for part in (2**30, 1000):  # a strip in one part; parts of two lines (the mosaic is 460 wide)
        monkeypatch.setattr(imars, "PART_PIXELS", part)
        out = tmp_path / f"out{part}"
        write_mosaic(dtm_strips, out, profile="imars", product_id="m", kind="dtm")
        write_mosaic(images, out, profile="imars", product_id="m", kind="ortho")
        made.append(contents(out))
    assert {"m_dtm.tif", "m_ori.tif"} <= made[0].keys()
    assert made[0] == made[1]


def test_heights_stored_as_read_are_the_float32_encoding_s_bytes(tmp_path, monkeypatch):
    """int16 heights at scale 1 are stored as read, no-data set to -32768 (products.imars._KeptDns),
    without converting them to float32 and back: the same bytes as the conversion, with and
    without the statistics pass."""
    inputs = strips(tmp_path)
    made = []
    for kept in (True, False):
        if not kept:
            monkeypatch.setattr(imars, "SAME_DNS", Int16Encoding(-1.0, 0.0))  # never the encoding: converted
        for trust in (True, False):
            monkeypatch.setattr(imars, "TRUST_SOURCE_RANGE", trust)
            out = tmp_path / f"out{kept}{trust}"
            write_mosaic(inputs, out, profile="imars", product_id="m", kind="dtm")
            made.append(contents(out))
    assert "m_dtm.tif" in made[0]
    assert all(files == made[0] for files in made[1:])
