"""HiRISE NOMAP Extras (`pdsgen extras --kind nomap`): the six files, read back by GDAL,
glymur, Pillow and jpylyzer, against numbers computed here from the input arrays."""

from __future__ import annotations

import re
import tracemalloc
import warnings
from pathlib import Path

import glymur
import numpy as np
import pytest
import rasterio
from click.testing import CliRunner
from PIL import Image
from rasterio.errors import NotGeoreferencedWarning

from pdsgen.cli import main
from pdsgen.extras import make_extras
from pdsgen.extras.nomap import PRODUCTS, input_stretches, open_inputs, render
from pdsgen.extras.stretch import Stretch
from pdsgen.missions import hirise

OBS = "PSP_005000_1000"
SIX = [f"{OBS}_{p}.NOMAP.{s}" for p in ("RED", "IRB", "RGB") for s in ("JP2", "browse.jpg")]


def mosaics(lines: int = 1500, samples: int = 700, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """10-bit DNs in uint16 (RED, and IRB = IR, RED, BG), DN 0 (no data) down the left edge.

    RED varies much more than BG, on other scales, so 2 x BG - 0.3 x RED is far from
    BG alone; smooth textures keep the lossy JPEG 2000 close to its input.
    """
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[0:lines, 0:samples].astype(np.float32)
    red = 500 + 250 * np.sin(cols / 37.0) * np.cos(rows / 53.0) + rng.normal(0, 3, rows.shape)
    bg = 300 + 45 * np.cos(rows / 29.0 + cols / 61.0) + rng.normal(0, 2, rows.shape)
    ir = 0.6 * red + 150 + 30 * np.sin(rows / 41.0)
    irb = np.stack([ir, red, bg]).clip(3, 1021).astype(np.uint16)
    irb[:, :, :25] = 0
    return irb[1].copy(), irb


def write_plain_tiff(path: Path, data: np.ndarray, **options) -> Path:
    """A GeoTIFF without georeferencing, as a NOMAP mosaic is."""
    bands = data if data.ndim == 3 else data[None]
    path.parent.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotGeoreferencedWarning)
        with rasterio.open(path, "w", driver="GTiff", width=bands.shape[2], height=bands.shape[1],
                           count=bands.shape[0], dtype=bands.dtype.name, tiled=True,
                           **options) as ds:
            ds.write(bands)
    return path


def read(path: Path) -> np.ndarray:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotGeoreferencedWarning)
        with rasterio.open(path) as ds:
            return ds.read()


@pytest.fixture(scope="module")
def nomap_run(tmp_path_factory):
    """One CLI run over a RED and an IRB mosaic (shared by the read-back tests)."""
    tmp = tmp_path_factory.mktemp("nomap")
    red, irb = mosaics()
    red_path = write_plain_tiff(tmp / "in" / f"{OBS}_RED.NOMAP.tif", red)
    irb_path = write_plain_tiff(tmp / "in" / f"{OBS}_IRB.NOMAP.tif", irb)
    out = tmp / "out"
    result = CliRunner().invoke(main, ["extras", "--kind", "nomap", str(red_path), str(irb_path),
                                       "-o", str(out)])
    assert result.exit_code == 0, result.output
    return out, red, irb, red_path, irb_path


def test_the_six_names_and_readme(nomap_run):
    out, *_ = nomap_run
    assert sorted(p.name for p in out.iterdir()) == sorted([*SIX, "README.TXT"])
    assert SIX == [n for n in hirise.rdr_extras_names(OBS) if ".NOMAP." in n]
    readme = (out / "README.TXT").read_bytes().decode("ascii")
    for name in SIX:
        assert f"\r\n    {name}\r\n" in readme
    assert "synthetic blue = 2 x BG - 0.3 x RED" in readme
    assert "not map-projected" in readme and "north is\r\nroughly down" in readme


