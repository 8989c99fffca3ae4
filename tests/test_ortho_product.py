"""The orthoimage product end to end: lossless JP2 read by OpenJPEG and GDAL, label read by pvl and pdr."""

import os

import glymur
import numpy as np
import pvl
import pytest
import rasterio
from affine import Affine
from click.testing import CliRunner
from rasterio.crs import CRS

from pdsgen import write_ortho
from pdsgen.cli import main
from pdsgen.errors import PdsgenError
from pdsgen.formats.jp2 import TILE_SIZE
from pdsgen.formats.scale_dn import SPECIAL_DNS
from pdsgen.synthetic import write_geotiff

EQC = CRS.from_proj4("+proj=eqc +lat_ts=-5 +lat_0=0 +lon_0=180 +R=3396190 +units=m +no_defs")
TRANSFORM = Affine(0.5, 0.0, 6099776.0, 0.0, -0.5, -563110.0)
SHAPE = (700, 800)  # 2 x 2 tiles of 512 with partial edge tiles


def _texture(shape, low, high, seed=3):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[: shape[-2], : shape[-1]]
    smooth = np.sin(yy / 37.0) * np.cos(xx / 53.0)
    noise = rng.normal(scale=0.2, size=shape)
    unit = (smooth + noise - (smooth + noise).min()) / np.ptp(smooth + noise)
    return low + unit * (high - low)


def _write(tmp_path, data, nodata=None, name="in.tif", crs=EQC, transform=TRANSFORM):
    return write_geotiff(tmp_path / name, data, transform, crs, nodata)


def _label_image(label):
    return label["UNCOMPRESSED_FILE"]["IMAGE"]


@pytest.mark.parametrize(
    ("bits", "dtype", "bands"),
    [(8, np.uint8, 1), (8, np.uint8, 3), (10, np.uint16, 1), (10, np.uint16, 3), (16, np.uint16, 1),
     (16, np.uint16, 3)],
)
def test_integer_dns_are_stored_losslessly(tmp_path, bits, dtype, bands):
    special = SPECIAL_DNS[bits]
    shape = (bands, *SHAPE)
    data = _texture(shape, special.valid_min, special.valid_max).astype(dtype)
    data[:, :40, :25] = 0  # nodata collar
    source = _write(tmp_path, data if bands == 3 else data[0], nodata=0)
    product = write_ortho(source, tmp_path / "out", bits=bits)
    assert (product.bits, product.bands, product.scaling_factor, product.offset) == (bits, bands, 1.0, 0.0)

    jp2 = glymur.Jp2k(product.jp2_path)
    decoded = jp2[:]
    expected = data[0] if bands == 1 else np.moveaxis(data, 0, -1)
    assert decoded.dtype == special.dtype
    np.testing.assert_array_equal(decoded, expected)

    ihdr = jp2.box[2].box[0]
    siz = jp2.get_codestream(header_only=True).segment[1]
    image = _label_image(pvl.load(str(product.label_path)))
    assert (ihdr.height, ihdr.width, ihdr.num_components) == (image["LINES"], image["LINE_SAMPLES"], image["BANDS"])
    assert ihdr.bits_per_component == bits == bin(image["SAMPLE_BIT_MASK"]).count("1")
    assert set(siz.bitdepth) == {bits}
    assert image["SAMPLE_BITS"] == (8 if bits == 8 else 16)
    assert image["SAMPLE_TYPE"] == ("UNSIGNED_INTEGER" if bits == 8 else "MSB_UNSIGNED_INTEGER")


