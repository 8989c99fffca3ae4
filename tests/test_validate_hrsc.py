"""The validator's HRSC profile: pdsgen's DT4/DA4/ND4 products validate clean, each one-defect
corruption is reported with its rule id, and HRSC's archive conventions (older offset
formula, alphabetical keywords in IMAGE_MAP_PROJECTION) are not reported as problems."""

from __future__ import annotations

import numpy as np
import pytest
from affine import Affine
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.products.dtm import write_dtm
from pdsgen.products.ortho import write_ortho
from pdsgen.validate import validate_paths
from test_validate_support import label_end, make_dtm, replace_in_label, resize_label_text

from helpers import elevation_array, stated_keywords, write_raster

GRIDS = {
    "sinusoidal": ("+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs",
                   Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0)),
    "south_polar": ("+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs",
                    Affine(50.0, 0, 100000.0, 0, -50.0, 60000.0)),
}


def _heights(tmp_path, grid: str):
    crs, transform = GRIDS[grid]
    heights = elevation_array(45, 38, seed=11)
    heights[3:6, 4:9] = np.nan  # missing data: MEX:DTM_MISSING_DN pixels
    return write_raster(tmp_path / f"in_{grid}.tif", heights, crs, transform)


def _dtm(tmp_path, grid: str = "sinusoidal", kind: str = "dt4", outdir: str = "out"):
    datum = "sphere" if kind == "dt4" else "areoid"
    return write_dtm(_heights(tmp_path, grid), tmp_path / outdir, profile="hrsc", kind=kind, vertical_datum=datum,
                     precision=0.05, source_product_ids=["H1234_0000_ND3"], params=stated_keywords("hrsc")).path


def _not_info(report) -> list[str]:
    return [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"]


def _errors(report) -> dict[str, str]:
    return {f.rule: f.message for f in report.findings if f.severity == "error"}


@pytest.mark.parametrize("grid", ["sinusoidal", "south_polar"])
@pytest.mark.parametrize("kind", ["dt4", "da4"])
def test_dt4_and_da4_validate_clean_strict(tmp_path, grid, kind):
    path = _dtm(tmp_path, grid, kind)
    assert path.name == f"h1234_0000_{kind}.img"
    report = validate_paths([path], strict=True)
    assert _not_info(report) == [] and report.exit_code == 0
    assert "MAP-004" in report.rule_ids("info")  # pdsgen writes the standard convention
    assert not report.rule_ids() & {"MAP-005", "MAP-011"}


def test_sinusoidal_and_south_polar_set_via_the_cli(tmp_path):
    """The acceptance run: DT4 and DA4 of both grids, `pdsgen validate` exits 0.
    Two products in one directory are a delivery set, so without Extras the one
    legitimate warning is SET-004 (no README.TXT / browse JPEGs); errors: none."""
    for grid in GRIDS:
        for kind in ("dt4", "da4"):
            _dtm(tmp_path, grid, kind, outdir=f"set_{grid}")
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "set_sinusoidal"),
                                       str(tmp_path / "set_south_polar")])
    assert result.exit_code == 0, result.output
    assert " 0 error(s)" in result.output
    warned = {line.split("[")[1].split("]")[0] for line in result.output.splitlines() if ": warning [" in line}
    assert warned == {"SET-004"}


def test_hrsc_extras_with_lower_case_names_complete_the_set(tmp_path):
    """SET-004 finds HRSC's lower-case Extras (`h1234_0000_dt4.br.jpg`) for upper-case PRODUCT_IDs."""
    from pdsgen.extras import make_extras

    products = [_dtm(tmp_path, "sinusoidal", kind) for kind in ("dt4", "da4")]
    report = validate_paths([tmp_path / "out"])
    assert {f.rule for f in report.findings if f.severity == "warning"} == {"SET-004"}
    written = make_extras(products, tmp_path / "out" / "extras")
    assert "h1234_0000_dt4.br.jpg" in {p.name for p in written}
    report = validate_paths([tmp_path / "out"], strict=True)
    assert _not_info(report) == [] and report.exit_code == 0
    for jpg in (tmp_path / "out" / "extras").glob("h1234_0000_da4.*.jpg"):
        jpg.unlink()
    missing = [f for f in validate_paths([tmp_path / "out"]).findings if f.rule == "SET-004"]
    assert len(missing) == 1 and missing[0].file.endswith("h1234_0000_da4.img")


