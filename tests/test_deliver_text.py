"""Delivery text that survives (issue 44): a delivery text file fills every [TO BE WRITTEN: ...]
of the volume and the bundle; a re-run keeps what a person wrote into the delivery and its
versions until the delivery is released or a new version is asked for; INDEX.TAB says when each
product was made; --label names the dialect as the product commands do.

The delivery is read back by independent readers: pvl (VOLDESC.CAT), pds4_tools (the bundle
label), csv (INDEX.TAB), md5sum (the manifest)."""

from __future__ import annotations

import csv
import datetime
import os
import subprocess
from pathlib import Path

import pds4_tools
import pvl
import pytest
from affine import Affine

from pdsgen.deliver import make_delivery
from pdsgen.products.dtm import write_dtm
from pdsgen.validate import validate_paths

from helpers import elevation_array, run_cli, write_raster

CRS = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs"
# every identification keyword stated, as a filled-in `pdsgen params --template generic` states them
PARAMS = {"DATA_SET_ID": "TEST-M-DTM-5-V1.0", "DATA_SET_NAME": "TEST DTM V1.0",
          "PRODUCER_INSTITUTION_NAME": "SOME UNIVERSITY", "PRODUCER_ID": "SU", "PRODUCER_FULL_NAME": "JANE DOE",
          "INSTRUMENT_HOST_NAME": "TEST ORBITER", "INSTRUMENT_HOST_ID": "TO", "INSTRUMENT_NAME": "TEST CAMERA",
          "INSTRUMENT_ID": "TC", "RATIONALE_DESC": "Tests of the delivery text"}
TEXT = '''[delivery]
title = "Terrain of a test crater"
description = """A digital terrain model of a test crater,
made to check the delivery text."""
authors = ["Doe, Jane", "Roe, R."]
readme = """This volume holds one terrain model.

It was made for the tests."""
keywords = ["Mars", "topography"]
address = "1 Test Street, Testtown"
facility = "TEST LABORATORY"
'''


def _products(root: Path, seed: int = 4) -> Path:
    """Two small DTMs with PDS3 and PDS4 labels."""
    source = root / "products"
    heights = elevation_array(30, 20, seed=seed)
    transform = Affine(1.0, 0, 0, 0, -1.0, 0)
    for name in ("A_DTM", "B_DTM"):
        write_dtm(write_raster(root / f"{name}.tif", heights, CRS, transform), source, product_id=name,
                  label="both", params=PARAMS, overwrite=True)
    return source


def _text_file(root: Path, text: str = TEXT) -> Path:
    path = root / "delivery.toml"
    path.write_text(text)
    return path


def _text(path: Path) -> str:
    """A delivery's text file as written (CR LF line ends kept)."""
    return path.read_bytes().decode("ascii")


def _write(path: Path, text: str) -> None:
    path.write_bytes(text.encode("ascii"))


def _placeholders(out: Path) -> list[str]:
    return [f.message for f in validate_paths([out]).findings if f.rule == "DLV-006"]


def test_the_text_file_fills_every_placeholder_of_volume_and_bundle(tmp_path):
    source = _products(tmp_path)
    out = tmp_path / "delivery"
    result = make_delivery(source, out, dialect="both", volume_id="TEST_0001", bundle_lid="urn:nasa:pds:test",
                           text=_text_file(tmp_path))
    assert result.placeholders == 0 and _placeholders(out) == []
    volume = pvl.load(str(out / "VOLDESC.CAT"))["VOLUME"]
    assert volume["VOLUME_NAME"] == "Terrain of a test crater"
    assert volume["VOLUME_SET_ID"] == "TEST_0001"
    assert " ".join(volume["DESCRIPTION"].split()).endswith(
        "A digital terrain model of a test crater, made to check the delivery text.")
    producer = volume["DATA_PRODUCER"]
    assert (producer["INSTITUTION_NAME"], producer["FULL_NAME"], producer["ADDRESS_TEXT"]) == (
        "SOME UNIVERSITY", "Doe, Jane; Roe, R.", "1 Test Street, Testtown")
    readme = _text(out / "AAREADME.TXT")
    assert "\r\nThis volume holds one terrain model.\r\n\r\nIt was made for the tests.\r\n" in readme
    assert "Authors: Doe, Jane; Roe, R." in readme
    bundle = pds4_tools.read(str(out / "bundle_test.xml"), lazy_load=True, quiet=True).label
    assert bundle.findtext("Identification_Area/title") == "Terrain of a test crater"
    citation = bundle.find("Identification_Area/Citation_Information")
    assert [k.text for k in citation.findall("keyword")] == ["Mars", "topography"]
    people = citation.findall("List_Author/Person")
    assert [(p.findtext("family_name"), p.findtext("given_name")) for p in people] == [("Doe", "Jane"), ("Roe", "R.")]
    assert bundle.findtext("Bundle/description").startswith("A digital terrain model of a test crater")
    report = validate_paths([out])
    assert report.count("error") == 0 and report.summary()["placeholders"] == 0


