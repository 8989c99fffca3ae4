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


def test_every_file_written_is_named_and_quiet_is_quiet_everywhere(tmp_path):
    """ortho's summary and --json name JP2INFO.TXT, the file it writes beside its product;
    extras -q prints nothing (not even the kind each product was taken for)."""
    image = np.random.default_rng(4).integers(0, 256, (30, 40), dtype="uint8")
    ortho_in = write_raster(tmp_path / "image.tif", image, CRS_EQUIRECTANGULAR, TRANSFORM)
    params = stated_params(tmp_path)
    told = run_cli("ortho", ortho_in, "-o", tmp_path / "out", "--params", params)
    assert told.returncode == 0, told.stderr
    assert told.stdout.startswith(f"{tmp_path / 'out' / 'IMAGE.JP2'}  IMAGE.LBL  JP2INFO.TXT: "), told.stdout
    again = run_cli("ortho", ortho_in, "-o", tmp_path / "out", "--params", params, "--overwrite", "--json")
    names = [p.name for p in _check_files(json.loads(again.stdout))]
    assert names == ["IMAGE.JP2", "IMAGE.LBL", "JP2INFO.TXT"]

    quiet = run_cli("extras", tmp_path / "out" / "IMAGE.LBL", "-o", tmp_path / "extras", "-q", "--params", params)
    assert (quiet.returncode, quiet.stdout, quiet.stderr) == (0, "", "")
    assert (tmp_path / "extras" / "README.TXT").is_file()
    loud = run_cli("extras", tmp_path / "out" / "IMAGE.LBL", "-o", tmp_path / "extras2", "--params", params)
    assert "taken as an orthoimage" in loud.stderr
    assert len(loud.stdout.splitlines()) == len(list((tmp_path / "extras2").iterdir()))  # one line per file


def test_the_output_option_is_named_as_the_help_names_it():
    """The writers' help says "into OUTDIR": the -o option is shown as OUTDIR, and demo takes it too."""
    for command in ("dtm", "ortho", "extras", "mosaic", "migrate", "demo"):
        shown = run_cli(command, "--help").stdout
        assert re.search(r"-o, --output OUTDIR ", shown), (command, shown)
        assert "-h, --help" in shown


def test_deliver_names_only_what_it_made(tmp_path):
    """--bundle-lid beside --label pds3 (a script giving both identifiers every time) makes no
    bundle, and the summary names none (it printed "PDS4 bundle X::None")."""
    source = write_raster(tmp_path / "dtm.tif", elevation_array(20, 20), CRS_EQUIRECTANGULAR, TRANSFORM)
    made = run_cli("dtm", source, "-o", tmp_path / "products", "-q", "--params", stated_params(tmp_path))
    assert made.returncode == 0, made.stderr
    run = run_cli("deliver", tmp_path / "products", "-o", tmp_path / "d", "--label", "pds3", "--volume-id", "V1",
                  "--bundle-lid", "urn:nasa:pds:x")
    assert run.returncode == 0, run.stderr
    assert "PDS3     volume V1" in run.stdout and "bundle" not in run.stdout and "::None" not in run.stdout


def test_the_review_page_is_titled_by_the_volume_and_shows_progress_on_a_terminal(tmp_path):
    from helpers import stderr_on_a_terminal

    source = write_raster(tmp_path / "dtm.tif", elevation_array(20, 20), CRS_EQUIRECTANGULAR, TRANSFORM)
    made = run_cli("dtm", source, "-o", tmp_path / "products", "-q", "--params", stated_params(tmp_path))
    assert made.returncode == 0, made.stderr
    made = run_cli("deliver", tmp_path / "products", "-o", tmp_path / "delivery", "--volume-id", "TEST_0001", "-q")
    assert made.returncode == 0, made.stderr
    status, shown = stderr_on_a_terminal("review", tmp_path / "delivery", "-o", tmp_path / "page.html")
    assert status == 0 and "file(s) checked" in shown, shown
    page = (tmp_path / "page.html").read_text()
    assert "<title>Review: TEST_0001</title>" in page and "(delivery)" not in page
    quiet = run_cli("review", tmp_path / "delivery", "-o", tmp_path / "page2.html", "-q")
    assert (quiet.returncode, quiet.stdout, quiet.stderr) == (0, "", "")


def test_demo_takes_the_output_option_and_names_every_file(tmp_path):
    run = run_cli("demo", "-o", tmp_path / "demo", "--json")
    assert run.returncode == 0, run.stderr
    names = {Path(entry["path"]).name for entry in json.loads(run.stdout)["files"]}
    assert {"JP2INFO.TXT", "README.TXT"} <= names
    both = run_cli("demo", tmp_path / "a", "-o", tmp_path / "b")
    assert both.returncode == 2 and "two output directories" in both.stderr
