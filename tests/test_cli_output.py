"""--json, --verbose and --quiet of the product commands, through real `python -m pdsgen` runs."""

from __future__ import annotations

import json
import re
from pathlib import Path

import glymur
import numpy as np
import pvl
import rasterio

from helpers import CRS_EQUIRECTANGULAR, ORIGINS, elevation_array, run_cli, stated_params, write_raster

TRANSFORM = ORIGINS["equirectangular"][1]


def _check_files(summary: dict) -> list[Path]:
    """Every file the summary names exists with the size it states."""
    paths = [Path(entry["path"]) for entry in summary["files"]]
    assert paths and [p.stat().st_size for p in paths] == [entry["bytes"] for entry in summary["files"]]
    return paths


def test_dtm_and_ortho_json_describe_what_was_written(tmp_path):
    dtm_in = write_raster(tmp_path / "dtm.tif", elevation_array(30, 40), CRS_EQUIRECTANGULAR, TRANSFORM)
    image = np.random.default_rng(2).integers(0, 256, (30, 40), dtype="uint8")
    ortho_in = write_raster(tmp_path / "image.tif", image, CRS_EQUIRECTANGULAR, TRANSFORM)

    run = run_cli("dtm", dtm_in, "-o", tmp_path / "out", "--json", "--params", stated_params(tmp_path))
    assert run.returncode == 0 and run.stderr == "", run.stderr
    summary = json.loads(run.stdout)  # stdout is the JSON document and nothing else
    (img,) = _check_files(summary)
    assert summary["command"] == "dtm" and summary["checks"] == {"label_rules": "passed", "warnings": []}
    assert pvl.load(str(img))["PRODUCT_ID"] == summary["product_id"]
    with rasterio.open(img) as written:
        assert (written.height, written.width) == (summary["lines"], summary["samples"]) == (30, 40)

    run = run_cli("ortho", ortho_in, "-o", tmp_path / "out", "--json", "--params", stated_params(tmp_path))
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    paths = _check_files(summary)
    jp2 = next(p for p in paths if p.suffix == ".JP2")
    label = next(p for p in paths if p.suffix == ".LBL")
    assert pvl.load(str(label))["PRODUCT_ID"] == summary["product_id"]
    assert glymur.Jp2k(str(jp2)).shape[:2] == (summary["lines"], summary["samples"]) == (30, 40)

    run = run_cli("extras", img, "-o", tmp_path / "extras", "--json", "--browse-width", "32")
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    names = {p.name for p in _check_files(summary)}
    assert "README.TXT" in names and any(name.endswith(".jpg") for name in names)


def test_verbose_tells_what_was_read_chosen_and_written_on_stderr(tmp_path):
    source = write_raster(tmp_path / "dtm.tif", elevation_array(20, 20), CRS_EQUIRECTANGULAR, TRANSFORM)
    run = run_cli("dtm", source, "-o", tmp_path / "out", "--verbose", "--params", stated_params(tmp_path))
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith(str(tmp_path / "out" / "DTM.IMG"))  # the usual line, on stdout
    lines = run.stderr.splitlines()
    assert all(re.match(r"\[ *\d+\.\d\d s\] ", line) for line in lines), lines
    assert any("read " in line and "dtm.tif: 20 lines x 20 samples" in line for line in lines), lines
    assert any("product ID DTM" in line for line in lines), lines
    size = (tmp_path / "out" / "DTM.IMG").stat().st_size
    assert any(line.endswith(f"wrote {tmp_path / 'out' / 'DTM.IMG'} ({size} bytes)") for line in lines), lines


def test_quiet_prints_nothing_and_excludes_verbose(tmp_path):
    source = write_raster(tmp_path / "dtm.tif", elevation_array(20, 20), CRS_EQUIRECTANGULAR, TRANSFORM)
    run = run_cli("dtm", source, "-o", tmp_path / "out", "--quiet", "--params", stated_params(tmp_path))
    assert (run.returncode, run.stdout, run.stderr) == (0, "", "")
    assert (tmp_path / "out" / "DTM.IMG").is_file()
    both = run_cli("dtm", source, "-o", tmp_path / "again", "-q", "-v")
    assert both.returncode == 2 and len(both.stderr.splitlines()) == 1
    assert "exclude each other" in both.stderr and not (tmp_path / "again").exists()