def test_code_stream_is_reversible_tiled_multi_resolution_with_plt(tmp_path):
    data = _texture(SHAPE, 1, 254).astype(np.uint8)
    product = write_ortho(_write(tmp_path, data), tmp_path / "out")
    glymur.set_option("parse.full_codestream", True)
    try:
        codestream = glymur.Jp2k(product.jp2_path).get_codestream(header_only=False)
    finally:
        glymur.set_option("parse.full_codestream", False)
    markers = [segment.marker_id for segment in codestream.segment]
    cod = next(s for s in codestream.segment if s.marker_id == "COD")
    assert cod.xform == 1  # 5/3 reversible
    assert cod.layers == 1 and cod.num_res >= 2  # decomposition levels
    assert cod.prog_order == glymur.core.RPCL
    assert "PLT" in markers
    assert markers.count("SOT") == -(-SHAPE[0] // TILE_SIZE) * -(-SHAPE[1] // TILE_SIZE) == 4
    jp2 = glymur.Jp2k(product.jp2_path)
    np.testing.assert_array_equal(jp2[600:650, 500:780], data[600:650, 500:780])
    np.testing.assert_array_equal(jp2[::4, ::4].shape, (175, 200))


def test_float_input_round_trips_through_scaling_factor_and_offset(tmp_path):
    reflectance = _texture(SHAPE, 0.031, 0.287).astype(np.float32)
    reflectance[:, :17] = np.nan
    product = write_ortho(_write(tmp_path, reflectance), tmp_path / "out", bits=10)
    image = _label_image(pvl.load(str(product.label_path)))
    scaling, offset = image["SCALING_FACTOR"], image["OFFSET"]
    assert (scaling, offset) == pytest.approx((product.scaling_factor, product.offset), rel=1e-13)
    with rasterio.open(product.jp2_path) as jp2:
        dns = jp2.read(1)
        assert jp2.tags(1, ns="IMAGE_STRUCTURE")["NBITS"] == "10"
    valid = np.isfinite(reflectance)
    assert (dns[~valid] == image["CORE_NULL"]).all()
    assert dns[valid].min() == 3 and dns[valid].max() == 1021
    back = dns[valid] * scaling + offset
    assert np.abs(back - reflectance[valid]).max() <= scaling / 2 * (1 + 1e-6)


def test_range_option_saturates_values_outside(tmp_path):
    data = np.linspace(-1.0, 2.0, 120 * 130, dtype=np.float32).reshape(120, 130)
    product = write_ortho(_write(tmp_path, data), tmp_path / "out", bits=8, value_range=(0.0, 1.0))
    dns = glymur.Jp2k(product.jp2_path)[:]
    assert (dns[data < -0.01] == 1).all() and (dns[data > 1.01] == 255).all()
    inside = (data >= 0) & (data <= 1)
    back = dns[inside] * product.scaling_factor + product.offset
    assert np.abs(back - data[inside]).max() <= product.scaling_factor / 2 * (1 + 1e-6)


def test_wide_integers_are_scaled_and_fitting_ones_kept(tmp_path):
    elevations = _texture((200, 210), -4000, 3000).astype(np.int16)
    product = write_ortho(_write(tmp_path, elevations, name="wide.tif"), tmp_path / "out", bits=8)
    assert product.scaling_factor != 1.0
    small = _texture((200, 210), 3, 1021).astype(np.uint16)
    kept = write_ortho(_write(tmp_path, small, name="small.tif"), tmp_path / "out", bits=10)
    assert (kept.scaling_factor, kept.offset) == (1.0, 0.0)
    np.testing.assert_array_equal(glymur.Jp2k(kept.jp2_path)[:], small)


def test_label_is_pds3_and_pdr_reads_label_and_image(tmp_path):
    data = np.stack([_texture(SHAPE, 0.05, 0.4, seed=s) for s in (1, 2, 3)]).astype(np.float32)
    product = write_ortho(
        _write(tmp_path, data), tmp_path / "out", profile="hirise", observation_id="ESP_042252_1930",
        source_dtm_id="DTEEC_042252_1930_042753_1930_A01", sequence=41,
    )
    assert product.product_id == "ESP_042252_1930_IRB_B_41_ORTHO"
    raw = product.label_path.read_bytes()
    assert all(len(line) <= 80 for line in raw.split(b"\r\n")) and raw.endswith(b"END\r\n")
    label = pvl.loads(raw.decode("ascii"))
    # hidtmgen's order: the DTM the image was projected on, then the observation
    assert label["SOURCE_PRODUCT_ID"] == ["DTEEC_042252_1930_042753_1930_A01", "ESP_042252_1930"]
    compressed, uncompressed = label["COMPRESSED_FILE"], label["UNCOMPRESSED_FILE"]
    image = uncompressed["IMAGE"]
    assert compressed["FILE_NAME"] == product.jp2_path.name
    assert compressed["REQUIRED_STORAGE_BYTES"].value == (
        uncompressed["RECORD_BYTES"].value * uncompressed["FILE_RECORDS"]
    ) == SHAPE[0] * SHAPE[1] * 2 * 3
    assert uncompressed["FILE_RECORDS"] == SHAPE[0] * 3
    assert image["FILTER_NAME"] == ["NEAR-INFRARED", "RED", "BLUE-GREEN"]
    assert [q.value for q in image["CENTER_FILTER_WAVELENGTH"]] == [900, 700, 500]
    assert label["IMAGE_MAP_PROJECTION"]["MAP_PROJECTION_TYPE"] == "EQUIRECTANGULAR"
    assert label["VIEWING_PARAMETERS"]["NORTH_AZIMUTH"].value == 270.0



@pytest.mark.parametrize(("bits", "bands"), [(10, 1), (16, 1), (8, 3)])
def test_pdr_reads_label_and_image(tmp_path, bits, bands):
    """pdr decodes JP2 through Pillow, whose colour modes are 8-bit: 3 bands only at 8 bits.

    Pillow widens 10-bit samples to 16 bits by shifting them left (DN * 64);
    GDAL and OpenJPEG return the DNs themselves.
    """
    pdr = pytest.importorskip("pdr")
    data = np.stack([_texture(SHAPE, 0.05, 0.4, seed=s) for s in range(bands)]).astype(np.float32)
    product = write_ortho(_write(tmp_path, data if bands == 3 else data[0]), tmp_path / "out", bits=bits)
    read = pdr.read(str(product.label_path))
    assert read.metaget("PRODUCT_ID") == product.product_id
    pdr_image = np.asarray(read["IMAGE"])
    decoded = glymur.Jp2k(product.jp2_path)[:]
    expected = decoded if bands == 1 else np.moveaxis(decoded, -1, 0)
    if bits == 10:
        expected = expected << 6
    np.testing.assert_array_equal(pdr_image.reshape(expected.shape), expected)


def test_hirise_red_name_and_source_ids_from_params(tmp_path):
    params = tmp_path / "p.toml"
    params.write_text('SOURCE_PRODUCT_ID = ["ESP_013951_1955", "ESP_014017_1955"]\n')
    data = _texture((100, 120), 0.1, 0.2).astype(np.float32)
    product = write_ortho(
        _write(tmp_path, data, transform=Affine(1.0, 0, 0, 0, -1.0, 0)), tmp_path / "out",
        profile="hirise", params=params, source_dtm_id="DTEEC_013951_1955_014017_1955_U01",
    )
    assert product.product_id == "ESP_013951_1955_RED_C_01_ORTHO"
    label = pvl.load(str(product.label_path))
    # the DTM first (hidtmgen's order), then the sources the params list
    assert label["SOURCE_PRODUCT_ID"] == [
        "DTEEC_013951_1955_014017_1955_U01", "ESP_013951_1955", "ESP_014017_1955"
    ]
    assert _label_image(label)["CENTER_FILTER_WAVELENGTH"].value == 700


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda p: p / "missing.tif", "no such file"),
        (lambda p: (p / "text.tif").write_text("not a raster") and p / "text.tif", "not a raster"),
        (lambda p: write_geotiff(p / "two.tif", np.ones((2, 50, 60), np.uint8), TRANSFORM, EQC, None), "2 bands"),
        (lambda p: write_geotiff(p / "nocrs.tif", np.ones((50, 60), np.uint8), TRANSFORM, None, None),
         "no coordinate reference system"),
        (lambda p: write_geotiff(p / "empty.tif", np.full((50, 60), np.nan, np.float32), TRANSFORM, EQC, None),
         "no valid pixels"),
        (lambda p: write_geotiff(p / "allnull.tif", np.zeros((50, 60), np.uint8), TRANSFORM, EQC, 0),
         "no valid pixels"),
    ],
)
def test_bad_input_exits_2_with_one_line_and_no_output(tmp_path, make, message):
    source = make(tmp_path)
    outdir = tmp_path / "out"
    result = CliRunner().invoke(main, ["ortho", str(source), "-o", str(outdir)])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines() if hasattr(result, "stderr") else result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdsgen: error: ") and message in lines[0]
    assert not outdir.exists() or os.listdir(outdir) == []