def test_nomap_jp2s_are_full_scale_and_decode_alike_with_gdal_and_glymur(nomap_run):
    out, red, irb, *_ = nomap_run
    for product, bands in (("RED", 1), ("IRB", 3), ("RGB", 3)):
        path = out / f"{OBS}_{product}.NOMAP.JP2"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            with rasterio.open(path) as ds:
                assert ds.driver == "JP2OpenJPEG" and ds.dtypes[0] == "uint8"
                assert (ds.count, ds.height, ds.width) == (bands, *red.shape)
                assert ds.crs is None  # no map: no invented georeferencing
                by_gdal = ds.read()
        by_glymur = glymur.Jp2k(str(path))[:]
        by_glymur = by_glymur[None] if by_glymur.ndim == 2 else np.moveaxis(by_glymur, -1, 0)
        # Two OpenJPEG builds; the irreversible 9/7 wavelet may round a rare sample apart.
        assert by_gdal.shape == by_glymur.shape
        assert np.abs(by_gdal.astype(int) - by_glymur).max() <= 1
        assert by_gdal[:, :, :20].max() <= 20  # no data stays black (lossy edge)
        assert by_gdal[:, :, 60:].mean() > 60  # data are shown


def test_rgb_third_band_is_the_synthetic_blue(nomap_run):
    """Band 3 of RGB follows 2 x BG - 0.3 x RED of the IRB input, not BG."""
    out, _, irb, *_ = nomap_run
    blue = read(out / f"{OBS}_RGB.NOMAP.JP2")[2].astype(float)[:, 60:]
    red, bg = irb[1].astype(float)[:, 60:], irb[2].astype(float)[:, 60:]
    synthetic = 2.0 * bg - 0.3 * red
    assert np.corrcoef(blue.ravel(), synthetic.ravel())[0, 1] >= 0.99
    assert np.corrcoef(blue.ravel(), bg.ravel())[0, 1] < 0.9  # BG alone would not give it
    # RGB's bands 1 and 2 are IRB's bands 2 and 3 (RED and BG, the same stretch).
    rgb, irb_out = read(out / f"{OBS}_RGB.NOMAP.JP2"), read(out / f"{OBS}_IRB.NOMAP.JP2")
    assert np.abs(rgb[0].astype(int) - irb_out[1]).mean() < 4  # lossy, each its own coding
    assert np.abs(rgb[1].astype(int) - irb_out[2]).mean() < 4


def _readme_stretch(readme: str, pid: str) -> dict[str, tuple[float, float]]:
    block = readme.split(f"Product ID:        {pid}\r\n")[1].split("Product ID:")[0]
    text = " ".join(block.split("Stretch:")[1].split("Projection:")[0].split())
    return {m[1].strip(): (float(m[2]), float(m[3]))
            for m in re.finditer(r"([A-Za-z ]+?) (-?[\d.e+-]+) \.\. (-?[\d.e+-]+)[;( ]", text)}


def test_stretch_points_are_the_0_1_and_0_01_percent_points(nomap_run):
    """Per band, over every valid pixel: README.TXT states them, the JP2s apply them."""
    out, red, irb, *_ = nomap_run
    readme = (out / "README.TXT").read_bytes().decode("ascii")
    valid = irb[1] > 0
    bands = {"IR": irb[0][valid].astype(float), "RED": irb[1][valid].astype(float),
             "BG": irb[2][valid].astype(float)}
    bands["synthetic blue"] = 2.0 * bands["BG"] - 0.3 * bands["RED"]
    expected = {k: np.percentile(v, [0.1, 99.99]) for k, v in bands.items()}
    stated = {**_readme_stretch(readme, f"{OBS}_IRB.NOMAP"),
              **_readme_stretch(readme, f"{OBS}_RGB.NOMAP")}
    assert set(stated) == {"IR", "RED", "BG", "synthetic blue"}
    for name, (low, high) in stated.items():
        assert low == pytest.approx(expected[name][0], abs=1.0), name
        assert high == pytest.approx(expected[name][1], abs=1.0), name
    assert _readme_stretch(readme, f"{OBS}_RED.NOMAP")["RED"] == stated["RED"]
    # Applied: about 0.1 % of the valid pixels at black, 0.01 % at white, per band.
    decoded = read(out / f"{OBS}_IRB.NOMAP.JP2")[:, :, 30:]
    for band in decoded:
        assert 0.0002 < np.mean(band <= 1) < 0.01
        assert np.mean(band >= 254) < 0.003