def test_without_a_text_file_placeholders_remain_and_are_counted(tmp_path):
    out = tmp_path / "delivery"
    result = make_delivery(_products(tmp_path), out, dialect="both", volume_id="TEST_0001",
                           bundle_lid="urn:nasa:pds:test")
    found = _placeholders(out)
    assert result.placeholders == len(found) > 0
    assert any("VOLUME_NAME" in message for message in found)
    # each placeholder once: DLV-006 reports it, DICT-010 does not repeat it
    assert not [f for f in validate_paths([out]).findings if f.rule == "DICT-010" and "TO BE WRITTEN" in f.message]


def test_a_rerun_keeps_what_a_person_wrote_into_the_delivery(tmp_path):
    source = _products(tmp_path)
    out = tmp_path / "delivery"
    make_delivery(source, out, dialect="both", volume_id="TEST_0001", bundle_lid="urn:nasa:pds:test")
    voldesc = _text(out / "VOLDESC.CAT")
    _write(out / "VOLDESC.CAT", voldesc.replace("[TO BE WRITTEN: VOLUME_NAME]", "Hand written name"))
    readme = _text(out / "AAREADME.TXT")
    _write(out / "AAREADME.TXT", readme.replace(
        "[TO BE WRITTEN: what this volume holds and why, in a paragraph for its\r\nreaders]",
        "A paragraph written\r\nby hand."))
    assert [f.rule for f in validate_paths([out]).findings if f.rule == "DLV-020"] == ["DLV-020", "DLV-020"]
    again = make_delivery(source, out, dialect="both")
    assert pvl.load(str(out / "VOLDESC.CAT"))["VOLUME"]["VOLUME_NAME"] == "Hand written name"
    assert "\r\nA paragraph written by hand.\r\n" in _text(out / "AAREADME.TXT")
    assert not [f for f in validate_paths([out]).findings if f.rule == "DLV-020"]  # the manifest is new
    assert again.bundle_version == "1.0" and 'VOLUME_VERSION_ID    = "VERSION 1"' in _text(out / "VOLDESC.CAT")
    # a text file given later wins over the hand-written text, field by field
    make_delivery(source, out, dialect="both", text=_text_file(tmp_path))
    assert pvl.load(str(out / "VOLDESC.CAT"))["VOLUME"]["VOLUME_NAME"] == "Terrain of a test crater"
    make_delivery(source, out, dialect="both")  # and is kept by the next run without it
    assert pvl.load(str(out / "VOLDESC.CAT"))["VOLUME"]["VOLUME_NAME"] == "Terrain of a test crater"
    assert _placeholders(out) == []


def _versions(out: Path) -> tuple[str, str, str]:
    volume = pvl.load(str(out / "VOLDESC.CAT"))["VOLUME"]["VOLUME_VERSION_ID"]
    bundle = pds4_tools.read(str(out / "bundle_test.xml"), lazy_load=True, quiet=True).label
    inventory = (out / "DATA" / "collection_data_inventory.csv").read_text()
    a_dtm = next(line for line in inventory.splitlines() if ":a_dtm::" in line)
    return volume, bundle.findtext("Identification_Area/version_id"), a_dtm.rsplit("::", 1)[1]


