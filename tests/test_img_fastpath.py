"""The float32 DTM fast path (formats/img.py) against a plain numpy reference.

float32 input is streamed by a path of its own: strips read into reused buffers on a
reading thread, examined in cache-sized chunks, minimum and maximum found without
where= by filling missing pixels with +inf, then MISSING_CONSTANT. Every case here
is one that path could get wrong; the expected stored samples and statistics are
computed in the test from the bit patterns (not with pdsgen's code), and the product
is read back through GDAL and pvl as well.
"""

from __future__ import annotations

import io
import time

import numpy as np
import pvl
import pytest
import rasterio
from rasterio.windows import Window

from pdsgen import write_dtm
from pdsgen.errors import PdsgenError
from pdsgen.formats import img
from pdsgen.formats.raster import open_raster, row_strips

from helpers import CRS_EQUIRECTANGULAR, ORIGINS, elevation_array, write_raster

TRANSFORM = ORIGINS["equirectangular"][1]
NULL_BITS = 0xFF7FFFFB  # ISIS NULL; LRS, LIS, HIS, HRS are the four patterns above it
NULL = np.array([NULL_BITS], np.uint32).view(np.float32)[0]
SPECIALS = np.arange(0xFF7FFFFB, 0xFF7FFFFF + 1, dtype=np.uint32).view(np.float32)
LARGEST = np.finfo(np.float32).max
JUST_ABOVE_NULL = np.array([NULL_BITS - 1], np.uint32).view(np.float32)[0]  # the lowest valid value


def reference(data: np.ndarray, nodata: float | None) -> tuple[np.ndarray, np.ndarray]:
    """Valid mask and stored samples as the PDS3 rules define them, from the bit patterns."""
    as_float = data.astype(np.float32)
    bits = as_float.view(np.uint32)
    exponent_all_ones = (bits & 0x7F800000) == 0x7F800000  # NaN and +/-inf
    special = (bits >= 0xFF7FFFFB) & (bits <= 0xFF7FFFFF)
    valid = ~exponent_all_ones & ~special
    if nodata is not None and not np.isnan(nodata):
        valid &= data != nodata
    stored = np.where(valid, as_float, NULL).astype(np.float32)
    return valid, stored


def stream(path, big_endian: bool) -> tuple[bytes, img.BandStatistics]:
    out = io.BytesIO()
    with open_raster(path) as dataset:
        stats = img.stream_float32_band(dataset, out, big_endian)
    return out.getvalue(), stats


def assert_streamed_as_reference(path, data: np.ndarray, nodata: float | None) -> None:
    valid, stored = reference(data, nodata)
    for big_endian in (False, True):
        raw, stats = stream(path, big_endian)
        expected = stored.astype(">f4" if big_endian else "<f4").tobytes()
        assert len(raw) == len(expected)
        assert raw == expected, f"stored samples differ (big_endian={big_endian})"
        assert stats.valid_count == int(valid.sum())
        if valid.any():
            assert np.float32(stats.minimum) == data[valid].astype(np.float32).min()
            assert np.float32(stats.maximum) == data[valid].astype(np.float32).max()


def assert_product_reads_back(tmp_path, source, data: np.ndarray, nodata: float | None) -> None:
    """GDAL reads the .IMG to the reference samples; pvl reads the label's statistics."""
    valid, stored = reference(data, nodata)
    for order in ("lsb", "msb"):
        product = write_dtm(source, tmp_path / f"out_{order}", product_id="FAST_PATH", byte_order=order,
                            any_kind=data.dtype == np.uint8)  # 8-bit heights on purpose, not image DNs
        with rasterio.open(product.path) as dataset:
            assert dataset.dtypes[0] == "float32"
            read = dataset.read(1)
        assert np.array_equal(read.view(np.uint32), stored.view(np.uint32))
        label = pvl.load(str(product.path))
        assert np.float32(label["IMAGE"]["VALID_MINIMUM"]) == data[valid].astype(np.float32).min()
        assert np.float32(label["IMAGE"]["VALID_MAXIMUM"]) == data[valid].astype(np.float32).max()


def three_line_strips(dataset):
    """Windows of 3 lines (the file's blocks are taller: GDAL reads parts of blocks)."""
    for row in range(0, dataset.height, 3):
        yield Window(0, row, dataset.width, min(3, dataset.height - row))


@pytest.fixture
def small_strips_and_chunks(monkeypatch):
    """Strips of 3 lines and chunks of 7 samples: many strip and chunk boundaries in a small raster."""
    monkeypatch.setattr(img, "row_strips", three_line_strips)
    monkeypatch.setattr(img, "CHUNK_SAMPLES", 7)


def mixed_specials(height: int, width: int, nodata: float) -> np.ndarray:
    data = elevation_array(height, width, seed=11)
    flat = data.reshape(-1)
    rng = np.random.default_rng(5)
    for value in (np.nan, np.inf, -np.inf, nodata, *SPECIALS):
        flat[rng.choice(flat.size, 40, replace=False)] = value
    return data