def test_synthetic_blue_clips_and_never_wraps():
    """Beyond the stretch a band saturates: a blue above `high` is 255, below `low` 0."""
    red = np.array([[0.0, 1000.0, 100.0, 500.0]], dtype=np.float32)
    bg = np.array([[1000.0, 0.0, 50.0, 300.0]], dtype=np.float32)
    data = {2: red, 3: bg}
    valid = {2: np.ones(red.shape, bool), 3: np.ones(red.shape, bool)}
    _, channels = PRODUCTS["RGB"]
    image = render(data, valid, channels, [Stretch(0, 1000), Stretch(0, 1000), Stretch(0, 600)])
    assert image[0, :, 2].tolist() == [255, 0, 30, 191]  # 2000 -> 255, -300 -> 0, 70, 450


def test_browse_widths(nomap_run, tmp_path: Path):
    out, red, *_ = nomap_run
    for product in ("RED", "IRB", "RGB"):  # 700 wide: never enlarged
        with Image.open(out / f"{OBS}_{product}.NOMAP.browse.jpg") as image:
            assert image.size == (red.shape[1], red.shape[0])
            assert image.mode == ("L" if product == "RED" else "RGB")
    wide = np.tile(mosaics(300, 700)[0], (1, 4))  # 2800 x 300
    path = write_plain_tiff(tmp_path / f"{OBS}_RED.NOMAP.tif", wide)
    make_extras([path], tmp_path / "out", kind="nomap")
    with Image.open(tmp_path / "out" / f"{OBS}_RED.NOMAP.browse.jpg") as image:
        assert image.size == (hirise.NOMAP_BROWSE_WIDTH, round(300 * 2048 / 2800))
        browse = np.asarray(image)
    # No scale bar, no north arrow, no margins: the no-data edge is black to the border.
    assert browse[:, :10].max() < 40 and browse[:, 30:].mean() > 60


def test_jpylyzer_finds_the_nomap_jp2s_valid(nomap_run):
    jpylyzer = pytest.importorskip("jpylyzer.jpylyzer")
    out, *_ = nomap_run
    for product in ("RED", "IRB", "RGB"):
        result = jpylyzer.checkOneFile(str(out / f"{OBS}_{product}.NOMAP.JP2"))
        failed = [n.tag for n in result.find("tests").iter() if n.text == "False"]
        assert result.find("isValid").text == "True", failed


def test_isis_cube_of_float_i_over_f(tmp_path: Path):
    """An ISIS cube of I/F floats (GDAL's ISIS3 driver), NULL pixels at its edge."""
    red = mosaics(400, 300)[0].astype(np.float32) * np.float32(1e-4)
    red[:, :25] = -3.4028226550889045e38  # ISIS NULL
    cube = tmp_path / f"{OBS}_RED.NOMAP.cub"
    with rasterio.open(cube, "w", driver="ISIS3", width=300, height=400, count=1,
                       dtype="float32", nodata=-3.4028226550889045e38) as ds:
        ds.write(red[None])
    written = make_extras([cube], tmp_path / "out", kind="nomap")
    assert [p.name for p in written] == [f"{OBS}_RED.NOMAP.JP2", f"{OBS}_RED.NOMAP.browse.jpg",
                                         "README.TXT"]
    decoded = read(tmp_path / "out" / f"{OBS}_RED.NOMAP.JP2")[0]
    assert decoded[:, :20].max() <= 20 and decoded[:, 40:].mean() > 60
    low, high = np.percentile(red[:, 25:], [0.1, 99.99])
    readme = (tmp_path / "out" / "README.TXT").read_bytes().decode("ascii")
    (stated_low, stated_high), = _readme_stretch(readme, f"{OBS}_RED.NOMAP").values()
    span = float(red[:, 25:].max() - red[:, 25:].min())
    assert abs(stated_low - low) < 1e-3 * span and abs(stated_high - high) < 1e-3 * span