def test_versions_advance_only_once_released_or_when_asked(tmp_path):
    source = _products(tmp_path)
    out = tmp_path / "delivery"
    make_delivery(source, out, dialect="both", volume_id="TEST_0001", bundle_lid="urn:nasa:pds:test")
    _products(tmp_path, seed=5)  # the products made again from other heights
    make_delivery(source, out, dialect="both")
    assert _versions(out) == ("VERSION 1", "1.0", "1.0")  # not released: brought up to date, same versions
    (out / ".released").touch()
    make_delivery(source, out, dialect="both")  # released, nothing changed: the same, still released
    assert _versions(out) == ("VERSION 1", "1.0", "1.0") and (out / ".released").is_file()
    _products(tmp_path, seed=6)
    changed = make_delivery(source, out, dialect="both")  # released and changed: the next version
    assert _versions(out) == ("VERSION 2", "2.0", "2.0") and "urn:nasa:pds:test:data:a_dtm::2.0" in changed.changed
    assert not (out / ".released").exists()  # the new version is not released yet
    make_delivery(source, out, dialect="both", new_version=True)  # asked: volume and bundle advance
    assert _versions(out) == ("VERSION 3", "3.0", "2.0")  # a product that did not change keeps its version
    assert not [f for f in validate_paths([out]).findings if f.severity == "error"]
    subprocess.run(["md5sum", "-c", "--quiet", "MD5SUMS.TXT"], cwd=out, check=True)


def test_the_release_marker_is_no_part_of_the_delivery(tmp_path):
    out = tmp_path / "delivery"
    make_delivery(_products(tmp_path), out, dialect="pds3", volume_id="TEST_0001")
    (out / ".released").touch()
    assert ".released" not in (out / "MD5SUMS.TXT").read_text()
    assert not [f for f in validate_paths([out]).findings if f.rule == "DLV-021"]


def test_index_creation_time_is_the_products_own(tmp_path):
    source = _products(tmp_path)
    made = datetime.datetime(2024, 3, 5, 6, 7, 8, tzinfo=datetime.timezone.utc).timestamp()
    os.utime(source / "A_DTM.IMG", (made, made))
    out = tmp_path / "delivery"
    make_delivery(source, out, dialect="pds3", volume_id="TEST_0001")
    label = pvl.load(str(out / "INDEX" / "INDEX.LBL"))
    names = [column["NAME"] for column in label["INDEX_TABLE"].getall("COLUMN")]
    with open(out / "INDEX" / "INDEX.TAB", newline="") as stream:
        rows = {row[2].strip(): dict(zip(names, (cell.strip() for cell in row), strict=True))
                for row in csv.reader(stream)}
    assert rows["A_DTM"]["PRODUCT_CREATION_TIME"] == "2024-03-05T06:07:08"
    assert rows["B_DTM"]["PRODUCT_CREATION_TIME"] != "N/A"


def test_label_both_equals_the_old_both_flag(tmp_path):
    source = _products(tmp_path)
    common = ["--volume-id", "TEST_0001", "--bundle-lid", "urn:nasa:pds:test", "-q"]
    new = run_cli("deliver", source, "-o", tmp_path / "new", "--label", "both", *common)
    old = run_cli("deliver", source, "-o", tmp_path / "old", "--both", *common)
    assert new.returncode == old.returncode == 0, new.stderr + old.stderr
    listed = [line.split("  ", 1)[1] for line in (tmp_path / "new" / "MD5SUMS.TXT").read_text().splitlines()]
    assert "bundle_test.xml" in listed and "VOLDESC.CAT" in listed
    for name in (*listed, "MD5SUMS.TXT"):
        assert (tmp_path / "new" / name).read_bytes() == (tmp_path / "old" / name).read_bytes(), name
    assert "--both" not in run_cli("deliver", "--help").stdout  # kept as a hidden alias


