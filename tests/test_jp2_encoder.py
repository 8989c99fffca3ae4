"""The JPEG 2000 encoder: every file decodes bit-exactly with GDAL, OpenJPEG (glymur) and Pillow.

Small tiles (32 or 64 samples) give small rasters several full and partial edge
tiles, so the per-tile encoding and the assembly of tile-parts are exercised
without large inputs.
"""

from __future__ import annotations

import dataclasses
import warnings

import glymur
import numpy as np
import pytest
import rasterio
from PIL import Image

from pdsgen.formats.jp2 import CODE_BLOCK_STYLES, choose_settings, write_jp2


def _data(shape, bands, bits, seed=7):
    """Smooth relief plus noise over the whole DN range, with both extremes present."""
    rng = np.random.default_rng(seed)
    full = shape if bands == 1 else (*shape, bands)
    yy = np.arange(shape[0])[:, None] / 11.0
    xx = np.arange(shape[1])[None, :] / 17.0
    relief = (np.sin(yy) * np.cos(xx) + 1) / 2
    if bands > 1:
        relief = relief[..., None]
    top = (1 << bits) - 1
    values = np.clip(relief * top + rng.normal(scale=top / 20, size=full), 0, top)
    out = values.astype(np.uint8 if bits <= 8 else np.uint16)
    out.flat[0], out.flat[-1] = 0, top
    return out


def _encode(path, data, bits, tile=32, threads=None):
    lines, samples = data.shape[:2]
    bands = 1 if data.ndim == 2 else data.shape[2]
    settings = dataclasses.replace(choose_settings(lines, samples), tile_shape=(tile, tile))
    write_jp2(path, lines, samples, bands, bits, lambda first, n: data[first:first + n].copy(),
              settings=settings, threads=threads)
    return path