@pytest.mark.parametrize("dtype", ["uint8", "float32"])
def test_nd4_validates_clean_strict(tmp_path, dtype):
    rng = np.random.default_rng(4)
    image = (rng.random((36, 28)) * (250 if dtype == "uint8" else 0.2)).astype(dtype)
    image[0, :3] = 0
    crs, transform = GRIDS["south_polar"]
    source = write_raster(tmp_path / "nd.tif", image, crs, transform, nodata=0)
    product = write_ortho(source, tmp_path / "out", profile="hrsc", source_product_ids=["H1234_0000_ND3"],
                          params=stated_keywords("hrsc"))
    report = validate_paths([product.path], strict=True)
    assert _not_info(report) == []
    assert not report.rule_ids() & {"HRSC-001", "HRSC-002", "HRSC-003", "HRSC-004", "HRSC-005", "HRSC-006"}


# -- one defect each -------------------------------------------------------------------------------
def test_missing_dn_differing_from_missing_constant(tmp_path):
    path = _dtm(tmp_path)
    replace_in_label(path, b"MEX:DTM_MISSING_DN     = -32768", b"MEX:DTM_MISSING_DN     = -32767")
    report = validate_paths([path])
    assert set(_errors(report)) == {"HRSC-001"} and report.exit_code == 1
    message = _errors(report)["HRSC-001"]
    assert "-32767" in message and "MISSING_CONSTANT = -32768" in message


def test_scaling_factor_differing_from_the_image(tmp_path):
    path = _dtm(tmp_path)
    replace_in_label(path, b"MEX:DTM_SCALING_FACTOR = 0.05 <M>", b"MEX:DTM_SCALING_FACTOR = 0.04 <M>")
    report = validate_paths([path])
    assert set(_errors(report)) == {"HRSC-002"} and report.exit_code == 1
    assert "0.04" in _errors(report)["HRSC-002"] and "SCALING_FACTOR = 0.05" in _errors(report)["HRSC-002"]


def test_offset_differing_from_the_image(tmp_path):
    path = _dtm(tmp_path)
    data = path.read_bytes()[: label_end(path.read_bytes())].decode("ascii")
    line = next(x for x in data.split("\r\n") if "MEX:DTM_OFFSET" in x)
    value = line.split("=")[1].split("<")[0].strip()
    changed = line.replace(value, value[:-1] + ("1" if value[-1] != "1" else "2"))
    replace_in_label(path, line.encode(), changed.encode())
    assert set(_errors(validate_paths([path]))) == {"HRSC-002"}


def test_dtm_desc_contradicting_the_file_name(tmp_path):
    """A consistent DT4 group (sphere radii, HEIGHT ABOVE SPHEROID) in a file named _da4."""
    path = _dtm(tmp_path)
    replace_in_label(path, b'PRODUCT_ID                = "H1234_0000_DT4"',
                     b'PRODUCT_ID                = "H1234_0000_DA4"')
    renamed = path.with_name("h1234_0000_da4.img")
    path.rename(renamed)
    report = validate_paths([renamed])
    assert set(_errors(report)) == {"HRSC-004"} and report.exit_code == 1
    message = _errors(report)["HRSC-004"]
    assert "HEIGHT ABOVE SPHEROID" in message and "HEIGHT ABOVE GM3-AREOID" in message


def test_dtm_desc_contradicting_radii_and_file_name(tmp_path):
    path = _dtm(tmp_path)
    resize_label_text(path, b'"HEIGHT ABOVE SPHEROID"', b'"HEIGHT ABOVE GM3-AREOID"')
    report = validate_paths([path])
    assert set(_errors(report)) == {"HRSC-003", "HRSC-004"}
    assert "MEX:DTM_A_AXIS_RADIUS = 3396" in _errors(report)["HRSC-003"]


