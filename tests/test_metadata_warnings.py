"""Missing and guessed metadata made visible (issue 44): a product made without identification
keywords warns once, naming the params file and its template; "UNK" in a delivery is a validation
warning that --strict fails; CI formats carry no notes; pdsgen's own orthoimage label draws no finding; a
DATA_SET_ID alone does not make a generic product HiRISE's; datums are stated, never guessed; a
HiRISE orthoimage refuses a source DTM ID of another kind; extras takes --root.

The params template is read back with Python's own TOML parser and loaded by pdsgen's params
reader; labels with pvl; the SARIF report with json."""

from __future__ import annotations

import json
import os
import re
import shutil
from pathlib import Path

import numpy as np
import pvl
import pytest
from affine import Affine

from pdsgen._compat import tomllib
from pdsgen.extras.product_source import open_product
from pdsgen.missions import LabelFacts, detect_mission
from pdsgen.params import load_params
from pdsgen.validate import validate_paths

from helpers import elevation_array, run_cli, write_raster

CRS = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs"
IDENTIFICATION = ("DATA_SET_ID", "DATA_SET_NAME", "PRODUCER_INSTITUTION_NAME", "PRODUCER_ID", "PRODUCER_FULL_NAME",
                  "INSTRUMENT_HOST_NAME", "INSTRUMENT_HOST_ID", "INSTRUMENT_NAME", "INSTRUMENT_ID", "RATIONALE_DESC")


