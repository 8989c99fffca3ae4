"""End to end: make_extras and `pdsgen extras` on GeoTIFFs, pdsgen .IMG, JP2 + .LBL, MOLA."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pvl
import pytest
import rasterio
import rasterio.errors
from click.testing import CliRunner
from PIL import Image, JpegImagePlugin

from pdsgen.cli import main
from pdsgen.errors import PdsgenError
from pdsgen.extras import make_extras
from pdsgen.extras.colour_ramp import first_colour
from test_extras_helpers import MARS_NORTH_POLAR, crater_field, write_geotiff

DTM_CODES = ("br", "ab", "th", "sb", "sa", "st", "cb", "ca", "ct")
ORTHO_CODES = ("browse", "abrowse", "thumb")


def rgb(path: Path) -> np.ndarray:
    with Image.open(path) as im:
        assert im.format == "JPEG"
        return np.asarray(im.convert("RGB")).astype(int)


def check_jpeg_set(outdir: Path, pid: str, codes: tuple[str, ...], browse_width: int,
                   thumb_width: int = 128) -> dict[str, np.ndarray]:
    images = {}
    for code in codes:
        path = outdir / f"{pid}.{code}.jpg"
        with warnings.catch_warnings():  # a JPEG has no georeferencing, as intended
            warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
            with rasterio.open(path) as ds:  # an independent JPEG reader (GDAL/libjpeg)
                assert ds.driver == "JPEG" and ds.count in (1, 3)
        images[code] = rgb(path)
        assert images[code].std() > 5, f"{path.name} is blank"
    for code in codes[1::3]:  # annotated: full chroma resolution (4:4:4)
        with Image.open(outdir / f"{pid}.{code}.jpg") as im:
            assert im.mode == "RGB" and JpegImagePlugin.get_sampling(im) == 0
    for browse, annotated, thumb in zip(codes[0::3], codes[1::3], codes[2::3], strict=True):
        b, a, t = images[browse], images[annotated], images[thumb]
        assert b.shape[1] == browse_width and t.shape[1] == thumb_width
        assert a.shape[0] > b.shape[0] and a.shape[1] > b.shape[1]
    return images


def is_grey(image: np.ndarray) -> bool:
    return bool((image[..., 0] == image[..., 1]).all() and (image[..., 1] == image[..., 2]).all())


def is_colourful(image: np.ndarray) -> bool:
    chroma = image.max(axis=-1) - image.min(axis=-1)
    return float(np.percentile(chroma, 75)) > 30


@pytest.fixture()
def dtm_tif(tmp_path: Path) -> Path:
    z = crater_field(480, 640)
    z[200:230, 300:340] = -3.4028226550889045e38
    return write_geotiff(tmp_path / "in" / "crater_dtm.tif", z, nodata=-3.4028226550889045e38)


@pytest.fixture(autouse=True)
def _mkdirs(tmp_path: Path) -> None:
    (tmp_path / "in").mkdir()


def test_dtm_geotiff_gives_nine_previews_and_readme(dtm_tif: Path, tmp_path: Path):
    out = tmp_path / "out"
    written = make_extras([dtm_tif], out, browse_width=320)
    assert sorted(p.name for p in written) == sorted(
        [f"crater_dtm.{c}.jpg" for c in DTM_CODES] + ["README.TXT"])
    images = check_jpeg_set(out, "crater_dtm", DTM_CODES, 320)
    for code in ("br", "ab", "th", "sb", "sa", "st"):
        assert is_grey(images[code]), code
    for code in ("cb", "ca", "ct"):
        assert is_colourful(images[code]), code
    # The hole is black (no data) in the browse; valid data never is.
    hole = images["sb"][200 * 320 // 640 + 3, 320 * 320 // 640 + 3]
    assert hole.max() <= 12
    # Thumbnail and browse share one stretch: same mean brightness.
    for browse, thumb in (("br", "th"), ("cb", "ct")):
        assert abs(images[browse].mean() - images[thumb].mean()) < 4.0


def test_pdsgen_dtm_img_readme_has_label_valid_range_and_lowest_height_is_first_colour(
        tmp_path: Path):
    from pdsgen import write_dtm

    z = crater_field(400, 600)
    z[:, :120] = float(z.min()) - 50.0           # a wide flat plain, the lowest ground
    tif = write_geotiff(tmp_path / "in" / "plain.tif", z, nodata=-3.4028226550889045e38)
    product = write_dtm(tif, tmp_path / "products", product_id="PLAIN_DTM_TEST")
    out = tmp_path / "extras"
    make_extras([product.path], out, browse_width=300, credit="Test credit")
    images = check_jpeg_set(out, "PLAIN_DTM_TEST", DTM_CODES, 300)
    plain = images["cb"][50:350, 5:50].reshape(-1, 3).mean(axis=0)
    assert np.abs(plain - np.array(first_colour())).max() <= 6

    label = pvl.loads(product.label_text)
    readme = (out / "README.TXT").read_bytes()
    text = readme.decode("ascii")
    for key in ("VALID_MINIMUM", "VALID_MAXIMUM"):
        value = float(label["IMAGE"][key])
        shown = re.search(rf"{key}:\s+(\S+)", text).group(1)
        assert float(shown) == pytest.approx(value, rel=1e-9)
    assert "PLAIN_DTM_TEST.ca.jpg" in text and "Test credit" in text
    check_plain_text(readme)


def check_plain_text(data: bytes) -> None:
    assert all(b < 128 for b in data)
    assert data.endswith(b"\r\n")
    lines = data.split(b"\r\n")[:-1]
    assert all(b"\n" not in line and b"\r" not in line for line in lines)
    assert max(len(line) + 2 for line in lines) <= 80


def test_three_band_ortho_geotiff_is_shown_in_colour_each_band_stretched(tmp_path: Path):
    rows, cols = np.mgrid[0:300, 0:500]
    # Different patterns and ranges per band: a colour scene once each is stretched.
    bands = np.stack([60 + cols * 0.1, 100 + rows * 0.3, 150 + 20 * np.sin(cols / 9.0)])
    bands = np.clip(bands, 1, 255).astype(np.uint8)
    bands[:, :, :40] = 0
    tif = write_geotiff(tmp_path / "in" / "ESP_000001_0001_IRB_B_01_ORTHO.tif", bands,
                        nodata=0)
    out = tmp_path / "out"
    make_extras([tif], out, browse_width=250, thumb_width=64)
    images = check_jpeg_set(out, "ESP_000001_0001_IRB_B_01_ORTHO", ORTHO_CODES, 250, 64)
    data = images["browse"][:, 30:]
    assert is_colourful(images["browse"])
    # Each band is stretched on its own: all three span (nearly) the full range.
    for c in range(3):
        assert data[..., c].min() <= 20 and data[..., c].max() >= 235
    assert images["browse"][:, :15].max() <= 12  # no-data is black


def test_jp2_with_detached_label_uses_core_null_and_product_id(tmp_path: Path):
    rng = np.random.default_rng(5)
    dn = rng.integers(300, 900, (400, 640)).astype(np.uint16)
    dn[:, :100] = 0  # CORE_NULL
    jp2 = write_geotiff(tmp_path / "in" / "esp_x_red.jp2", dn, driver="JP2OpenJPEG",
                        QUALITY=100, REVERSIBLE="YES", RESOLUTIONS=4)
    (tmp_path / "in" / "esp_x_red.lbl").write_text(
        "PDS_VERSION_ID = PDS3\r\nPRODUCT_ID = ESP_012345_1234_RED_B_01_ORTHO\r\n"
        "OBJECT = COMPRESSED_FILE\r\n  FILE_NAME = \"ESP_X_RED.JP2\"\r\n"
        "  ENCODING_TYPE = \"JP2\"\r\nEND_OBJECT = COMPRESSED_FILE\r\n"
        "OBJECT = UNCOMPRESSED_FILE\r\n  OBJECT = IMAGE\r\n    LINES = 400\r\n"
        "    LINE_SAMPLES = 640\r\n    SAMPLE_TYPE = MSB_UNSIGNED_INTEGER\r\n"
        "    SAMPLE_BITS = 16\r\n    SCALING_FACTOR = 0.0001\r\n    OFFSET = 0.05\r\n"
        "    CORE_NULL = 0\r\n    CORE_HIGH_REPR_SATURATION = 1023\r\n"
        "  END_OBJECT = IMAGE\r\nEND_OBJECT = UNCOMPRESSED_FILE\r\nEND\r\n")
    out = tmp_path / "out"
    for product in (tmp_path / "in" / "esp_x_red.lbl", jp2):
        make_extras([product], out, browse_width=320, overwrite=True)
        pid = "ESP_012345_1234_RED_B_01_ORTHO"
        images = check_jpeg_set(out, pid, ORTHO_CODES, 320)
        assert is_grey(images["browse"])
        browse = images["browse"][..., 0]
        assert browse[:, :45].max() <= 10            # null margin black, no grey fringe
        assert browse[:, 60:].min() <= 10 and browse[:, 60:].max() >= 245
        text = (out / "README.TXT").read_text()
        assert "I/F = DN * 0.0001 + 0.05" in text


def test_mola_megdr_from_the_corpus(corpus_dir: Path, tmp_path: Path):
    label = corpus_dir / "products" / "MOLA_MEGDR_megt90n000cb" / "megt90n000cb.lbl"
    out = tmp_path / "out"
    make_extras([label], out, browse_width=360)
    images = check_jpeg_set(out, "MEGT90N000CB", DTM_CODES, 360)
    assert is_grey(images["br"]) and is_colourful(images["cb"])
    text = (out / "README.TXT").read_bytes().decode("ascii")
    assert re.search(r"VALID_MINIMUM:\s+-8068\b", text)
    assert re.search(r"VALID_MAXIMUM:\s+21134\b", text)
    # 1440 px of 0.25 deg at the equator of a 3396 km sphere, shown 360 px wide.
    assert "14818 m per product pixel" in text.replace(",", "")


def test_cli_writes_extras_and_reports_bad_input_in_one_line(dtm_tif: Path, tmp_path: Path):
    runner = CliRunner()
    out = tmp_path / "cli"
    ok = runner.invoke(main, ["extras", str(dtm_tif), "-o", str(out), "--browse-width", "200",
                              "--thumb-width", "100", "--azimuth", "300", "--credit", "ME"])
    assert ok.exit_code == 0, ok.output
    assert (out / "crater_dtm.ca.jpg").exists() and (out / "README.TXT").exists()
    assert Image.open(out / "crater_dtm.th.jpg").width == 100

    again = runner.invoke(main, ["extras", str(dtm_tif), "-o", str(out)])
    assert again.exit_code == 2
    assert again.stderr.count("\n") == 1 and "use --overwrite" in again.stderr

    bogus = tmp_path / "in" / "notes.img"
    bogus.write_text("this is not an image\n")
    fresh = tmp_path / "fresh"
    bad = runner.invoke(main, ["extras", str(dtm_tif), str(bogus), "-o", str(fresh)])
    assert bad.exit_code == 2
    assert bad.stderr.startswith("pdsgen: error: ") and "notes.img" in bad.stderr
    assert bad.stderr.count("\n") == 1 and "Traceback" not in bad.output
    assert not fresh.exists() or not any(fresh.iterdir())  # nothing written for anyone


def test_missing_file_and_bad_kind_are_user_errors(tmp_path: Path):
    with pytest.raises(PdsgenError, match="no such file"):
        make_extras([tmp_path / "nope.IMG"], tmp_path / "out")
    z = crater_field(50, 60)
    tif = write_geotiff(tmp_path / "in" / "small.tif", z)
    with pytest.raises(PdsgenError, match="unknown product kind"):
        make_extras([tif], tmp_path / "out", kind="map")


def test_kind_override_renders_a_float_image_as_an_ortho(tmp_path: Path):
    refl = (np.random.default_rng(1).random((200, 300)) * 0.2).astype(np.float32)
    tif = write_geotiff(tmp_path / "in" / "refl.tif", refl)
    out = tmp_path / "out"
    make_extras([tif], out, kind="ortho", browse_width=150)
    check_jpeg_set(out, "refl", ORTHO_CODES, 150)


def test_readme_takes_producer_contact_and_known_artifacts_from_params(dtm_tif: Path,
                                                                      tmp_path: Path):
    params = tmp_path / "in" / "params.toml"
    params.write_text(
        'PROJECT_NAME = "HiRISE DTM test project"\n'
        'PRODUCER_FULL_NAME = "A. Producer"\n'
        'TECHNICAL_CONTACT = "A. Producer, Lunar and Planetary Laboratory, Tucson AZ"\n'
        'CREDIT = "NASA/JPL/Somebody"\n'
        'KNOWN_ARTIFACTS = "' + "Faint seams run north-south where the stereo pair "
        "overlaps; patches of interpolated terrain fill shadowed crater floors. " * 3 + '"\n')
    out = tmp_path / "out"
    make_extras([dtm_tif], out, params=params, browse_width=200)
    data = (out / "README.TXT").read_bytes()
    check_plain_text(data)
    text = data.decode("ascii")
    assert text.startswith("HiRISE DTM test project\r\n=======")
    assert "A. Producer, Lunar and Planetary" in text and "NASA/JPL/Somebody" in text
    artifacts = text.split("KNOWN ARTIFACTS")[1]
    assert "Faint seams run" in artifacts and "crater floors." in artifacts
    assert "crater_dtm.sa.jpg" in text and "crater_dtm.th.jpg" in text
    # The computed range is the real one of the full raster.
    with rasterio.open(dtm_tif) as ds:
        full = ds.read(1, masked=True)
    shown = re.search(r"VALID_MINIMUM:\s+(\S+)", text).group(1)
    assert float(shown) == pytest.approx(float(full.min()), rel=1e-7)


def test_unknown_params_keyword_is_refused_before_anything_is_written(dtm_tif: Path,
                                                                      tmp_path: Path):
    params = tmp_path / "in" / "params.toml"
    params.write_text('CONTACT_PERSON = "typo"\n')
    with pytest.raises(PdsgenError, match="unknown keyword"):
        make_extras([dtm_tif], tmp_path / "out", params=params)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("origin", [(300000.0, 2000.0), (-1600.0, 1200.0)])
def test_polar_stereographic_products_off_and_on_the_pole(tmp_path: Path, origin):
    z = crater_field(240, 320)
    tif = write_geotiff(tmp_path / "in" / "polar.tif", z, crs=MARS_NORTH_POLAR, pixel=10.0,
                        origin=origin)
    out = tmp_path / "out"
    make_extras([tif], out, browse_width=160)
    check_jpeg_set(out, "polar", DTM_CODES, 160)
    assert "POLAR" in (out / "README.TXT").read_text().upper()


def test_product_without_georeferencing_and_non_ascii_credit_are_refused(tmp_path: Path):
    plain = tmp_path / "in" / "plain.tif"
    with rasterio.open(plain, "w", driver="GTiff", width=40, height=30, count=1,
                       dtype="float32") as ds:
        ds.write(crater_field(30, 40), 1)
    with pytest.raises(PdsgenError, match="no map projection"):
        make_extras([plain], tmp_path / "out")
    tif = write_geotiff(tmp_path / "in" / "ok.tif", crater_field(30, 40))
    with pytest.raises(PdsgenError, match="ASCII"):
        make_extras([tif], tmp_path / "out", credit="NASA/JPL/Universit\u00e9")
    assert not (tmp_path / "out").exists()


def test_mola_image_file_is_found_through_its_sibling_label(corpus_dir: Path, tmp_path: Path):
    image = corpus_dir / "products" / "MOLA_MEGDR_megt90n000cb" / "megt90n000cb.img"
    written = make_extras([image], tmp_path / "out", browse_width=200, thumb_width=50)
    assert {p.name for p in written} >= {"MEGT90N000CB.ca.jpg", "MEGT90N000CB.st.jpg"}


def test_archived_label_whose_data_file_is_absent_is_a_clear_error(corpus_dir: Path,
                                                                   tmp_path: Path):
    label = corpus_dir / "real" / "ESP_013951_1955_RED.LBL"
    with pytest.raises(PdsgenError, match="byte.tif"):
        make_extras([label], tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_damaged_data_leaks_no_library_warning(tmp_path: Path):
    """Garbage floats from a damaged tile: numpy/rasterio warnings stay inside."""
    z = crater_field(300, 400)
    tif = write_geotiff(tmp_path / "in" / "damaged.tif", z, compress="deflate", tiled=True)
    data = bytearray(tif.read_bytes())
    middle = len(data) // 3
    data[middle:middle + 2000] = b"\x55" * 2000
    tif.write_bytes(bytes(data))
    result = CliRunner().invoke(main, ["extras", str(tif), "-o", str(tmp_path / "out"),
                                       "--kind", "dtm"])
    assert "Warning" not in result.stderr and "Traceback" not in result.output
    assert "previous exception" not in result.stderr
    assert result.stderr.count("\n") == 1  # the kind line, or one error line


def test_credit_and_title_come_from_the_product(corpus_dir: Path, tmp_path: Path):
    label = corpus_dir / "products" / "MOLA_MEGDR_megt90n000cb" / "megt90n000cb.lbl"
    out = tmp_path / "out"
    make_extras([label], out, browse_width=360)
    text = " ".join((out / "README.TXT").read_text().split())
    assert "Image credit: MARS GLOBAL SURVEYOR / GODDARD SPACE FLIGHT CENTER" in text
    assert "University of Arizona" not in text
    assert "Label identifier: MEGT90N000CB.IMG" in text  # the title, as the label writes it
    assert "Heights: metres above the Mars areoid" in text


def test_truncated_jp2_is_one_line_without_gdal_messages(tmp_path: Path):
    """Run as a real process: GDAL writes its own messages to file descriptor 2."""
    from pdsgen.products import ortho

    from helpers import run_cli

    rng = np.random.default_rng(3)
    iof = (0.05 + 0.1 * rng.random((1100, 1200))).astype(np.float32)
    tif = write_geotiff(tmp_path / "in" / "o.tif", iof)
    product = ortho.write_ortho(tif, tmp_path / "p", product_id="CUT")
    with open(product.jp2_path, "r+b") as handle:
        handle.truncate(product.jp2_path.stat().st_size // 3)
    result = run_cli("extras", product.label_path, "-o", tmp_path / "out")
    assert result.returncode == 2 and result.stderr.count("\n") == 1, result.stderr
    assert "CUT.LBL: cannot read the raster" in result.stderr
    assert "ERROR" not in result.stderr and "previous exception" not in result.stderr
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())