def test_areoid_radii_under_a_sphere_description(tmp_path):
    path = _dtm(tmp_path, kind="da4")
    resize_label_text(path, b'"HEIGHT ABOVE GM3-AREOID"', b'"HEIGHT ABOVE SPHEROID"')
    assert set(_errors(validate_paths([path]))) == {"HRSC-003", "HRSC-004"}


def _generic_named_hrsc(tmp_path, crs: str, transform: Affine):
    """A product written by the generic writer (no MEX:DTM group) under an HRSC name, with HRSC's
    identification."""
    from pdsgen import write_dtm

    source = write_raster(tmp_path / "generic.tif", elevation_array(30, 20, seed=3), crs, transform)
    return write_dtm(source, tmp_path / "generic", product_id="H1234_0000_DT4",
                     params=stated_keywords(mission="hrsc")).path


def test_reference_body_other_than_the_hrsc_sphere(tmp_path):
    path = _generic_named_hrsc(tmp_path, "+proj=sinu +lon_0=70 +R=3396190 +units=m +no_defs",
                               GRIDS["sinusoidal"][1])
    report = validate_paths([path])
    assert set(_errors(report)) == {"HRSC-005"} and report.exit_code == 1
    assert "3396.19" in _errors(report)["HRSC-005"]


def test_sinusoidal_poleward_of_85_degrees_is_a_warning(tmp_path):
    # centre near 87.5 S: HRSC would map it polar stereographic
    path = _generic_named_hrsc(tmp_path, "+proj=sinu +lon_0=0 +R=3396000 +units=m +no_defs",
                               Affine(50.0, 0, 0.0, 0, -50.0, -5185000.0))
    report = validate_paths([path])
    assert report.exit_code == 0
    warnings = {f.rule: f.message for f in report.findings if f.severity == "warning"}
    assert set(warnings) == {"HRSC-006"} and "POLAR STEREOGRAPHIC" in warnings["HRSC-006"]
    assert validate_paths([path], strict=True).exit_code == 1


def test_polar_stereographic_near_the_equator_is_a_warning(tmp_path):
    path = _generic_named_hrsc(tmp_path, "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs",
                               Affine(50.0, 0, 100000.0, 0, -50.0, 3000000.0))
    warnings = {f.rule for f in validate_paths([path]).findings if f.severity == "warning"}
    assert warnings == {"HRSC-006"}


# -- the HRSC archive's own conventions --------------------------------------------------------------
def _shift_offsets(path, by: float) -> None:
    text = path.read_bytes()[: label_end(path.read_bytes())].decode("ascii")
    for key in ("LINE_PROJECTION_OFFSET", "SAMPLE_PROJECTION_OFFSET"):
        line = next(x for x in text.split("\r\n") if x.strip().startswith(key))
        value = line.split("=")[1].split("<")[0].strip()
        shifted = line.replace(f"= {value}", f"= {float(value) + by!r}")
        resize_label_text(path, line.encode(), shifted.encode())


def test_older_offset_convention_is_information_for_hrsc(tmp_path):
    """DSMAP.CAT's one-pixel-apart formula is the HRSC archive's own: MAP-011 (info), not MAP-005."""
    path = _dtm(tmp_path)
    _shift_offsets(path, 1.0)
    report = validate_paths([path], strict=True)
    assert _not_info(report) == [] and report.exit_code == 0
    assert "MAP-011" in report.rule_ids("info") and "MAP-005" not in report.rule_ids()
    assert "HRSC archive's own" in next(f.message for f in report.findings if f.rule == "MAP-011")


def test_older_offset_convention_is_still_a_warning_elsewhere(tmp_path):
    path = make_dtm(tmp_path, "sinusoidal")
    _shift_offsets(path, 1.0)
    report = validate_paths([path])
    assert "MAP-005" in report.rule_ids("warning") and "MAP-011" not in report.rule_ids()