def test_the_fast_path_is_the_one_taken(tmp_path, monkeypatch):
    """float32 input never goes through the general path's strip masks (so the tests here test it)."""
    data = elevation_array(20, 30)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)

    def general_path(*args, **kwargs):
        raise AssertionError("general path used for float32 input")

    monkeypatch.setattr(img, "physical_strips", general_path)
    assert_streamed_as_reference(source, data, -9999.0)


def test_nan_inf_isis_specials_and_nodata_mixed(tmp_path, small_strips_and_chunks):
    data = mixed_specials(40, 50, -9999.0)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    assert_streamed_as_reference(source, data, -9999.0)
    assert_product_reads_back(tmp_path, source, data, -9999.0)


def test_whole_strips_and_chunks_of_missing_pixels(tmp_path, small_strips_and_chunks):
    """Strips where every pixel is missing (each kind of missing), between valid ones."""
    data = elevation_array(30, 50, seed=2)
    data[0:3] = -9999.0  # the first strip: all nodata
    data[6:9] = np.nan  # a middle strip: all NaN
    data[12:15] = NULL
    data[15:18] = np.inf
    data[27:30] = -np.inf  # the last strip
    data[20, 13:20] = -9999.0  # one chunk of 7 samples, all missing
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    assert_streamed_as_reference(source, data, -9999.0)
    assert_product_reads_back(tmp_path, source, data, -9999.0)


@pytest.mark.parametrize("end", ["maximum", "minimum"])
def test_nodata_equal_to_the_extreme_value(tmp_path, small_strips_and_chunks, end):
    """The nodata value is the raster's largest (smallest) value: it must not be the statistic."""
    data = elevation_array(20, 50, seed=4)
    nodata = float(data.max() if end == "maximum" else data.min())
    data[::4, ::3] = nodata
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=nodata)
    assert_streamed_as_reference(source, data, nodata)
    assert_product_reads_back(tmp_path, source, data, nodata)


def test_valid_values_at_the_ends_of_the_float32_range(tmp_path, small_strips_and_chunks):
    """The largest float32 and the lowest value above ISIS NULL are valid and are the extremes;
    the fill values of the fast path (+inf, MISSING_CONSTANT) must not shadow them."""
    data = elevation_array(12, 50, seed=6)
    data[3, 7] = LARGEST
    data[8, 44] = JUST_ABOVE_NULL
    data[5, :] = np.inf
    data[5, 10] = NULL
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    _, stats = stream(source, False)
    assert np.float32(stats.maximum) == LARGEST
    assert np.float32(stats.minimum) == JUST_ABOVE_NULL
    assert_streamed_as_reference(source, data, -9999.0)


@pytest.mark.parametrize("shape", [(300, 1), (1, 1000), (1, 1)])
def test_one_pixel_wide_and_one_line_rasters(tmp_path, shape):
    data = elevation_array(*shape, seed=8)
    data.reshape(-1)[::5] = -9999.0
    data.reshape(-1)[-1] = 12.5  # valid, and the maximum
    if data.size > 3:
        data.reshape(-1)[1] = np.nan
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    assert_streamed_as_reference(source, data, -9999.0)
    assert_product_reads_back(tmp_path, source, data, -9999.0)


def test_real_strip_and_chunk_sizes(tmp_path):
    """At the real sizes: three strips of 16 MB (838, 838, 324 lines of 5000), chunk
    boundaries falling inside lines, missing pixels on both sides of each boundary."""
    data = elevation_array(2000, 5000, seed=9)
    data[:, :3] = -9999.0
    for boundary in (837, 838, 1675, 1676):
        data[boundary, ::97] = np.nan
    flat = data.reshape(-1)
    for start in range(0, flat.size, img.CHUNK_SAMPLES):  # the first and last sample of every chunk
        flat[start] = -9999.0
        flat[min(flat.size, start + img.CHUNK_SAMPLES) - 1] = NULL
    flat[img.CHUNK_SAMPLES * 3: img.CHUNK_SAMPLES * 4] = -np.inf  # one whole chunk missing
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    with open_raster(source) as dataset:
        assert [window.height for window in row_strips(dataset)] == [838, 838, 324]
    assert_streamed_as_reference(source, data, -9999.0)


def test_no_nodata_value(tmp_path, small_strips_and_chunks):
    """Without a nodata value, -9999 is an elevation; NaN and the specials are still missing."""
    data = mixed_specials(20, 50, -9999.0)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM)
    assert_streamed_as_reference(source, data, None)
    _, stats = stream(source, False)
    assert stats.minimum == -9999.0


def test_fast_path_equals_the_general_path(tmp_path, small_strips_and_chunks):
    """The same bytes and statistics as stream_band's general path (an encoder that is not
    encode_float32 itself takes it)."""
    data = mixed_specials(25, 50, -9999.0)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    for big_endian in (False, True):
        fast, general = io.BytesIO(), io.BytesIO()
        with open_raster(source) as dataset:
            fast_stats = img.stream_band(dataset, fast, big_endian)
            general_stats = img.stream_band(dataset, general, big_endian, lambda v, i: img.encode_float32(v, i))
        assert fast.getvalue() == general.getvalue()
        assert fast_stats == general_stats


