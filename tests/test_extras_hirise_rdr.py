"""Map-projected HiRISE RDR Extras from genuine-shaped RDR labels: RED and COLOR.

The labels are the release's own (`tests/data/hirise_rdr/ESP_013951_1955_RED.LBL`,
see PROVENANCE.md) with the file name, size and observation filled in for a small
JPEG 2000 written here: 10-bit DNs with DN 0 (CORE_NULL) outside a skewed swath,
as a map-projected RDR holds them.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import rasterio
from PIL import Image

from pdsgen.extras import make_extras
from pdsgen.extras.product_source import open_product
from pdsgen.extras.renderings import render_product
from pdsgen.formats.jp2 import write_jp2
from pdsgen.missions import hirise

GENUINE = Path(__file__).parent / "data" / "hirise_rdr" / "ESP_013951_1955_RED.LBL"
OBS = "PSP_005000_1000"
SCALING, OFFSET = 1.07543902665525e-04, 0.081203337858079  # the genuine label's


def _set(text: str, key: str, value: str) -> str:
    """Replace one keyword's (one-line) value, keeping the label's layout."""
    new, count = re.subn(rf"(?m)^(\s*{key}\s*=\s*)\S.*$", lambda m: m.group(1) + value, text,
                         count=1)
    assert count == 1, key
    return new


def write_rdr(folder: Path, colour: str, dn: np.ndarray) -> Path:
    """`<OBS>_<colour>.JP2` (lossless, 10-bit) and its detached label; returns the label."""
    bands, lines, samples = dn.shape
    folder.mkdir(parents=True, exist_ok=True)
    jp2 = folder / f"{OBS}_{colour}.JP2"
    rows = np.moveaxis(dn, 0, -1) if bands == 3 else dn[0]
    write_jp2(jp2, lines, samples, bands, 10, lambda first, count: rows[first:first + count])
    text = GENUINE.read_text("ascii")
    for key, value in (("OBSERVATION_ID", f'"{OBS}"'), ("PRODUCT_ID", f'"{OBS}_{colour}"'),
                       ("LINE_LAST_PIXEL", str(lines)), ("SAMPLE_LAST_PIXEL", str(samples)),
                       ("FILE_NAME", f'"{jp2.name}"'), ("RECORD_BYTES", f"{2 * samples} <BYTES>"),
                       ("FILE_RECORDS", str(lines * bands)), ("LINES", str(lines)),
                       ("LINE_SAMPLES", str(samples)), ("BANDS", str(bands))):
        text = _set(text, key, value)
    if bands == 3:  # a COLOR RDR: IR, RED, BG
        text = _set(text, "CENTER_FILTER_WAVELENGTH", "(900, 700, 500) <NM>")
        text = _set(text, "FILTER_NAME", '("NEAR-INFRARED", "RED", "BLUE-GREEN")')
    label = folder / f"{OBS}_{colour}.LBL"
    label.write_bytes(text.replace("\n", "\r\n").encode("ascii"))
    return label


def swath(lines: int, samples: int, bands: int, seed: int = 5) -> np.ndarray:
    """10-bit DNs in a skewed swath (DN 0 outside); each band its own range."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[0:lines, 0:samples].astype(np.float32)
    out = []
    for b in range(bands):
        base, amp = (650 - 200 * b, 120 + 60 * b)
        layer = base + amp * np.sin(cols / (31.0 + 7 * b)) * np.cos(rows / 47.0)
        out.append(layer + rng.normal(0, 8, rows.shape))
    dn = np.stack(out).clip(3, 1021).astype(np.uint16)
    skew = cols - 0.1 * rows
    dn[:, (skew < 0.08 * samples) | (skew > 0.92 * samples - 0.1 * lines)] = 0
    return dn


@pytest.fixture(scope="module")
def rdrs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("rdr")
    red = swath(1600, 4096, 1)
    color = swath(1500, 800, 3, seed=6)
    color[0, 700:720, 300:400] = 1023  # saturated: flags, not data
    return (write_rdr(folder, "RED", red), red, write_rdr(folder, "COLOR", color), color)