def test_alphabetical_keywords_in_image_map_projection_are_not_a_finding(tmp_path):
    """The HRSC archive writes IMAGE_MAP_PROJECTION keywords in alphabetical order: pdsgen's
    DT4 with its projection block sorted that way still validates clean (same bytes, reordered)."""
    path = _dtm(tmp_path)
    data = path.read_bytes()
    end = label_end(data)
    text = data[:end].decode("ascii")
    start = text.index("OBJECT = IMAGE_MAP_PROJECTION\r\n") + len("OBJECT = IMAGE_MAP_PROJECTION\r\n")
    stop = text.index("END_OBJECT = IMAGE_MAP_PROJECTION")
    lines = text[start:stop].split("\r\n")[:-1]
    ordered = sorted(lines, key=lambda line: line.strip().lstrip("^"))
    assert ordered != lines
    sorted_text = text[:start] + "\r\n".join(ordered) + "\r\n" + text[stop:]
    path.write_bytes(sorted_text.encode("ascii") + data[end:])
    report = validate_paths([path], strict=True)
    assert _not_info(report) == [] and "MAP-004" in report.rule_ids("info")


def test_real_h6541_label_alphabetical_projection_block_has_no_order_finding(corpus_dir):
    path = corpus_dir / "real" / "H6541_0000_IR4_cropped.img.lbl"
    report = validate_paths([path], labels_only=True)
    text = path.read_bytes().decode("latin-1").splitlines()
    first = next(i for i, x in enumerate(text, 1) if x.strip() == "Object = IMAGE_MAP_PROJECTION")
    last = next(i for i, x in enumerate(text, 1) if i > first and x.strip() == "End_Object")
    inside = {f.rule for f in report.findings if f.line and first <= f.line <= last}
    # the real defects of this cropped copy (test_validate_corpus.KNOWN_DEFECTS) and nothing else
    assert inside <= {"SYNTAX-002", "SYNTAX-006", "MAP-003", "MAP-008"}, inside
    assert not [f for f in report.findings if "order" in f.message.lower() or "alphabet" in f.message.lower()]
    # recognised as HRSC, on the 3396.0 km sphere and sinusoidal at ~22 S: no HRSC finding
    assert not {r for r in report.rule_ids() if r.startswith("HRSC")}
    # its MEX:DTM group holds image placeholders (N/A, -1e+32): nothing compared, nothing unknown;
    # -1e+32 has no decimal point, which ODL reals need: a warning (SYNTAX-016), as DLR writes it
    mex = [f for f in report.findings if (f.keyword or "").startswith("MEX:")]
    assert mex and {(f.rule, f.severity) for f in mex} == {("SYNTAX-016", "warning")}


def test_mex_keywords_of_the_corpus_are_in_the_dictionary(corpus_dir):
    from pdsgen.validate.dictionary import load

    dictionary = load()
    seen = set()
    for name in ("H6541_0000_IR4_cropped.img.lbl", "H0010_0023_SR2.lbl"):
        for word in (corpus_dir / "real" / name).read_text(encoding="latin-1").split():
            if word.upper().startswith("MEX:") and word.upper() != "MEX:DTM":
                seen.add(word.upper())
    assert {"MEX:DTM_MISSING_DN", "MEX:REFLECTANCE_OFFSET", "MEX:DTM_DESC"} <= seen
    for keyword in seen:
        entry = dictionary.lookup(keyword)
        assert entry is not None and entry["type"] in ("REAL", "INTEGER", "CHARACTER"), keyword
    assert dictionary.lookup("MEX:DTM_A_AXIS_RADIUS")["unit"] == "km"
    assert dictionary.lookup("MEX:DTM_SCALING_FACTOR")["unit"] == "m"