def test_product_id_gives_the_observation(tmp_path: Path):
    red, irb = mosaics(200, 150)
    a = write_plain_tiff(tmp_path / "red_mosaic.tif", red)
    b = write_plain_tiff(tmp_path / "colour_mosaic.tif", irb)
    result = CliRunner().invoke(main, ["extras", "--kind", "nomap", str(a), str(b), "-o",
                                       str(tmp_path / "out"), "--product-id", "ESP_012345_1234"])
    assert result.exit_code == 0, result.output
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == sorted([n.replace(OBS, "ESP_012345_1234") for n in SIX] + ["README.TXT"])


@pytest.mark.parametrize("case", ["irb_two_bands", "no_observation", "two_observations",
                                  "product_id_without_nomap", "relief_option_with_nomap"])
def test_bad_inputs_one_line_exit_2_nothing_written(tmp_path: Path, case: str):
    red, irb = mosaics(120, 100)
    args = []
    if case == "irb_two_bands":
        args = [write_plain_tiff(tmp_path / f"{OBS}_RED.NOMAP.tif", red),
                write_plain_tiff(tmp_path / f"{OBS}_IRB.NOMAP.tif", irb[:2])]
        expected = f"{OBS}_IRB.NOMAP.tif: has 2 bands; an IRB NOMAP mosaic needs 3"
    elif case == "no_observation":
        args = [write_plain_tiff(tmp_path / "red.tif", red)]
        expected = "red.tif: names no HiRISE observation ID"
    elif case == "two_observations":
        args = [write_plain_tiff(tmp_path / f"{OBS}_RED.NOMAP.tif", red),
                write_plain_tiff(tmp_path / "ESP_011111_2222_IRB.NOMAP.tif", irb)]
        expected = "ESP_011111_2222_IRB.NOMAP.tif: is of observation ESP_011111_2222"
    extra = ["--product-id", OBS] if case == "product_id_without_nomap" else ["--kind", "nomap"]
    if case == "relief_option_with_nomap":
        args = [write_plain_tiff(tmp_path / f"{OBS}_RED.NOMAP.tif", red)]
        extra += ["--thumb-width", "300"]
        expected = "--thumb-width has no use with --kind nomap"
    if case == "product_id_without_nomap":
        args = [write_plain_tiff(tmp_path / "red.tif", red)]
        expected = "--product-id names a NOMAP observation; it needs --kind nomap"
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["extras", *map(str, args), "-o", str(out), *extra])
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and expected in result.stderr, result.stderr
    assert "Traceback" not in result.output
    assert not out.exists()