def test_the_six_map_projected_names(rdrs, tmp_path: Path):
    red_label, _, color_label, _ = rdrs
    out = tmp_path / "out"
    make_extras([red_label, color_label], out)
    names = {p.name for p in out.iterdir()}
    six = hirise.rdr_extras_names(OBS)[:6]
    assert six == [f"{OBS}_{c}.{s}" for c in ("RED", "COLOR")
                   for s in ("QLOOK.JP2", "browse.jpg", "abrowse.jpg")]
    assert names == {*six, f"{OBS}_RED.thumb.jpg", f"{OBS}_COLOR.thumb.jpg", "README.TXT"}
    for label in (red_label, color_label):  # named by the .JP2 instead: the same product
        by_jp2 = open_product(label.with_suffix(".JP2"))
        assert (by_jp2.label_path, by_jp2.product_id) == (label, label.stem)
    with Image.open(out / f"{OBS}_RED.browse.jpg") as image:
        assert image.size == (2048, round(1600 * 2048 / 4096))
    with Image.open(out / f"{OBS}_COLOR.browse.jpg") as image:
        assert image.size == (800, 1500) and image.mode == "RGB"  # never enlarged
    # GDAL's PDS driver reads the genuine-shaped label itself (through COMPRESSED_FILE):
    # the quick look sits on the same ground, corners and centre in metres.
    with rasterio.open(red_label) as rdr, rasterio.open(out / f"{OBS}_RED.QLOOK.JP2") as ql:
        assert rdr.driver == "PDS"
        assert (ql.width, ql.height, ql.count, ql.dtypes[0]) == (4096, 1600, 1, "uint8")
        for col, row in ((0, 0), (4096, 1600), (2048, 800)):
            assert ql.transform @ (col, row) == pytest.approx(rdr.transform @ (col, row),
                                                              abs=0.01)
        assert ql.transform @ (0, 0) == pytest.approx((-12278396 * 0.5, 1872007 * 0.5))


def test_color_bands_each_stretched_at_0_1_and_0_01_percent(rdrs, tmp_path: Path):
    _, _, color_label, color = rdrs
    src = open_product(color_label)
    assert (src.band_count, src.scale, src.offset, src.nodata) == (3, SCALING, OFFSET, 0.0)
    previews = render_product(src, credit="", browse_width=None, thumb_width=128,
                              azimuth=315, altitude=45)
    # Exact, from every pixel: the 0.1 % and 99.99 % order statistics of the valid DNs
    # (no data and the CORE_* saturation DNs left out), in I/F.
    for band, stretch in zip(color, previews.stretches, strict=True):
        assert stretch is not None
        valid = band[(band > 0) & ~np.isin(band, [1, 2, 1022, 1023])].astype(float)
        low, high = np.percentile(valid, [0.1, 99.99], method="lower") * SCALING + OFFSET
        assert stretch.low == pytest.approx(low, rel=1e-12)
        assert stretch.high == pytest.approx(high, rel=1e-12)
    # Each band on its own: three different ranges, as the bands have.
    assert len({round(s.low, 4) for s in previews.stretches if s}) == 3
    out = tmp_path / "out"
    make_extras([color_label], out)
    with rasterio.open(out / f"{OBS}_COLOR.QLOOK.JP2") as ql:
        shown = ql.read()
    inside = color[0] > 0
    for band in shown:
        values = band[inside]
        assert np.mean(values <= 2) < 0.01 and np.mean(values >= 253) < 0.01
        assert values.min() <= 10 and values.max() >= 245  # the full range is used


def _expected_metres_per_browse_pixel(lines: int, step: float) -> float:
    """MAP_SCALE (true at CENTER_LATITUDE) scaled to the image centre's parallel."""
    radius = 3394.8398133163e3
    centre_line = 1872006.5 - lines / 2.0
    latitude = math.degrees(centre_line * 0.5 / radius)
    return 0.5 * step * math.cos(math.radians(latitude)) / math.cos(math.radians(15.0))


