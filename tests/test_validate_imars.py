"""The validator's iMars profile: `*_ucl.pvl` metadata checked against its GeoTIFF (opened with
GDAL) and the scene footprint. pdsgen's iMars DTM + ORI validate clean; each one-defect
corruption is reported with its IMARS rule id and exit status 1, never a traceback."""

from __future__ import annotations

import json

import numpy as np
import pytest
import rasterio
from affine import Affine
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.products.dtm import write_dtm
from pdsgen.products.ortho import write_ortho
from pdsgen.validate import discover, validate_paths

from helpers import elevation_array, write_raster

GRIDS = {
    "south_polar": ("+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs",
                    Affine(100.0, 0, -20000.0, 0, -100.0, 150000.0)),
    "sinusoidal": ("+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs",
                   Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0)),
}


def _delivery(tmp_path, grid: str = "south_polar"):
    """An iMars DTM (int16, areoid heights) and ORI (byte) of one scene, as pdsgen writes them."""
    crs, transform = GRIDS[grid]
    heights = elevation_array(90, 70, seed=11)
    heights[:5, :] = np.nan
    dtm_source = write_raster(tmp_path / "dtm_in.tif", heights, crs, transform)
    image = np.linspace(0.0, 1.0, 90 * 70, dtype=np.float32).reshape(90, 70)
    image[:, :3] = np.nan
    ori_source = write_raster(tmp_path / "ori_in.tif", image, crs, transform)
    out = tmp_path / "out"
    dtm = write_dtm(dtm_source, out, profile="imars", product_id="h0022_0000", precision=0.1)
    ori = write_ortho(ori_source, out, profile="imars", product_id="h0022_0000")
    return dtm, ori


def _errors(report) -> dict[str, list[str]]:
    found: dict[str, list[str]] = {}
    for f in report.findings:
        if f.severity == "error":
            found.setdefault(f.rule, []).append(f.message)
    return found


def _edit(path, old: str, new: str) -> None:
    text = path.read_text()
    assert text.count(old) == 1, old
    path.write_text(text.replace(old, new))


@pytest.mark.parametrize("grid", sorted(GRIDS))
def test_dtm_and_ori_validate_clean(tmp_path, grid):
    dtm, ori = _delivery(tmp_path, grid)
    report = validate_paths([tmp_path / "out"], strict=True)
    names = sorted(r.path.rsplit("/", 1)[-1] for r in report.files)
    assert names == ["h0022_0000_da4_ucl.pvl", "h0022_0000_nd4_ucl.pvl"]  # not the .tif or .geojson
    assert report.findings == [] and report.exit_code == 0
    for product in (dtm, ori):  # named on their own as well
        single = validate_paths([product.pvl_path], strict=True)
        assert single.findings == [] and single.exit_code == 0