def _gdal(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
        with rasterio.open(path) as dataset:
            bands = dataset.read()
            nbits = dataset.tags(1, ns="IMAGE_STRUCTURE").get("NBITS")
    return (bands[0] if bands.shape[0] == 1 else np.moveaxis(bands, 0, -1)), nbits


def _pillow_view(data, bits):
    """What Pillow's modes can hold of `data`: 8-bit RGB (rounded down from more bits) or L / I;16."""
    wide = data.astype(np.int64)
    if data.ndim == 3 and bits > 8:  # RGB mode is 8 bits: Pillow rounds to nearest, modulo 256
        shift = bits - 8
        return ((wide + (1 << (shift - 1))) >> shift) % 256
    if data.ndim == 2 and 8 < bits < 16:  # I;16: Pillow scales the samples up to 16 bits
        return wide << (16 - bits)
    return wide


@pytest.mark.parametrize(
    ("shape", "bands", "bits"),
    [((75, 101), 1, 8), ((70, 45), 1, 10), ((33, 97), 1, 16), ((65, 40), 3, 8), ((47, 66), 3, 10), ((40, 33), 3, 16)],
)
def test_decodes_bit_exactly_with_gdal_glymur_and_pillow(tmp_path, shape, bands, bits):
    data = _data(shape, bands, bits)
    path = _encode(tmp_path / "t.jp2", data, bits)
    np.testing.assert_array_equal(glymur.Jp2k(path)[:], data)
    decoded, nbits = _gdal(path)
    np.testing.assert_array_equal(decoded, data)
    assert nbits == (str(bits) if bits not in (8, 16) else None)
    with Image.open(path) as image:
        assert image.size == (shape[1], shape[0])
        np.testing.assert_array_equal(np.asarray(image).astype(np.int64), _pillow_view(data, bits))


def test_one_tile_image_and_single_lines(tmp_path):
    for shape in [(1, 1), (1, 40), (40, 1), (5, 9)]:
        data = _data(shape, 1, 10)
        lines, samples = shape
        path = tmp_path / f"{lines}x{samples}.jp2"
        write_jp2(path, lines, samples, 1, 10, lambda first, n, d=data: d[first:first + n].copy())
        np.testing.assert_array_equal(glymur.Jp2k(path)[:], data)
        np.testing.assert_array_equal(_gdal(path)[0], data)


def test_code_stream_has_bypass_plt_tlm_and_the_image_size(tmp_path):
    data = _data((150, 203), 1, 10)
    path = _encode(tmp_path / "t.jp2", data, 10, tile=64)
    glymur.set_option("parse.full_codestream", True)
    try:
        codestream = glymur.Jp2k(path).get_codestream(header_only=False)
    finally:
        glymur.set_option("parse.full_codestream", False)
    segments = codestream.segment
    siz = next(s for s in segments if s.marker_id == "SIZ")
    assert (siz.ysiz, siz.xsiz, siz.ytsiz, siz.xtsiz) == (150, 203, 64, 64)
    cod = next(s for s in segments if s.marker_id == "COD")
    assert cod.xform == glymur.core.WAVELET_XFORM_5X3_REVERSIBLE and cod.layers == 1
    assert cod.scod & 0x01  # user-defined precincts
    assert cod.cstyle == CODE_BLOCK_STYLES["BYPASS"]
    tiles = [s for s in segments if s.marker_id == "SOT"]
    assert [t.isot for t in tiles] == list(range(3 * 4))
    tlm = next(s for s in segments if s.marker_id == "TLM")
    assert list(tlm.ttlm) == [t.isot for t in tiles] and list(tlm.ptlm) == [t.psot for t in tiles]
    assert sum(s.marker_id == "PLT" for s in segments) == len(tiles)
    assert segments[-1].marker_id == "EOC"


def test_thread_count_does_not_change_a_byte(tmp_path):
    data = _data((130, 170), 3, 8)
    one = _encode(tmp_path / "one.jp2", data, 8, threads=1).read_bytes()
    three = _encode(tmp_path / "three.jp2", data, 8, threads=3).read_bytes()
    assert one == three


def test_bad_arguments_are_refused(tmp_path):
    data = _data((10, 10), 1, 8)
    with pytest.raises(ValueError, match="threads"):
        _encode(tmp_path / "t.jp2", data, 8, threads=0)
    with pytest.raises(ValueError, match="bands"):
        write_jp2(tmp_path / "t.jp2", 10, 10, 2, 8, lambda first, n: data[first:first + n])
    wide = _data((40, 100), 1, 8)
    with pytest.raises(ValueError, match="power of two"):  # a 48-sample tile at x = 48 codes differently
        _encode(tmp_path / "t.jp2", wide, 8, tile=48)
    assert not list(tmp_path.iterdir())


def test_a_failing_reader_leaves_no_scratch_files(tmp_path):
    def broken(first, lines):
        if first > 0:
            raise OSError("read error")
        return np.zeros((lines, 80), np.uint8)

    settings = dataclasses.replace(choose_settings(100, 80), tile_shape=(32, 32))
    with pytest.raises(OSError, match="read error"):
        write_jp2(tmp_path / "t.jp2", 100, 80, 1, 8, broken, settings=settings)
    assert [p.name for p in tmp_path.iterdir()] == ["t.jp2"]  # the caller stages and removes it


def test_lossy_settings_cut_each_tile_to_the_compression_ratio(tmp_path):
    """reversible=False with compression_ratio: 9/7, about 1/N of the samples' bytes, still decodable."""
    data = _data((256, 192), 3, 8)
    lines, samples = data.shape[:2]
    settings = dataclasses.replace(choose_settings(lines, samples), tile_shape=(64, 64),
                                   reversible=False, compression_ratio=20)
    path = tmp_path / "lossy.jp2"
    write_jp2(path, lines, samples, 3, 8, lambda first, n: data[first:first + n].copy(), settings=settings)
    assert path.stat().st_size < data.nbytes / 15
    decoded, _ = _gdal(path)
    assert decoded.shape == data.shape and not np.array_equal(decoded, data)
    assert np.abs(decoded.astype(float) - data).mean() < 12  # lossy, the same picture
    cod = next(s for s in glymur.Jp2k(str(path)).get_codestream().segment if s.marker_id == "COD")
    assert cod.xform == 0  # 9/7 irreversible wavelet


def test_at_most_two_rows_of_tiles_are_held(tmp_path):
    """The next row is read once half of the current row's tiles are coded: memory is two rows of tiles.

    A row's tiles are views of it, so a row lives until its last tile is encoded;
    when a row is read, no row before the one being encoded may still be alive.
    """
    import weakref

    data = _data((32 * 6, 32 * 8), 1, 8)
    rows: list[weakref.ref] = []
    alive_when_read = []

    def read(first, lines):
        alive_when_read.append(sum(row() is not None for row in rows))
        row = data[first:first + lines].copy()
        rows.append(weakref.ref(row))
        return row

    settings = dataclasses.replace(choose_settings(*data.shape), tile_shape=(32, 32))
    path = tmp_path / "rows.jp2"
    write_jp2(path, *data.shape, 1, 8, read, settings=settings, threads=2)
    assert len(alive_when_read) == 6 and max(alive_when_read) == 1
    assert np.array_equal(_gdal(path)[0], data)