@pytest.fixture(scope="module")
def rasters(tmp_path_factory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("inputs")
    transform = Affine(1.0, 0, 6123456.0, 0, -1.0, -563210.0)
    image = np.linspace(0.05, 0.25, 40 * 30, dtype=np.float32).reshape(40, 30)
    return {"dtm": write_raster(root / "dtm.tif", elevation_array(40, 30, seed=5), CRS, transform),
            "ortho": write_raster(root / "ortho.tif", image, CRS, transform)}


def _filled_template(profile: str, path: Path) -> Path:
    """The params template of `profile` with every keyword uncommented and given a value."""
    lines = []
    for line in run_cli("params", "--template", profile).stdout.splitlines():
        match = re.fullmatch(r"# ([A-Z_]+) = (.*)", line)
        if match:
            value = match.group(2).replace('"..."', '"STATED"')
            lines.append(f"{match.group(1)} = {value}")
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_product_without_identification_warns_once_naming_the_params_file(tmp_path, rasters):
    told = run_cli("dtm", rasters["dtm"], "-o", tmp_path, "-q")
    assert told.returncode == 0
    assert told.stderr == (
        f"warning: {tmp_path}/DTM.IMG: {', '.join(IDENTIFICATION)} are \"UNK\" (not stated); write them in a "
        "params file (pdsgen params --template generic prints one to fill in) and make the product again with "
        "it as --params\n")
    label = pvl.load(str(tmp_path / "DTM.IMG"))
    assert all(label[keyword] == "UNK" for keyword in IDENTIFICATION)


def test_the_filled_template_states_every_keyword_and_silences_the_warning(tmp_path, rasters):
    params = _filled_template("generic", tmp_path / "params.toml")
    assert set(IDENTIFICATION) <= set(load_params(params))
    told = run_cli("dtm", rasters["dtm"], "-o", tmp_path / "out", "-q", "--params", params)
    assert told.returncode == 0 and told.stderr == ""
    label = pvl.load(str(tmp_path / "out" / "DTM.IMG"))
    assert label["INSTRUMENT_NAME"] == "STATED"
    run_cli("deliver", tmp_path / "out", "-o", tmp_path / "delivery", "--volume-id", "TEST_0001", "-q")
    assert not [f for f in validate_paths([tmp_path / "delivery"]).findings if f.rule == "DLV-007"]


@pytest.mark.parametrize("profile", ["generic", "hirise", "hrsc", "hrsc-ax", "imars"])
def test_each_profiles_template_is_toml_that_loads_as_it_is(tmp_path, profile):
    text = run_cli("params", "--template", profile).stdout
    assert tomllib.loads(text) == {}  # every line a comment: the file changes nothing until filled in
    assert all(f"# {keyword} = " in text for keyword in IDENTIFICATION)
    assert load_params(_filled_template(profile, tmp_path / "p.toml"))


def test_the_template_is_written_to_a_new_file_only(tmp_path):
    target = tmp_path / "params.toml"
    first = run_cli("params", "--template", "hirise", "-o", target)
    assert first.returncode == 0 and "MRO-M-HIRISE-5-DTM-V1.0" in target.read_text()
    again = run_cli("params", "--template", "hirise", "-o", target)
    assert again.returncode == 2
    assert again.stderr == f"pdsgen: error: {target}: exists; give a new file name (a params file is not overwritten)\n"


def test_unk_identification_in_a_delivery_warns_and_fails_under_strict(tmp_path, rasters):
    run_cli("dtm", rasters["dtm"], "-o", tmp_path / "products", "-q")
    # a product alone says the same as in a delivery: UNK is text still to write (issue 49), failing --strict
    for given in (tmp_path / "products" / "DTM.IMG", tmp_path / "products"):
        alone = run_cli("validate", given)
        assert alone.returncode == 0 and alone.stdout.count("[DLV-007]") == len(IDENTIFICATION)
        assert run_cli("validate", "--strict", given).returncode == 1
    delivery = tmp_path / "delivery"
    run_cli("deliver", tmp_path / "products", "-o", delivery, "--volume-id", "TEST_0001", "-q")
    plain = run_cli("validate", delivery)
    assert plain.returncode == 0
    assert (f"{delivery}/DATA/DTM.IMG:28: warning [DLV-007] DATA_SET_ID: \"UNK\": not stated (write it in a params "
            "file, `pdsgen params --template PROFILE` lists every keyword, and make the product again)") in plain.stdout
    assert plain.stdout.count("[DLV-007]") == len(IDENTIFICATION)
    placeholders = plain.stdout.count("[DLV-007]") + plain.stdout.count("[DLV-006]")
    assert plain.stdout.rstrip().endswith(f"{placeholders} placeholder(s) still to write - OK")
    strict = run_cli("validate", "--strict", delivery)
    assert strict.returncode == 1 and strict.stdout.rstrip().endswith("(strict) - FAILED")
    summary = json.loads(run_cli("validate", "--format", "json", delivery).stdout)["summary"]
    assert summary["placeholders"] == placeholders


def test_ci_formats_leave_notes_out(tmp_path, rasters):
    run_cli("dtm", rasters["dtm"], "-o", tmp_path / "products", "-q")
    run_cli("deliver", tmp_path / "products", "-o", tmp_path / "d", "--volume-id", "TEST_0001", "-q")
    text = run_cli("validate", tmp_path / "d").stdout
    assert "info [MAP-004]" in text  # a note for people ...
    github = run_cli("validate", "--format", "github", tmp_path / "d").stdout
    assert "::notice" not in github and "MAP-004" not in github and "::warning" in github
    sarif = json.loads(run_cli("validate", "--format", "sarif", tmp_path / "d").stdout)
    results = sarif["runs"][0]["results"]
    assert results and {r["level"] for r in results} == {"warning"}
    assert sarif["runs"][0]["properties"]["info"] >= 1  # ... counted, not annotated


def test_pdsgens_own_orthoimage_label_draws_no_storage_bytes_note(tmp_path, rasters):
    told = run_cli("ortho", rasters["ortho"], "-o", tmp_path, "-q", "--params",
                   _filled_template("generic", tmp_path / "p.toml"))
    assert told.returncode == 0, told.stderr
    label = pvl.load(str(tmp_path / "ORTHO.LBL"))
    assert label["COMPRESSED_FILE"]["REQUIRED_STORAGE_BYTES"].units == "BYTES"
    findings = validate_paths([tmp_path / "ORTHO.LBL"]).findings
    assert findings and not [f for f in findings if f.keyword == "REQUIRED_STORAGE_BYTES" or f.rule == "DICT-009"]


def test_a_data_set_id_alone_does_not_make_a_generic_product_hirise():
    borrowed = "MRO-M-HIRISE-5-DTM-V1.0"
    assert detect_mission(LabelFacts(data_set_id=borrowed)) == "hirise"  # no instrument stated: the data set says
    assert detect_mission(LabelFacts(data_set_id=borrowed, instrument_id="UNK")) is None
    assert detect_mission(LabelFacts(data_set_id=borrowed, instrument_id="HIRISE")) == "hirise"
    assert detect_mission(LabelFacts(data_set_id="MEX-M-HRSC-5-REFDR-DTM-V1.0", instrument_id="UNK")) is None


def test_a_hirise_orthoimage_refuses_a_source_dtm_id_of_another_kind(tmp_path, rasters):
    told = run_cli("ortho", rasters["ortho"], "-o", tmp_path / "o", "--profile", "hirise", "--observation-id",
                   "PSP_008669_1705", "--source-dtm-id", "PSP_008669_1705_RED_C_01_ORTHO")
    assert told.returncode == 2 and not (tmp_path / "o").exists()
    assert told.stderr == ("pdsgen: error: --source-dtm-id PSP_008669_1705_RED_C_01_ORTHO is not a hirise DTM "
                           "product ID (e.g. DTEEC_008669_1705_009025_1705_U01)\n")
    good = run_cli("ortho", rasters["ortho"], "-o", tmp_path / "g", "--profile", "hirise", "--observation-id",
                   "PSP_008669_1705", "--source-dtm-id", "DTEEC_008669_1705_009025_1705_U01", "-q")
    assert good.returncode == 0, good.stderr


def test_dtm_vertical_datum_is_stated_in_the_note(tmp_path, rasters):
    run_cli("dtm", rasters["dtm"], "-o", tmp_path / "a", "-q", "--vertical-datum", "areoid")
    note = " ".join(pvl.load(str(tmp_path / "a" / "DTM.IMG"))["IMAGE"]["NOTE"].split())
    assert note.endswith("Heights are above the Mars areoid.")
    run_cli("dtm", rasters["dtm"], "-o", tmp_path / "s", "-q", "--vertical-datum", "sphere")
    note = " ".join(pvl.load(str(tmp_path / "s" / "DTM.IMG"))["IMAGE"]["NOTE"].split())
    assert note.endswith("Heights are above the 3396.19 km sphere.")
    run_cli("dtm", rasters["dtm"], "-o", tmp_path / "n", "-q")
    assert "above" not in pvl.load(str(tmp_path / "n" / "DTM.IMG"))["IMAGE"]["NOTE"]


@pytest.mark.parametrize(("profile", "stderr"), [
    ("hirise", "pdsgen: error: hirise DTM heights are above the Mars 2000 areoid, not a sphere; leave out "
               "--vertical-datum\n"),
    ("hrsc-ax", "pdsgen: error: --vertical-datum does not apply to --profile hrsc-ax\n"),
])
def test_dtm_vertical_datum_that_contradicts_the_profile_is_refused(tmp_path, rasters, profile, stderr):
    told = run_cli("dtm", rasters["dtm"], "-o", tmp_path / "o", "--profile", profile, "--vertical-datum", "sphere",
                   "--product-id", "DTEEC_000001_1000_000002_1000_U01")
    assert (told.returncode, told.stderr) == (2, stderr) and not (tmp_path / "o").exists()


def test_extras_state_a_datum_only_from_the_label_or_the_user(tmp_path, rasters):
    params = tmp_path / "borrowed.toml"
    params.write_text('DATA_SET_ID = "MRO-M-HIRISE-5-DTM-V1.0"\n')
    run_cli("dtm", rasters["dtm"], "-o", tmp_path / "g", "-q", "--params", params)
    product = tmp_path / "g" / "DTM.IMG"
    assert open_product(product).heights.datum == "a reference surface the label does not name"
    run_cli("extras", product, "-o", tmp_path / "x1", "-q")
    readme = " ".join((tmp_path / "x1" / "README.TXT").read_text().split())
    assert "metres above a reference surface the label does not name" in readme and "areoid" not in readme
    run_cli("extras", product, "-o", tmp_path / "x2", "-q", "--vertical-datum", "the Mars 2000 areoid")
    assert "metres above the Mars 2000 areoid" in " ".join((tmp_path / "x2" / "README.TXT").read_text().split())
    run_cli("dtm", rasters["dtm"], "-o", tmp_path / "h", "-q", "--profile", "hirise",
            "--product-id", "DTEEC_000001_1000_000002_1000_U01")
    assert open_product(tmp_path / "h" / "DTEEC_000001_1000_000002_1000_U01.IMG").heights.datum == \
        "the Mars 2000 areoid"  # the label's own NOTE says it, in the mission's words


def test_extras_root_trusts_the_tree_given(tmp_path, rasters):
    """A detached label naming its JP2 in another directory of the tree: refused without --root (the
    label's directory is the tree), read with --root naming the volume."""
    run_cli("ortho", rasters["ortho"], "-o", tmp_path / "made", "-q")
    volume = tmp_path / "volume"
    (volume / "LABEL").mkdir(parents=True)
    (volume / "DATA").mkdir()
    shutil.copy(tmp_path / "made" / "ORTHO.JP2", volume / "DATA" / "ORTHO.JP2")
    climbing = f'"{os.pardir}/DATA/ORTHO.JP2"'.encode()  # the label names its image one directory up
    text = (tmp_path / "made" / "ORTHO.LBL").read_bytes().replace(b'"ORTHO.JP2"', climbing)
    (volume / "LABEL" / "ORTHO.LBL").write_bytes(text)
    refused = run_cli("extras", volume / "LABEL" / "ORTHO.LBL", "-o", tmp_path / "x")
    assert refused.returncode == 2 and not (tmp_path / "x").exists()
    assert "lies outside" in refused.stderr and refused.stderr.count("\n") == 1
    taken = run_cli("extras", volume / "LABEL" / "ORTHO.LBL", "-o", tmp_path / "x", "--root", volume, "-q")
    assert taken.returncode == 0, taken.stderr
    assert (tmp_path / "x" / "ORTHO.browse.jpg").is_file()


@pytest.mark.parametrize(("given", "problem"), [
    ({"vertical_datum": "the Mars areoid"},
     "`vertical_datum` has no use with `kind='nomap'` (NOMAP Extras show no heights)"),
    ({"root": "."}, "`root` has no use with `kind='nomap'` (NOMAP mosaics are read as images, without labels)"),
])
def test_nomap_extras_refuse_the_options_they_have_no_use_for(tmp_path, given, problem):
    from pdsgen.errors import ParamsError
    from pdsgen.extras import make_extras

    with pytest.raises(ParamsError) as raised:
        make_extras([tmp_path / "PSP_005000_1000_RED.NOMAP.JP2"], tmp_path / "out", kind="nomap", **given)
    assert str(raised.value) == problem and not (tmp_path / "out").exists()