def test_bad_options_are_refused(tmp_path):
    source = _write(tmp_path, _texture((50, 60), 0, 1).astype(np.float32))
    with pytest.raises(PdsgenError, match="MIN < MAX"):
        write_ortho(source, tmp_path / "out", value_range=(1.0, 0.0))
    with pytest.raises(PdsgenError, match="`observation_id`"):
        write_ortho(source, tmp_path / "out", profile="hirise")
    with pytest.raises(PdsgenError, match="bits"):
        write_ortho(source, tmp_path / "out", bits=12)
    assert not (tmp_path / "out").exists() or os.listdir(tmp_path / "out") == []


def test_existing_product_is_kept_without_overwrite(tmp_path):
    source = _write(tmp_path, _texture((50, 60), 1, 200).astype(np.uint8))
    first = write_ortho(source, tmp_path / "out")
    before = first.jp2_path.read_bytes()
    with pytest.raises(PdsgenError, match="`overwrite=True`"):
        write_ortho(source, tmp_path / "out")
    assert first.jp2_path.read_bytes() == before
    assert sorted(os.listdir(tmp_path / "out")) == ["IN.JP2", "IN.LBL", "JP2INFO.TXT"]


def test_cli_writes_both_files(tmp_path):
    source = _write(tmp_path, _texture((80, 90), 0.1, 0.3).astype(np.float32), name="demo_red.tif")
    result = CliRunner().invoke(main, ["ortho", str(source), "-o", str(tmp_path / "o"), "--bits", "8", "--gmljp2"])
    assert result.exit_code == 0, result.output
    assert sorted(os.listdir(tmp_path / "o")) == ["DEMO_RED.JP2", "DEMO_RED.LBL", "JP2INFO.TXT"]
    assert "8-bit" in result.output


def test_layout_gives_several_resolution_levels_for_large_images():
    from pdsgen.formats.jp2 import choose_layout

    big = choose_layout(67395, 19243)
    assert big.tile_shape == (TILE_SIZE, TILE_SIZE) and big.resolutions >= 5
    assert choose_layout(8000, 8000).resolutions == 6
    tiny = choose_layout(1, 5)
    assert tiny.tile_shape == (1, 5) and tiny.resolutions == 1


@pytest.mark.parametrize("shape", [(1, 5), (3, 700), (600, 2)])
def test_tiny_and_thin_images(tmp_path, shape):
    data = (np.arange(np.prod(shape)) % 250 + 1).astype(np.uint8).reshape(shape)
    product = write_ortho(_write(tmp_path, data), tmp_path / "out")
    np.testing.assert_array_equal(glymur.Jp2k(product.jp2_path)[:], data)