def test_red_abrowse_has_title_and_a_scale_bar_matching_map_scale(rdrs, tmp_path: Path):
    red_label, red, _, _ = rdrs
    src = open_product(red_label)
    assert src.title == f"{OBS}_RED" and src.georeferencing == "label"
    previews = render_product(src, credit="NASA/JPL/University of Arizona", browse_width=None,
                              thumb_width=128, azimuth=315, altitude=45)
    layout = previews.previews[0].layout
    mpp = _expected_metres_per_browse_pixel(red.shape[1], 4096 / 2048)
    bar = layout.scale_bar
    assert abs(bar.pixels - bar.metres / mpp) <= 1
    assert bar.pixels != round(bar.metres / 1.0)  # true scale at the centre, not MAP_SCALE x 2
    out = tmp_path / "out"
    make_extras([red_label], out)
    with Image.open(out / f"{OBS}_RED.abrowse.jpg") as image:
        annotated = np.asarray(image.convert("L")).astype(int)
    x0, y0, x1, _ = layout.scale_bar_box
    row = annotated[y0 + 1]
    dark = np.flatnonzero(row[: x1 + 40] < 100)
    assert dark.min() == pytest.approx(x0, abs=1) and dark.max() == pytest.approx(x1, abs=1)
    image_top = layout.image_box[1]
    assert (annotated[:image_top - 2] < 100).sum() > 200  # the title and subtitle lines


def test_readme_indexes_all_twelve_merged_with_the_directory(rdrs, tmp_path: Path):
    """Map-projected run, then the NOMAP run into the same directory, then NOMAP again."""
    from test_extras_nomap import mosaics, write_plain_tiff

    red_label, _, color_label, _ = rdrs
    out = tmp_path / "out"
    make_extras([red_label, color_label], out)
    red, irb = mosaics(300, 200)
    nomaps = [write_plain_tiff(tmp_path / f"{OBS}_RED.NOMAP.tif", red),
              write_plain_tiff(tmp_path / f"{OBS}_IRB.NOMAP.tif", irb)]
    make_extras(nomaps, out, kind="nomap")
    first = (out / "README.TXT").read_bytes()
    make_extras(nomaps, out, kind="nomap", overwrite=True)  # replaced in place, not repeated
    readme = (out / "README.TXT").read_bytes().decode("ascii")
    assert readme.encode("ascii") == first
    assert readme.count("\r\nProduct ID:") == 5
    lines = readme.split("\r\n")
    index = lines.index("HIRISE OBSERVATIONS")
    block = lines[index + 4:lines.index("PRODUCER AND CONTACT")]
    assert lines[index + 3] == OBS
    for name in hirise.rdr_extras_names(OBS):
        (line,) = [i for i, text in enumerate(block) if text.startswith(f"  {name}  ")]
        assert block[line + 1].startswith(f"  {OBS}_") or block[line + 1] == ""  # one line
    assert {p.name for p in out.iterdir()} >= set(hirise.rdr_extras_names(OBS))
    assert "synthetic blue = 2 x BG - 0.3 x RED" in readme


def test_readme_examples_run_as_written(tmp_path: Path):
    """The README's HiRISE RDR Extras commands, in order, on small inputs of each kind."""
    import shlex
    import subprocess
    import sys

    import docs_text
    from test_extras_nomap import mosaics, write_plain_tiff
    body = docs_text.section("HiRISE RDR Extras")
    examples = [line for block in re.findall(r"```sh\n(.*?)```", body, re.S)
                for line in block.splitlines() if line.startswith("pdsgen ")]
    assert len(examples) == 3
    write_rdr(tmp_path, "RED", swath(300, 500, 1))
    write_rdr(tmp_path, "COLOR", swath(300, 200, 3))
    red, irb = mosaics(200, 150)
    for name, data in (("RED", red[None]), ("IRB", irb)):  # ISIS cubes, as ISIS writes NOMAPs
        with rasterio.open(tmp_path / f"{OBS}_{name}.NOMAP.cub", "w", driver="ISIS3",
                           width=150, height=200, count=data.shape[0], dtype="uint16") as ds:
            ds.write(data)
    write_plain_tiff(tmp_path / "red_mosaic.tif", red)
    write_plain_tiff(tmp_path / "irb_mosaic.tif", irb)
    for example in examples:
        result = subprocess.run([sys.executable, "-m", "pdsgen", *shlex.split(example)[1:]],
                                cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, f"{example}\n{result.stderr}"
    written = {p.name for p in (tmp_path / "extras").iterdir()}
    assert set(hirise.rdr_extras_names(OBS)) | set(hirise.rdr_extras_names("ESP_012345_1234")[6:]) <= written