def test_input_stretches_stream_and_memory_stays_flat(tmp_path: Path, monkeypatch):
    """A 4x taller IRB mosaic costs no more memory: strips, tile windows, browse strips."""
    from pdsgen.extras import nomap

    peaks = {}
    windows = []
    real = nomap._read_bands

    def spy(ds, bands, window):
        windows.append(window.height * window.width)
        return real(ds, bands, window)

    monkeypatch.setattr(nomap, "_read_bands", spy)
    for lines in (2048, 8192):
        irb = np.tile(mosaics(1024, 1024)[1], (1, lines // 1024, 1))
        path = write_plain_tiff(tmp_path / str(lines) / f"{OBS}_IRB.NOMAP.tif", irb)
        del irb
        tracemalloc.start()
        make_extras([path], tmp_path / str(lines) / "out", kind="nomap", browse_width=256)
        peaks[lines] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    raster_growth = 3 * 2 * 1024 * (8192 - 2048)  # bytes the taller input adds
    assert peaks[8192] - peaks[2048] < 0.05 * raster_growth, peaks
    assert peaks[8192] < 3 * 2 * 1024 * 8192  # less than the raw input alone
    assert max(windows) <= 1024 * 1024  # never more than a tile or a strip of input


def test_open_inputs_takes_roles_from_names_or_band_count(tmp_path: Path):
    red, irb = mosaics(50, 40)
    a = write_plain_tiff(tmp_path / "a.tif", irb)
    b = write_plain_tiff(tmp_path / "b.tif", red)
    observation, inputs = open_inputs([a, b], "PSP_000001_0001")
    assert observation == "PSP_000001_0001" and set(inputs) == {"RED", "IRB"}
    assert inputs["IRB"].path == a and inputs["RED"].nodata == 0.0
    stretches = input_stretches(inputs["RED"], PRODUCTS["RED"][1])
    (stretch,) = stretches.values()
    assert stretch is not None
    assert (stretch.low, stretch.high) == tuple(
        float(v) for v in np.percentile(red[red > 0], [0.1, 99.99], method="lower"))


def test_a_batch_extras_job_makes_nomap_extras_with_product_id(tmp_path: Path):
    """`kind = "nomap"` and `product_id` in a manifest's [[extras]] reach the library."""
    from pdsgen.batch import Settings, load_manifest
    from pdsgen.batch.run import make_task
    from pdsgen.batch.worker import run_job

    red, irb = mosaics(120, 100)
    write_plain_tiff(tmp_path / "in" / "red.tif", red)
    write_plain_tiff(tmp_path / "in" / "irb.tif", irb)
    (tmp_path / "batch.toml").write_text("""
[[extras]]
id = "nomap"
inputs = ["in/red.tif", "in/irb.tif"]
kind = "nomap"
product_id = "ESP_012345_1234"
outdir = "extras"
""", encoding="utf-8")
    manifest = load_manifest(tmp_path / "batch.toml", tmp_path / "out")
    (job,) = manifest.jobs
    outcome = run_job(make_task(job, manifest, Settings(), {}))
    assert outcome["status"] == "done", outcome
    names = {p.name for p in (tmp_path / "out" / "extras").iterdir()}
    assert names == {n.replace(OBS, "ESP_012345_1234") for n in SIX} | {"README.TXT"}


def test_one_line_blocks_are_read_many_lines_at_a_time(tmp_path: Path):
    """A raster whose blocks are single lines (a PDS .IMG, a striped TIFF) is read in strips of
    many lines, not a read per line (the full-resolution RDR stretch did that)."""
    from pdsgen.extras import full_stretch
    from pdsgen.formats.raster import bounded_windows

    path = tmp_path / "lines.tif"
    with rasterio.open(path, "w", driver="GTiff", width=600, height=2000, count=3, dtype="uint16",
                       blockysize=1) as ds:
        ds.write(np.ones((3, 2000, 600), np.uint16))
    with rasterio.open(path) as ds:
        assert ds.block_shapes[0][0] == 1
        windows = list(bounded_windows(ds, full_stretch.STRIP_BYTES, full_stretch.WINDOW_PIXELS))
    assert len(windows) <= 4 and sum(w.width * w.height for w in windows) == 600 * 2000


def test_statistics_windows_cover_a_wide_mosaic_once_in_bounded_pieces(tmp_path: Path):
    from pdsgen.extras import nomap
    from pdsgen.formats.raster import bounded_windows

    path = write_plain_tiff(tmp_path / "wide.tif", np.ones((3, 1100, 5000), np.uint16))
    with rasterio.open(path) as ds:
        windows = list(bounded_windows(ds, nomap.STATISTICS_STRIP_BYTES, nomap.WINDOW_PIXELS))
    covered = np.zeros((1100, 5000), np.int8)
    for w in windows:
        assert w.width * w.height <= nomap.WINDOW_PIXELS
        covered[w.row_off:w.row_off + w.height, w.col_off:w.col_off + w.width] += 1
    assert (covered == 1).all()