def test_cli_validates_an_imars_delivery(tmp_path):
    _delivery(tmp_path)
    result = CliRunner().invoke(main, ["validate", "--strict", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert result.output.startswith("2 file(s) checked: 0 error(s), 0 warning(s)")


def test_any_pvl_with_productinfo_and_image_is_picked_up(tmp_path):
    dtm, _ = _delivery(tmp_path)
    other = tmp_path / "out" / "metadata.pvl"
    other.write_text(dtm.pvl_path.read_text())
    (tmp_path / "out" / "unrelated.pvl").write_text("Object = Something\n  A = 1\nEnd_Object\nEnd\n")
    found = {p.name for p in discover([tmp_path / "out"])}
    assert "metadata.pvl" in found and "unrelated.pvl" not in found
    errors = _errors(validate_paths([other]))
    assert set(errors) == {"IMARS-003"}  # only its name is wrong
    assert "h0022_0000_da4_ucl.pvl" in errors["IMARS-003"][0]


# -- one defect each -----------------------------------------------------------------------------
def test_lines_wrong(tmp_path):
    dtm, _ = _delivery(tmp_path)
    _edit(dtm.pvl_path, "Lines           = 90", "Lines           = 91")
    report = validate_paths([dtm.pvl_path])
    assert set(_errors(report)) == {"IMARS-006"} and report.exit_code == 1
    (message,) = _errors(report)["IMARS-006"]
    assert "Lines = 91" in message and "expected Lines = 90" in message
    finding = next(f for f in report.findings if f.rule == "IMARS-006")
    assert finding.line == dtm.pvl_path.read_text().splitlines().index("  Lines           = 91") + 1


def test_upper_left_corner_moved_by_one_pixel(tmp_path):
    dtm, _ = _delivery(tmp_path)
    _edit(dtm.pvl_path, "UpperLeftCornerX  = -20000.0 <m>", "UpperLeftCornerX  = -19900.0 <m>")
    errors = _errors(validate_paths([dtm.pvl_path]))
    assert set(errors) == {"IMARS-007"}
    assert "-19900.0" in errors["IMARS-007"][0] and "-20000.0" in errors["IMARS-007"][0]
    assert "1 px off" in errors["IMARS-007"][0]


def test_sub_tolerance_corner_is_accepted_and_pixel_size_is_checked_at_the_far_edge(tmp_path):
    dtm, _ = _delivery(tmp_path)
    _edit(dtm.pvl_path, "UpperLeftCornerX  = -20000.0 <m>", "UpperLeftCornerX  = -20000.05 <m>")  # 5e-4 px
    assert validate_paths([dtm.pvl_path]).exit_code == 0
    _edit(dtm.pvl_path, "PixelResolution   = 100.0 <m>", "PixelResolution   = 100.01 <m>")  # 0.009 px at 90 px
    assert set(_errors(validate_paths([dtm.pvl_path]))) == {"IMARS-007"}


def test_nodata_wrong(tmp_path):
    _, ori = _delivery(tmp_path)
    _edit(ori.pvl_path, "NoData        = 0", "NoData        = 255")
    errors = _errors(validate_paths([ori.pvl_path]))
    assert set(errors) == {"IMARS-006"}
    assert "NoData = 255" in errors["IMARS-006"][0] and "expected NoData = 0" in errors["IMARS-006"][0]


def test_valid_maximum_wrong(tmp_path):
    dtm, _ = _delivery(tmp_path)
    with rasterio.open(dtm.tiff_path) as dataset:
        high = int(dataset.read(1, masked=True).max())
    _edit(dtm.pvl_path, f"ValidMaximum    = {high}", f"ValidMaximum    = {high + 1}")
    errors = _errors(validate_paths([dtm.pvl_path]))
    assert set(errors) == {"IMARS-009"} and f"expected ValidMaximum = {high}" in errors["IMARS-009"][0]
    # label-only runs do not read the data, so they cannot see it
    assert validate_paths([dtm.pvl_path], labels_only=True).findings == []


def test_proj4_of_another_body(tmp_path):
    dtm, _ = _delivery(tmp_path)
    _edit(dtm.pvl_path, "+R=3396000 ", "+R=3396190 ")
    errors = _errors(validate_paths([dtm.pvl_path]))
    assert set(errors) == {"IMARS-008"} and "3396190" in errors["IMARS-008"][0]


def test_geotiff_missing(tmp_path):
    dtm, _ = _delivery(tmp_path)
    dtm.tiff_path.unlink()
    report = validate_paths([dtm.pvl_path])
    assert set(_errors(report)) == {"IMARS-004"} and report.exit_code == 1
    assert "h0022_0000_da4_ucl.tif" in _errors(report)["IMARS-004"][0]


def test_geotiff_in_another_case(tmp_path):
    dtm, _ = _delivery(tmp_path)
    dtm.tiff_path.rename(dtm.tiff_path.with_name("H0022_0000_DA4_UCL.TIF"))
    errors = _errors(validate_paths([dtm.pvl_path]))
    assert set(errors) == {"IMARS-004"} and "case differs" in errors["IMARS-004"][0]


def test_data_file_gdal_cannot_open(tmp_path):
    dtm, _ = _delivery(tmp_path)
    dtm.tiff_path.write_bytes(b"not a tiff at all")
    errors = _errors(validate_paths([dtm.pvl_path]))
    assert set(errors) == {"IMARS-005"}


def test_footprint_missing_its_feature(tmp_path):
    dtm, ori = _delivery(tmp_path)
    collection = json.loads(dtm.footprint_path.read_text())
    collection["features"] = [f for f in collection["features"] if f["id"] != "h0022_0000_da4"]
    dtm.footprint_path.write_text(json.dumps(collection))
    report = validate_paths([tmp_path / "out"])
    assert {(f.rule, f.file.rsplit("/", 1)[-1]) for f in report.findings} == {
        ("IMARS-011", "h0022_0000_da4_ucl.pvl")}
    assert "ids found: h0022_0000_nd4" in _errors(report)["IMARS-011"][0]


def test_footprint_absent_or_not_a_collection(tmp_path):
    dtm, _ = _delivery(tmp_path)
    dtm.footprint_path.write_text(json.dumps({"type": "Feature", "id": "h0022_0000_da4"}))
    assert set(_errors(validate_paths([dtm.pvl_path]))) == {"IMARS-010"}
    dtm.footprint_path.unlink()
    errors = _errors(validate_paths([dtm.pvl_path]))
    assert set(errors) == {"IMARS-010"} and "h0022_0000.geojson" in errors["IMARS-010"][0]


def test_broken_pvl_syntax(tmp_path):
    dtm, _ = _delivery(tmp_path)
    _edit(dtm.pvl_path, "= (N/A)", "= (N/A")
    report = validate_paths([dtm.pvl_path])
    assert set(_errors(report)) == {"IMARS-001"} and report.exit_code == 1
    assert not [f for f in report.findings if "could not run" in f.message]
    result = CliRunner().invoke(main, ["validate", str(dtm.pvl_path)])
    assert result.exit_code == 1 and "[IMARS-001]" in result.output and "Traceback" not in result.output


def test_missing_object_and_group(tmp_path):
    dtm, _ = _delivery(tmp_path)
    text = dtm.pvl_path.read_text()
    start, stop = text.index("Object = Algorithm"), text.index("End_Object = Algorithm")
    text = text[:start] + text[stop + len("End_Object = Algorithm\n"):]
    start, stop = text.index("  Group = Producer"), text.index("  End_Group = Producer")
    text = text[:start] + text[stop + len("  End_Group = Producer\n"):]
    dtm.pvl_path.write_text(text)
    errors = _errors(validate_paths([dtm.pvl_path]))
    assert set(errors) == {"IMARS-002"}
    joined = " ".join(errors["IMARS-002"])
    assert "Algorithm" in joined and "Producer" in joined


def test_list_rules_names_the_imars_and_hrsc_families():
    result = CliRunner().invoke(main, ["validate", "--list-rules"])
    ids = {line.split()[0] for line in result.output.splitlines() if line.strip()}
    assert {f"IMARS-{n:03d}" for n in range(1, 12)} <= ids
    assert {f"HRSC-{n:03d}" for n in range(1, 7)} | {"MAP-011"} <= ids
