"""HRSC-AX airborne tiles: VICAR channel files on a UTM grid of the HRSC-AX ellipsoid to a
PDS3 DEM, read back by GDAL (its PDS driver) and pvl."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pvl
import pytest
import rasterio
from affine import Affine
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen import write_dtm
from pdsgen.errors import PdsgenError
from pdsgen.formats.vicar import read_vicar_label
from pdsgen.missions import hrsc_ax
from pdsgen.validate import validate_paths

from helpers import run_cli
from hrsc_ax_tiles import GEODETIC, dtm_group, grid_corner_positions, map_group, tile_name, write_vicar

EAST, NORTH, PIXEL = 430000.0, 8765000.0, 0.5
LINES, SAMPLES = 48, 64
OFFSET, SCALING = 100.0, 0.25
MISSING = -32768.0


def _stored() -> np.ndarray:
    rows, cols = np.mgrid[0:LINES, 0:SAMPLES]
    stored = (rows * 7.0 - cols * 3.5 + 0.25 * rows * cols).astype(np.float32)
    stored[5, 9] = MISSING
    stored[LINES - 1, 0] = MISSING
    return stored


def _dem(tmp_path: Path, big_endian: bool = False) -> Path:
    name = tile_name(430, 8765, LINES, PIXEL)
    return write_vicar(tmp_path / f"{name}.dsm", _stored(), {
        "MAP": map_group(EAST, NORTH, PIXEL),
        "DIGITAL_TERRAIN_MODEL": dtm_group(OFFSET, SCALING, -500.0, 2000.0),
    }, big_endian=big_endian)


def _ground_m(lon, lat):
    """Positions on the HRSC-AX ellipsoid as metres of a local tangent grid (east, north)."""
    local = CRS.from_proj4(f"+proj=aeqd +lat_0=78.94 +lon_0=11.73 +a={hrsc_ax.A_AXIS_KM * 1000} "
                           f"+b={hrsc_ax.C_AXIS_KM * 1000} +units=m +no_defs")
    x, y = warp_transform(CRS.from_proj4(GEODETIC), local, list(lon), list(lat))
    return np.array(x), np.array(y)


def _ground_errors_m(transform, crs) -> np.ndarray:
    """For the corner and centre pixels: metres between where a reader's grid (`transform`,
    `crs`) puts each pixel and where the source label puts it."""
    pixels, lon, lat = grid_corner_positions(EAST, NORTH, PIXEL, LINES, SAMPLES)
    xs, ys = zip(*(transform @ (s + 0.5, r + 0.5) for r, s in pixels), strict=True)
    glon, glat = warp_transform(crs, CRS.from_proj4(GEODETIC), list(xs), list(ys))
    (ex, ey), (gx, gy) = _ground_m(lon, lat), _ground_m(glon, glat)
    return np.hypot(gx - ex, gy - ey)


def test_vicar_label_read_with_its_property_groups(tmp_path):
    path = _dem(tmp_path, big_endian=True)
    label = read_vicar_label(path)
    assert (label.lines, label.samples, label.format) == (LINES, SAMPLES, "REAL")
    assert label.dtype == np.dtype(">f4")
    assert label.group("MAP")["SCALE_FACTOR"] == 0.9996
    assert label.group("MAP")["MAP_PROJECTION_TYPE"] == "TRANSVERSE_MERCATOR"
    assert label.group("DIGITAL_TERRAIN_MODEL")["DTM_RANGE"] == (-500.0, 2000.0)
    raw = np.fromfile(path, dtype=">f4", offset=label.image_offset).reshape(LINES, SAMPLES)
    np.testing.assert_array_equal(raw, _stored())


@pytest.mark.parametrize("big_endian", [False, True])
def test_dem_heights_and_every_corner_within_a_centimetre(tmp_path, big_endian):
    product = write_dtm(_dem(tmp_path, big_endian), tmp_path / "out", profile="hrsc-ax")
    assert product.product_id == "HRSCAX_430_8765_0_0X0_0KM_DEM"
    expected = OFFSET + _stored().astype(np.float64) * SCALING
    with rasterio.open(product.path) as ds:
        assert ds.driver == "PDS"
        heights = ds.read(1)
        assert ds.nodata == pytest.approx(-3.4028226550889045e38)
        missing = _stored() == MISSING
        assert (heights[missing] == np.float32(ds.nodata)).all()
        np.testing.assert_array_equal(heights[~missing], expected[~missing].astype(np.float32))
        # Where GDAL's PDS reader puts each pixel, against where the source label puts it.
        assert _ground_errors_m(ds.transform, ds.crs).max() < 0.01


def test_dem_label_says_what_the_numbers_are(tmp_path):
    product = write_dtm(_dem(tmp_path), tmp_path / "out", profile="hrsc-ax")
    label = pvl.load(str(product.path))
    projection = label["IMAGE_MAP_PROJECTION"]
    assert label["TARGET_NAME"] == "EARTH"
    assert label["INSTRUMENT_ID"] == "HRSC-AX"
    assert projection["MAP_PROJECTION_TYPE"] == "TRANSVERSE MERCATOR"
    assert projection["COORDINATE_SYSTEM_NAME"] == "PLANETOGRAPHIC"
    assert [projection[k].value for k in ("A_AXIS_RADIUS", "B_AXIS_RADIUS", "C_AXIS_RADIUS")] == \
        [6378.14, 6378.14, 6356.75]
    # The scale factor is folded into MAP_SCALE: ground metres per pixel on the central meridian.
    assert projection["MAP_SCALE"].value == pytest.approx(PIXEL / 0.9996, rel=1e-12)
    note = " ".join(label["IMAGE"]["NOTE"].split())
    assert "ellipsoid heights" in note and "+36.5 m" in note and "-500 .. 2000 m" in note
    text = product.path.read_bytes()[:product.records.label_bytes].decode("ascii")
    assert "scale factor 0.9996" in text and "false easting 500000.000 m" in text
    report = validate_paths([product.path])
    assert not [f for f in report.findings if f.severity == "error"]


def test_gdal_vicar_reader_disagrees_with_the_label_and_the_label_wins(tmp_path):
    """GDAL reads the VICAR tile with scale factor 1 and another offset convention: metres
    off at 70 km from the central meridian, kilometres at 8,765 km north. pdsgen's product
    follows the label."""
    path = _dem(tmp_path)
    with rasterio.open(path) as ds:
        assert ds.driver == "VICAR"
        assert _ground_errors_m(ds.transform, ds.crs).min() > 100.0  # GDAL's own reading of the tile is far off
    product = write_dtm(path, tmp_path / "out", profile="hrsc-ax")
    with rasterio.open(product.path) as ds:
        assert _ground_errors_m(ds.transform, ds.crs).max() < 0.01


def test_product_id_override_and_cli(tmp_path):
    path = _dem(tmp_path)
    result = run_cli("dtm", path, "-o", tmp_path / "out", "--profile", "hrsc-ax", "--product-id", "SVALBARD_TILE_1")
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "out" / "SVALBARD_TILE_1.IMG").is_file()


def test_xml_image_label_gives_missing_keywords_and_the_survey_date(tmp_path):
    name = tile_name(430, 8765, LINES, PIXEL)
    path = write_vicar(tmp_path / f"{name}.dsm", _stored(), {"MAP": map_group(EAST, NORTH, PIXEL)})
    xml = tmp_path / "dem_label.xml"
    xml.write_text("<ImageLabel><DIGITAL_TERRAIN_MODEL><DTM_OFFSET>100.0</DTM_OFFSET>"
                   "<DTM_SCALING_FACTOR>0.25</DTM_SCALING_FACTOR><DTM_RANGE>(-500, 2000)</DTM_RANGE>"
                   "</DIGITAL_TERRAIN_MODEL><ACQUISITION_DATE>2008-07-17</ACQUISITION_DATE></ImageLabel>")
    product = write_dtm(path, tmp_path / "out", profile="hrsc-ax", source_labels=[xml])
    with rasterio.open(product.path) as ds:
        assert ds.read(1)[0, 0] == np.float32(OFFSET + _stored()[0, 0] * SCALING)
    note = " ".join(pvl.load(str(product.path))["IMAGE"]["NOTE"].split())
    assert "2008-07-17" in note and "-500 .. 2000 m" in note


@pytest.mark.parametrize("damage, message", [
    (lambda p: p.write_bytes(p.read_bytes()[:-100]), "is truncated"),
    (lambda p: p.write_bytes(b"NOT A VICAR FILE" + p.read_bytes()), "is not a VICAR file"),
    (lambda p: p.write_bytes(p.read_bytes().replace(b"NLB=0", b"NLB=X", 1)), "unusable NLB"),
])
def test_bad_input_is_one_line_exit_2_nothing_written(tmp_path, damage, message):
    path = _dem(tmp_path)
    damage(path)
    result = run_cli("dtm", path, "-o", tmp_path / "out", "--profile", "hrsc-ax")
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0] and path.name in lines[0]
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


def test_tile_names_make_legal_pds_identifiers():
    assert hrsc_ax.tile_product_id("430-8765_5.0x5.0km", "CIR") == "HRSCAX_430_8765_5_0X5_0KM_CIR"
    with pytest.raises(PdsgenError, match="not an HRSC-AX tile name"):
        hrsc_ax.tile_product_id("svalbard", "DEM")


@pytest.mark.parametrize("dialect", ["pds4", "both"])
def test_pds4_transverse_mercator_with_scale_factor_read_by_gdal_and_pds4_tools(tmp_path, dialect):
    from pdsgen.validate.pds4 import schematron
    from pdsgen.validate.pds4.label_checks import validate_pds4

    pds4_tools = pytest.importorskip("pds4_tools")
    product = write_dtm(_dem(tmp_path), tmp_path / "out", profile="hrsc-ax", label=dialect)
    xml = product.pds4_label_path
    text = xml.read_text()
    assert "<cart:map_projection_name>Transverse Mercator</cart:map_projection_name>" in text
    assert "<cart:scale_factor_at_central_meridian>0.9996</cart:scale_factor_at_central_meridian>" in text
    assert "<cart:latitude_type>Planetographic</cart:latitude_type>" in text
    if schematron.available():
        assert validate_pds4(xml) == []
    expected = (OFFSET + _stored().astype(np.float64) * SCALING).astype(np.float32)
    missing = _stored() == MISSING
    with rasterio.open(xml) as ds:
        assert ds.driver == "PDS4"
        np.testing.assert_array_equal(ds.read(1)[~missing], expected[~missing])
        assert _ground_errors_m(ds.transform, ds.crs).max() < 0.01
    structures = pds4_tools.read(str(xml), quiet=True, lazy_load=True)
    array = np.asarray(structures[len(structures.structures) - 1].data)
    np.testing.assert_array_equal(array[~missing], expected[~missing])


def test_readme_examples_run_as_written(tmp_path):
    import re
    import shlex
    import subprocess
    import sys

    import docs_text
    body = docs_text.section("HRSC-AX airborne tiles")
    examples = [line for block in re.findall(r"```sh\n(.*?)```", body, re.S) for line in block.splitlines()
                if line.startswith("pdsgen ")]
    assert len(examples) == 5
    stem = "430-8765_5.0x5.0km"
    write_vicar(tmp_path / f"{stem}.dsm", _stored(), {"MAP": map_group(EAST, NORTH, PIXEL),
                                                       "DIGITAL_TERRAIN_MODEL": dtm_group(OFFSET, SCALING, -500, 2000)})
    for seed, extension in enumerate(("pan", "re", "gr", "bl", "cir_re", "cir_gr", "cir_bl")):
        data = np.random.default_rng(seed).integers(1, 256, (LINES, SAMPLES)).astype(np.uint8)
        write_vicar(tmp_path / f"{stem}.{extension}", data, {"MAP": map_group(EAST, NORTH, PIXEL)})
    (tmp_path / "dem_label.xml").write_text("<Label><ACQUISITION_DATE>2008-07-17</ACQUISITION_DATE></Label>")
    for example in examples:
        result = subprocess.run([sys.executable, "-m", "pdsgen", *shlex.split(example)[1:]], cwd=tmp_path,
                                capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, f"{example}\n{result.stderr}"
    written = {p.name for p in (tmp_path / "out").iterdir()}
    assert {f"HRSCAX_430_8765_5_0X5_0KM_{k}.JP2" for k in ("PAN", "RGB", "CIR")} <= written
    assert "HRSCAX_430_8765_5_0X5_0KM_DEM.IMG" in written
    assert {p.name for p in (tmp_path / "both").iterdir()} == {"HRSCAX_430_8765_5_0X5_0KM_DEM.IMG",
                                                              "HRSCAX_430_8765_5_0X5_0KM_DEM.xml"}
    report = validate_paths([tmp_path / "out", tmp_path / "both"])
    assert not [f for f in report.findings if f.severity == "error"]


def test_half_dem_and_all_missing_named_by_the_users_file(tmp_path):
    name = tile_name(430, 8765, LINES, PIXEL)
    stored = (np.arange(LINES * SAMPLES) % 3000 - 1000).astype(np.int16).reshape(LINES, SAMPLES)
    path = write_vicar(tmp_path / f"{name}.dsm", stored, {
        "MAP": map_group(EAST, NORTH, PIXEL), "DIGITAL_TERRAIN_MODEL": dtm_group(36.5, 0.1, -100, 300)},
        big_endian=True)
    product = write_dtm(path, tmp_path / "out", profile="hrsc-ax")
    with rasterio.open(product.path) as ds:
        np.testing.assert_array_equal(ds.read(1), (36.5 + stored.astype(np.float64) * 0.1).astype(np.float32))
    (tmp_path / "empty").mkdir()
    empty = write_vicar(tmp_path / "empty" / f"{name}.dsm", np.full((4, 5), MISSING, np.float32),
                        {"MAP": map_group(EAST, NORTH, PIXEL)})
    result = run_cli("dtm", empty, "-o", tmp_path / "out2", "--profile", "hrsc-ax")
    assert result.returncode == 2
    assert result.stderr.strip() == f"pdsgen: error: {empty}: has no valid pixels (all nodata)"


def test_vicar_items_strings_lists_and_refusals(tmp_path):
    from pdsgen.errors import InputError
    from pdsgen.formats.vicar import parse_items

    items = parse_items("LBLSIZE=100  FORMAT='BYTE'  NOTE='it''s'  R=(1.5,-2,3E2)  W=(  'A', 'B')  X=7 ")
    assert items == [("LBLSIZE", 100), ("FORMAT", "BYTE"), ("NOTE", "it's"), ("R", (1.5, -2, 300.0)),
                     ("W", ("A", "B")), ("X", 7)]
    with pytest.raises(InputError, match="a list inside a list"):
        parse_items("LBLSIZE=100  R=((1,2),3)")
    path = _dem(tmp_path)
    vax = path.read_bytes().replace(b"REALFMT='RIEEE'", b"REALFMT='VAX'  ")
    path.write_bytes(vax)
    with pytest.raises(InputError, match="REALFMT VAX reals are not read"):
        read_vicar_label(path)


@pytest.mark.skipif(shutil.which("gdalinfo") is None, reason="GDAL's command-line tools not installed")
def test_installed_gdal_command_line_places_the_dem_too(tmp_path):
    """The system's GDAL (Debian bookworm: 3.6, the release the issue names) reads the PDS3 label
    to the same ground positions, within 1 cm, as the GDAL rasterio carries."""
    import json
    import subprocess

    product = write_dtm(_dem(tmp_path), tmp_path / "out", profile="hrsc-ax")
    info = json.loads(subprocess.run(["gdalinfo", "-json", str(product.path)], capture_output=True, text=True,
                                     check=True, timeout=60).stdout)
    crs = CRS.from_wkt(info["coordinateSystem"]["wkt"])
    assert _ground_errors_m(Affine.from_gdal(*info["geoTransform"]), crs).max() < 0.01