def test_mex_radius_in_degrees_is_a_unit_error(tmp_path):
    path = _dtm(tmp_path)
    resize_label_text(path, b"MEX:DTM_A_AXIS_RADIUS  = 3396.0 <KM>", b"MEX:DTM_A_AXIS_RADIUS  = 3396.0 <DEG>")
    errors = _errors(validate_paths([path]))
    assert set(errors) == {"DICT-011"} and "MEX:DTM_A_AXIS_RADIUS" in errors["DICT-011"]


def test_level_2_hrsc_label_without_a_map_has_no_hrsc_finding(corpus_dir):
    report = validate_paths([corpus_dir / "real" / "H0010_0023_SR2.lbl"], labels_only=True)
    assert not {r for r in report.rule_ids() if r.startswith("HRSC") or r == "MAP-011"}


def test_statistics_leave_out_mex_dtm_missing_dn_pixels(tmp_path):
    """Real HRSC labels may carry the missing DN only in MEX:DTM: with the IMAGE's
    MISSING_CONSTANT removed, the -32768 pixels still stay out of MINIMUM, and
    HRSC-001 has nothing to compare (as for those archive labels)."""
    path = _dtm(tmp_path)
    resize_label_text(path, b"  MISSING_CONSTANT   = -32768\r\n", b"")  # aligned with STANDARD_DEVIATION
    report = validate_paths([path], strict=True)
    assert _not_info(report) == []
    # control: with the group's DN changed too, -32768 counts as data and MINIMUM is wrong
    replace_in_label(path, b"MEX:DTM_MISSING_DN     = -32768", b"MEX:DTM_MISSING_DN     = -32767")
    errors = _errors(validate_paths([path]))
    assert set(errors) == {"IMG-007"} and "-32768" in errors["IMG-007"]


def test_projection_rule_is_for_single_orbit_products_only(tmp_path):
    """An HRSC mosaic (DATA_SET_ID MEX-M-HRSC..., no hOOOO_NNNN name) may use another projection."""
    from pdsgen import write_dtm

    source = write_raster(tmp_path / "mosaic.tif", elevation_array(30, 20, seed=3),
                          "+proj=sinu +lon_0=0 +R=3396000 +units=m +no_defs",
                          Affine(50.0, 0, 0.0, 0, -50.0, -5185000.0))
    mosaic = {**stated_keywords(mission="hrsc"), "DATA_SET_ID": "MEX-M-HRSC-5-RDR-MOSAIC-V1.0"}
    path = write_dtm(source, tmp_path / "mosaic", product_id="HRSC_MOSAIC_SOUTH", params=mosaic).path
    data = path.read_bytes()
    assert b'DATA_SET_ID               = "MEX-M-HRSC-5-RDR-MOSAIC-V1.0"' in data[:label_end(data)]
    report = validate_paths([path], strict=True)
    assert _not_info(report) == []
    renamed = path.with_name("h1234_0000_dt4.img")  # the same map as a single-orbit product: a warning
    path.rename(renamed)
    assert "HRSC-006" in validate_paths([renamed]).rule_ids("warning")


def test_hrsc_numeric_not_applicable_is_information_not_a_range_error(corpus_dir, tmp_path):
    real = validate_paths([corpus_dir / "real" / "H6541_0000_IR4_cropped.img.lbl"], labels_only=True)
    placeholders = {f.keyword for f in real.findings if f.rule == "DICT-012"}
    assert placeholders == {"RIGHT_ASCENSION", "DECLINATION"}
    assert not [f for f in real.findings if f.rule == "DICT-003"]
    # Missions share the convention (-1e+32, -9.99e+31, -2147483648): the same value in any
    # label is the placeholder; another number out of range is still reported.
    other = tmp_path / "other.lbl"
    other.write_bytes(b"PDS_VERSION_ID = PDS3\r\nRIGHT_ASCENSION = -1e+32\r\nDECLINATION = -91.5\r\nEND\r\n")
    elsewhere = validate_paths([other], labels_only=True)
    assert {(f.rule, f.keyword) for f in elsewhere.findings if f.rule.startswith("DICT-01") or
            f.rule == "DICT-003"} == {("DICT-012", "RIGHT_ASCENSION"), ("DICT-003", "DECLINATION")}
