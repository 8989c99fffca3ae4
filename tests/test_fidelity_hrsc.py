"""HRSC level-4 labels shaped like DLR's, keywords carried from real level-2 labels,
the offset convention, and heights converted between reference surfaces.

Keyword grouping, order and units are written from the structure of genuine DLR labels
in tests/data/corpus/real (H0010_0023_SR2.lbl: a level-2 SRC label, DLR formatting;
H6541_0000_IR4_cropped.img.lbl: a level-4 label, IMAGE_MAP_PROJECTION in alphabetical
order with <km>, <km/pixel>, <pixel/degree>, N/A parallels and reference point,
COORDINATE_SYSTEM_TYPE). Those files are read in place, never copied.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pvl
import pytest
import rasterio
from affine import Affine
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen.errors import InputError
from pdsgen.products.dtm import write_dtm
from pdsgen.products.ortho import write_ortho
from pdsgen.validate import validate_paths
from test_fidelity_hirise import keyword_sequence

from helpers import elevation_array, run_cli, stated_keywords, write_raster

SINUSOIDAL = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"
GRID = Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0)
SOURCE_LABEL = "real/H0010_0023_SR2.lbl"  # orbit 10, sequence 23
CARRIED = ("DETECTOR_ID", "EVENT_TYPE", "MISSION_PHASE_NAME", "SPACECRAFT_CLOCK_START_COUNT",
           "SPACECRAFT_CLOCK_STOP_COUNT", "START_TIME", "STOP_TIME", "ORBITAL_ECCENTRICITY",
           "SPACECRAFT_POINTING_MODE", "PERIAPSIS_TIME")
HIRISE_ONLY = ("PROJECTION_LATITUDE_TYPE", "KEYWORD_LATITUDE_TYPE", "OBJECT=VIEWING_PARAMETERS")
DLR_PROJECTION = [
    "^DATA_SET_MAP_PROJECTION_CATALOG", "A_AXIS_RADIUS", "B_AXIS_RADIUS", "C_AXIS_RADIUS", "CENTER_LATITUDE",
    "CENTER_LONGITUDE", "COORDINATE_SYSTEM_NAME", "COORDINATE_SYSTEM_TYPE", "EASTERNMOST_LONGITUDE",
    "FIRST_STANDARD_PARALLEL", "LINE_FIRST_PIXEL", "LINE_LAST_PIXEL", "/*", "LINE_PROJECTION_OFFSET",
    "MAP_PROJECTION_ROTATION", "MAP_PROJECTION_TYPE", "MAP_RESOLUTION", "MAP_SCALE", "MAXIMUM_LATITUDE",
    "MINIMUM_LATITUDE", "POSITIVE_LONGITUDE_DIRECTION", "REFERENCE_LATITUDE", "REFERENCE_LONGITUDE",
    "SAMPLE_FIRST_PIXEL", "SAMPLE_LAST_PIXEL", "SAMPLE_PROJECTION_OFFSET", "SECOND_STANDARD_PARALLEL",
    "WESTERNMOST_LONGITUDE",
]


GENUINE_LEVEL4 = Path(__file__).parent / "data" / "genuine_pds3" / "isis3" / "h6541_0000_ir4_cropped.img"


@pytest.fixture
def heights(tmp_path):
    return write_raster(tmp_path / "in.tif", elevation_array(30, 24, seed=4), SINUSOIDAL, GRID)


def _errors(path):
    report = validate_paths([path], strict=True)
    return [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"]


def test_dt4_carries_identification_and_orbit_keywords_of_a_real_level2_label(tmp_path, heights, corpus_dir):
    source = corpus_dir / SOURCE_LABEL
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "MEX_POINTING_DESC.TXT").write_text("pointing modes\r\n")  # as the volume holds it
    product = write_dtm(heights, tmp_path / "out", profile="hrsc", product_id="h0010_0023", source_labels=[source],
                        params=stated_keywords("hrsc"))
    label, real = pvl.load(str(product.path)), pvl.load(str(source))
    for key in CARRIED:
        assert label[key] == real[key], key
    assert label["ORBIT_NUMBER"] == 10
    # a description pointer is carried only when the delivery holds the file it names
    assert label["^MEX_POINTING_DESC"] == "MEX_POINTING_DESC.TXT"
    assert "^MEX_ORIENTATION_DESC" not in label
    sequence, _ = keyword_sequence(product.label_text)
    # DLR's sections: identification, time, orbit, then the data objects
    assert sequence.index("DETECTOR_ID") < sequence.index("START_TIME") < sequence.index("ORBITAL_ECCENTRICITY")
    assert sequence.index("TARGET_NAME") < sequence.index("OBJECT=IMAGE")
    # DLR's OFFSET_ANGLE is in no dictionary the validator knows: a warning, as for DLR's own labels
    assert [e.split()[0:2] for e in _errors(product.path)] == [["DICT-001", "OFFSET_ANGLE"]]


def test_without_a_source_label_the_keywords_are_left_out(tmp_path, heights):
    product = write_dtm(heights, tmp_path / "out", profile="hrsc", product_id="h0010_0023")
    sequence, _ = keyword_sequence(product.label_text)
    assert not set(CARRIED) & set(sequence)
    assert "ORBIT_NUMBER" in sequence  # from the product name, a fact rather than a placeholder


def test_a_source_label_of_another_orbit_is_refused(tmp_path, heights, corpus_dir):
    with pytest.raises(InputError, match="orbit 10.*orbit 1234"):
        write_dtm(heights, tmp_path / "out", profile="hrsc", product_id="h1234_0000",
                  source_labels=[corpus_dir / SOURCE_LABEL])
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


def test_image_object_statistics_and_dlr_projection(tmp_path, heights):
    product = write_dtm(heights, tmp_path / "out", profile="hrsc", product_id="h0010_0023", precision=0.5,
                        params=stated_keywords("hrsc"))
    sequence, values = keyword_sequence(product.label_text)
    assert not set(HIRISE_ONLY) & set(sequence)
    start = sequence.index("OBJECT=IMAGE_MAP_PROJECTION") + 1
    assert sequence[start:start + len(DLR_PROJECTION)] == DLR_PROJECTION
    assert values["A_AXIS_RADIUS"] == "3396.0 <km>"
    assert values["MAP_SCALE"] == "0.05 <km/pixel>"
    assert values["MAP_RESOLUTION"].endswith("<pixel/degree>")
    assert values["COORDINATE_SYSTEM_TYPE"] == '"BODY-FIXED ROTATING"'
    for key in ("FIRST_STANDARD_PARALLEL", "SECOND_STANDARD_PARALLEL", "REFERENCE_LATITUDE",
                "REFERENCE_LONGITUDE"):
        assert values[key] == '"N/A"'
    assert values["^DATA_SET_MAP_PROJECTION_CATALOG"] == '"DSMAP.CAT"'
    image = pvl.load(str(product.path))["IMAGE"]
    assert image["INTERCHANGE_FORMAT"] == "BINARY" and image["BAND_STORAGE_TYPE"] == "BAND_SEQUENTIAL"
    with rasterio.open(product.path) as stored:
        dns = stored.read(1, masked=True).compressed().astype(np.float64)
    assert (image["MINIMUM"], image["MAXIMUM"]) == (dns.min(), dns.max())
    assert image["STANDARD_DEVIATION"] == pytest.approx(dns.std(), rel=1e-5)
    # heights below the datum: a negative MEAN, written as DLR writes it
    assert image["MEAN"] == pytest.approx(dns.mean(), rel=1e-5) and image["MEAN"] < 0
    assert _errors(product.path) == []


def test_projection_object_has_the_keywords_of_a_genuine_dlr_level4_label_in_its_order(tmp_path, heights):
    """The same keys, in the same order, as a DLR level-4 label kept in tests/data (ISIS3's
    hrsc2isis test file; PROVENANCE.md), pointer name included."""
    genuine = pvl.load(str(GENUINE_LEVEL4))["IMAGE_MAP_PROJECTION"]
    product = write_dtm(heights, tmp_path / "out", profile="hrsc", product_id="h0010_0023")
    written = pvl.load(str(product.path))["IMAGE_MAP_PROJECTION"]
    assert list(written.keys()) == list(genuine.keys())
    assert "^DATA_SET_MAP_PROJECTION_CATALOG" in written and written["^DATA_SET_MAP_PROJECTION_CATALOG"] == "DSMAP.CAT"


def test_mean_is_of_the_valid_dns_only_over_many_strips(tmp_path, monkeypatch):
    """MEAN and STANDARD_DEVIATION count only valid samples, summed strip by strip while the
    data are written: strips of 4 KiB, a third of the samples missing, read back by GDAL."""
    import pdsgen.formats.img as img
    import pdsgen.formats.raster as raster

    strips = []

    def small_strips(dataset):
        for window in raster.row_strips(dataset, 4096):
            strips.append(window)
            yield window

    monkeypatch.setattr(img, "row_strips", small_strips)
    values = elevation_array(700, 40, seed=9)
    values[::3, :] = -99999.0  # every third line missing, spread across all strips
    values[5:600, 7] = -99999.0
    source = write_raster(tmp_path / "holes.tif", values, SINUSOIDAL, GRID, nodata=-99999.0)
    product = write_dtm(source, tmp_path / "out", profile="hrsc", product_id="h0010_0023", precision=0.5,
                        params=stated_keywords("hrsc"))
    image = pvl.load(str(product.path))["IMAGE"]
    with rasterio.open(product.path) as stored:
        assert stored.height == 700
        dns = stored.read(1, masked=True)
    valid = dns.compressed().astype(np.float64)
    assert valid.size == np.count_nonzero(values != -99999.0)
    assert len(strips) >= 20
    assert image["MEAN"] == pytest.approx(valid.mean(), rel=1e-5)
    assert image["STANDARD_DEVIATION"] == pytest.approx(valid.std(), rel=1e-5)
    # with the missing DN counted the mean would be far off
    assert abs(dns.data.astype(np.float64).mean() - valid.mean()) > 100
    assert _errors(product.path) == []


def test_nd4_is_in_the_dtm_data_set_with_its_statistics(tmp_path):
    nadir = (np.arange(30 * 24).reshape(30, 24) % 200 + 20).astype("uint8")
    source = write_raster(tmp_path / "nadir.tif", nadir, SINUSOIDAL, GRID)
    product = write_ortho(source, tmp_path / "out", profile="hrsc", product_id="h0010_0023",
                          params=stated_keywords("hrsc"))
    label = pvl.load(str(product.path))
    assert label["DATA_SET_ID"] == "MEX-M-HRSC-5-REFDR-DTM-V1.0"
    assert label["IMAGE"]["MEAN"] == pytest.approx(nadir.mean(), rel=1e-5)
    assert label["IMAGE"]["STANDARD_DEVIATION"] == pytest.approx(nadir.std(), rel=1e-5)
    assert _errors(product.path) == []


def test_dlr_offset_convention_is_one_pixel_apart_and_recognised(tmp_path, heights):
    standard = write_dtm(heights, tmp_path / "std", profile="hrsc", product_id="h0010_0023")
    result = run_cli("dtm", heights, "-o", tmp_path / "dlr", "--profile", "hrsc", "--product-id", "h0010_0023",
                     "--offset-convention", "dlr")
    assert result.returncode == 0, result.stderr
    dlr = tmp_path / "dlr" / "h0010_0023_dt4.img"
    one, other = pvl.load(str(standard.path)), pvl.load(str(dlr))
    for key in ("LINE_PROJECTION_OFFSET", "SAMPLE_PROJECTION_OFFSET"):
        assert other["IMAGE_MAP_PROJECTION"][key].value == one["IMAGE_MAP_PROJECTION"][key].value + 1
    data = dlr.read_bytes()
    assert "DLR's convention" in data[:data.index(b"\r\nEND\r\n")].decode("ascii")
    report = validate_paths([dlr])
    assert [f.rule for f in report.findings if f.severity == "error"] == []
    assert any("one-pixel-apart convention" in f.message and f.severity == "info" for f in report.findings)
    with rasterio.open(standard.path) as exact:
        assert exact.transform.almost_equals(GRID)


def _radius_on_ellipse(a: float, c: float, geodetic_lat_deg: np.ndarray) -> np.ndarray:
    """Independent radius model: the point of the meridian ellipse at a geodetic latitude,
    through its parametric latitude beta (tan beta = c/a tan phi)."""
    beta = np.arctan(c / a * np.tan(np.radians(geodetic_lat_deg)))
    return np.hypot(a * np.cos(beta), c * np.sin(beta))


def test_reproject_converts_heights_between_reference_surfaces(tmp_path):
    a, c = 3396190.0, 3376200.0
    ellipsoid = f"+proj=eqc +lat_ts=0 +lon_0=70 +a={a} +b={c} +units=m +no_defs"
    height = 1000.0  # metres above the ellipsoid everywhere: the radius is R(lat) + 1000 m
    data = np.full((40, 40), height, dtype="float32")
    source = write_raster(tmp_path / "ell.tif", data, ellipsoid, Affine(500.0, 0, 0.0, 0, -500.0, 2400000.0))
    product = write_dtm(source, tmp_path / "out", profile="hrsc", product_id="h0010_0023", reproject_input=True,
                        precision=0.1)
    with rasterio.open(product.path) as out:
        stored = out.read(1, masked=True)
        rows, cols = np.nonzero(~np.ma.getmaskarray(stored))
        xs, ys = out.transform @ (cols + 0.5, rows + 0.5)
        _, lats = warp_transform(out.crs, CRS.from_proj4("+proj=longlat +R=3396000 +no_defs"), xs, ys)
        written = stored.compressed() * out.scales[0] + out.offsets[0]
    expected = _radius_on_ellipse(a, c, np.asarray(lats)) + height - 3396000.0
    assert np.abs(written - expected).max() < 0.1
    # at ~40 degrees the surfaces differ by far more than the 190 m of the equator
    assert expected.min() < height - 3000
    assert re.search(r"MAP_PROJECTION_TYPE\s+= \"SINUSOIDAL\"", product.label_text)


@pytest.mark.filterwarnings("ignore::rasterio.errors.NotGeoreferencedWarning")  # the VICAR part alone
def test_vicar2_header_is_read_by_gdals_vicar_driver(tmp_path, heights):
    product = write_dtm(heights, tmp_path / "out", profile="hrsc", product_id="h0010_0023", precision=0.5,
                        params=stated_keywords("hrsc"))
    label = pvl.loads(product.label_text)
    header = label["IMAGE_HEADER"]
    assert (header["HEADER_TYPE"], header["INTERCHANGE_FORMAT"]) == ("VICAR2", "ASCII")
    assert header["^DESCRIPTION"] == "VICAR2.TXT" and (tmp_path / "out" / "VICAR2.TXT").is_file()
    record = label["RECORD_BYTES"]
    assert label["^IMAGE"] == label["^IMAGE_HEADER"] + header["BYTES"] // record
    with rasterio.open(product.path) as pds:
        assert pds.driver == "PDS"
        expected = pds.read(1)
    # GDAL hands a PDS3 file with a VICAR header to its VICAR driver when asked to
    with rasterio.Env(GDAL_TRY_PDS3_WITH_VICAR="YES"), rasterio.open(product.path) as vicar:
        assert vicar.driver == "VICAR"
        np.testing.assert_array_equal(vicar.read(1), expected)
    # and the VICAR part alone (header + image) is a VICAR file
    data = product.path.read_bytes()
    alone = tmp_path / "alone.vic"
    alone.write_bytes(data[(label["^IMAGE_HEADER"] - 1) * record:])
    with rasterio.open(alone) as vicar:
        assert vicar.driver == "VICAR" and vicar.dtypes == ("int16",)
        np.testing.assert_array_equal(vicar.read(1), expected)
    assert _errors(product.path) == []


def test_da4_note_keeps_the_acronyms_case(tmp_path, heights):
    product = write_dtm(heights, tmp_path / "out", profile="hrsc", product_id="h0010_0023", kind="da4",
                        vertical_datum="areoid")
    label = pvl.loads(product.label_text)
    assert "GM3 areoid" in label["IMAGE"]["NOTE"] and "gm3" not in label["IMAGE"]["NOTE"]
    assert label["MEX:DTM"]["MEX:DTM_DESC"] == "HEIGHT ABOVE GM3-AREOID"