def test_label_and_an_old_flag_that_disagree_are_refused(tmp_path):
    told = run_cli("deliver", _products(tmp_path), "-o", tmp_path / "d", "--label", "pds4", "--pds3")
    assert told.returncode == 2 and not (tmp_path / "d").exists()
    assert told.stderr == ("pdsgen: error: --label pds4 and --pds3 disagree; give --label only "
                           "(see 'pdsgen deliver --help')\n")


@pytest.mark.parametrize(("text", "problem"), [
    ('[delivery]\ntitle = "T"\nsubtitle = "S"\n',
     "unknown key 'subtitle' in [delivery]; known keys: title, description, authors, readme, keywords, contact, "
     "address, institution, facility, volume_series_name, volume_set_name, volume_set_id"),
    ('[deliver]\ntitle = "T"\n', "unknown key 'deliver': the delivery text is the [delivery] table"),
    ('[delivery]\nauthors = "Doe, J."\n', '[delivery] authors must be a list of strings, e.g. authors = ["Last, F."]'),
    ('[delivery]\nauthors = ["Jane Doe"]\n',
     '[delivery] authors: each is "Last, F." (family name, comma, given names)'),
    ('[delivery]\ntitle = "A \\"quoted\\" title"\n',
     "[delivery] title: a PDS string cannot contain a double quote"),
])
def test_a_text_file_it_cannot_take_is_refused_in_one_line(tmp_path, text, problem):
    source = _products(tmp_path)
    path = _text_file(tmp_path, text)
    told = run_cli("deliver", source, "-o", tmp_path / "d", "--volume-id", "TEST_0001", "--text", path)
    assert told.returncode == 2 and not (tmp_path / "d").exists()
    assert told.stderr == f"pdsgen: error: {path}: {problem}\n"


def test_a_changed_file_tells_how_to_mend_the_manifest(tmp_path):
    out = tmp_path / "delivery"
    make_delivery(_products(tmp_path), out, dialect="pds3", volume_id="TEST_0001")
    with open(out / "AAREADME.TXT", "a") as stream:
        stream.write("More.\r\n")
    [finding] = [f for f in validate_paths([out]).findings if f.rule == "DLV-020"]
    line = next(n for n, text in enumerate((out / "MD5SUMS.TXT").read_text().splitlines(), 1)
                if text.endswith("  AAREADME.TXT"))
    assert finding.message == (
        f"MD5 differs from MD5SUMS.TXT line {line}: the file changed after the manifest was written; to mend, "
        "run pdsgen deliver again: it rewrites the manifest and keeps text written into AAREADME.TXT, "
        "VOLDESC.CAT or the bundle label (a delivery text file, [delivery] table, keeps it for good)")
    make_delivery(out, dialect="pds3")  # the mend the message names
    assert not [f for f in validate_paths([out]).findings if f.rule == "DLV-020"]


def test_the_four_keys_of_the_walk_through_leave_no_placeholder(tmp_path):
    """title, description, authors and readme are enough: the producer's facility and address,
    not given, are N/A (not applicable), not placeholders."""
    text = ('[delivery]\ntitle = "Crater terrain"\ndescription = "A DTM of a crater."\n'
            'authors = ["Doe, J."]\nreadme = "One DTM."\n')
    out = tmp_path / "delivery"
    result = make_delivery(_products(tmp_path), out, dialect="both", volume_id="TEST_0001",
                           bundle_lid="urn:nasa:pds:test", text=_text_file(tmp_path, text))
    producer = pvl.load(str(out / "VOLDESC.CAT"))["VOLUME"]["DATA_PRODUCER"]
    assert (producer["FACILITY_NAME"], producer["ADDRESS_TEXT"], producer["FULL_NAME"]) == ("N/A", "N/A", "Doe, J.")
    report = validate_paths([out], strict=True)
    assert result.placeholders == 0 and report.summary()["placeholders"] == 0
    # the delivery's own checks pass (the products have no Extras and made-up dictionary values: SET, DICT)
    assert [f"{f.rule} {f.message}" for f in report.findings if f.rule.startswith("DLV-")] == []