@pytest.mark.parametrize("dtype, nodata", [("int16", -32768), ("int16", 0.5), ("uint8", 0), ("float64", -9999.0)])
def test_integer_and_float64_inputs(tmp_path, small_strips_and_chunks, dtype, nodata):
    """Other input types take the general path, with the same rules; an integer nodata the
    type cannot hold (0.5 in int16) marks nothing missing."""
    rng = np.random.default_rng(3)
    info = np.iinfo(dtype) if dtype != "float64" else None
    if info is not None:
        data = rng.integers(info.min, info.max, (20, 50), endpoint=True).astype(dtype)
        data[0, 0], data[1, 1] = info.min, info.max
    else:
        data = rng.normal(-4000, 50, (20, 50))
        data[2, 2] = np.nan
    if float(nodata).is_integer():
        data[::3, ::4] = nodata
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=nodata)
    assert_streamed_as_reference(source, data, nodata)
    assert_product_reads_back(tmp_path, source, data, nodata)


def test_float64_beyond_float32_is_refused(tmp_path):
    data = np.full((10, 10), -4000.0)
    data[7, 3] = 1e39
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=1e300)
    with pytest.raises(PdsgenError, match="beyond the 32-bit float range"):
        stream(source, False)


def test_all_missing_is_refused_without_output(tmp_path, small_strips_and_chunks):
    data = np.full((9, 50), -9999.0, np.float32)
    data[4, 4] = np.nan
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    raw, stats = stream(source, False)
    assert stats.valid_count == 0
    assert raw == np.full(data.shape, NULL, "<f4").tobytes()
    with pytest.raises(PdsgenError, match="no valid pixels"):
        write_dtm(source, tmp_path / "out", product_id="EMPTY")
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


class SlowFile(io.BytesIO):
    """A file that takes its time over each write, as a busy disk does."""

    def write(self, data) -> int:  # noqa: ANN001 - bytes-like, like a file
        time.sleep(0.002)
        return super().write(data)


@pytest.mark.parametrize("slots", [1, 2, 3])
def test_a_strip_buffer_is_reused_only_once_written(tmp_path, small_strips_and_chunks, monkeypatch, slots):
    """With few read buffers and a slow file, the reading thread must wait for the writer
    before it reads the next strip into a buffer still being written (fewer than two
    buffers are taken as two: one is read into while the other is worked on)."""
    monkeypatch.setattr(img, "READ_SLOTS", slots)
    data = mixed_specials(60, 50, -9999.0)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    _, stored = reference(data, -9999.0)
    out = SlowFile()
    with open_raster(source) as dataset:
        img.stream_float32_band(dataset, out, False)
    assert out.getvalue() == stored.astype("<f4").tobytes()


class RecordingFile(io.BytesIO):
    """Keeps the size of every write() call."""

    def __init__(self) -> None:
        super().__init__()
        self.calls: list[int] = []

    def write(self, data) -> int:  # noqa: ANN001 - bytes-like, like a file
        self.calls.append(memoryview(data).nbytes)
        return super().write(data)


@pytest.mark.parametrize("big_endian", [False, True])
def test_strips_are_written_in_pieces_of_whole_samples(tmp_path, big_endian):
    """A 16 MB strip reaches the file as 1 MB write() calls (large calls cost several times
    the system time), each a whole number of samples, the bytes in order."""
    data = elevation_array(1000, 5000, seed=12)  # two strips: 838 and 162 lines
    data[:, 0] = -9999.0
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    out = RecordingFile()
    with open_raster(source) as dataset:
        img.stream_float32_band(dataset, out, big_endian)
    assert max(out.calls) == img.WRITE_CHUNK == 2**20
    assert all(size % 4 == 0 for size in out.calls)
    assert sum(out.calls) == data.size * 4
    _, stored = reference(data, -9999.0)
    assert out.getvalue() == stored.astype(">f4" if big_endian else "<f4").tobytes()


def test_a_failing_write_stops_the_pass_with_its_error(tmp_path, small_strips_and_chunks):
    """A disk that fills up mid-product: the write's own error reaches the caller (the product
    writer's staging then removes the partial file), and the reading thread stops with it."""
    import errno
    import threading

    class FullDisk(io.RawIOBase):
        def __init__(self, room: int) -> None:
            self.room = room

        def writable(self) -> bool:
            return True

        def write(self, data) -> int:
            size = memoryview(data).nbytes
            if size > self.room:
                raise OSError(errno.ENOSPC, "No space left on device")
            self.room -= size
            return size

    data = elevation_array(60, 50, seed=12)
    source = write_raster(tmp_path / "in.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM, nodata=-9999.0)
    with open_raster(source) as dataset, pytest.raises(OSError) as raised:
        img.stream_float32_band(dataset, FullDisk(room=data.nbytes // 3), big_endian=False)
    assert raised.value.errno == errno.ENOSPC
    assert not [t for t in threading.enumerate() if t.name.startswith(("pdsgen-read", "pdsgen-write"))]
