"""pdsgen deliver: a PDS3 volume and a PDS4 bundle around real products, read back by
independent readers (pvl, pdr, lxml + the shipped schemas, Saxon Schematron, csv, md5sum),
re-runs that version what changed and leave nothing stale, and the validator's DLV rules
catching seeded defects."""

from __future__ import annotations

import csv
import os
import shutil
import subprocess
from pathlib import Path

import pytest
from affine import Affine
from lxml import etree

from pdsgen.deliver import make_delivery
from pdsgen.extras import make_extras
from pdsgen.products.dtm import write_dtm
from pdsgen.validate import validate_paths
from pdsgen.validate.pds4.label_checks import validate_label

from helpers import demo_products as make_demo_products
from helpers import elevation_array, run_cli, stderr_on_a_terminal, write_raster

REPO = Path(__file__).resolve().parents[1]
PDS_XSD = REPO / "schemas" / "pds4" / "1O00" / "PDS4_PDS_1O00.xsd"
PDS_NS = {"pds": "http://pds.nasa.gov/pds4/pds/v1"}
MADE_CLASSES = ("Product_Bundle", "Product_Collection", "Product_Browse", "Product_Document", "Product_Ancillary")
HRSC_SINUSOIDAL = "+proj=sinu +lon_0=0 +R=3396000 +units=m +no_defs"


@pytest.fixture(scope="module")
def demo_products(tmp_path_factory) -> Path:
    """The demo's products (DTM, orthoimage with JP2INFO.TXT, Extras) at a small size, with
    PDS3 and PDS4 labels (--label both)."""
    return make_demo_products(tmp_path_factory.mktemp("demo"))


def _copy(products: Path, tmp_path: Path) -> Path:
    source = tmp_path / "products"
    shutil.copytree(products, source)
    return source


def _errors(path: Path, *rules: str) -> list:
    report = validate_paths([path])
    return [f for f in report.findings if f.severity == "error" and (not rules or f.rule in rules)]


def test_pds3_volume_index_read_by_pvl_and_pdr(demo_products, tmp_path):
    import pdr
    import pvl

    out = tmp_path / "vol"
    result = make_delivery(demo_products, out, dialect="pds3", volume_id="DEMO_0001")
    assert result.products == 2 and result.previews == 13 and result.documents == 2
    for name in ("AAREADME.TXT", "VOLDESC.CAT", "INDEX/INDEX.TAB", "INDEX/INDEX.LBL", "DATA/JP2INFO.TXT",
                 "EXTRAS/README.TXT", "DATA/DTEEC_008669_1705_009025_1705_U01.IMG"):
        assert (out / name).is_file(), name
    label = pvl.load(str(out / "INDEX" / "INDEX.LBL"))
    table = label["INDEX_TABLE"]
    raw = (out / "INDEX" / "INDEX.TAB").read_bytes()
    rows = raw.split(b"\r\n")[:-1]
    assert raw.endswith(b"\r\n") and len(rows) == table["ROWS"] == 2
    assert all(len(row) + 2 == table["ROW_BYTES"] == label["RECORD_BYTES"] for row in rows)
    columns = table.getall("COLUMN")
    assert [c["NAME"] for c in columns][:3] == ["VOLUME_ID", "FILE_SPECIFICATION_NAME", "PRODUCT_ID"]
    for row in rows:  # every row through the columns pvl read: quoted strings, numbers obeying FORMAT
        values = {}
        for c in columns:
            start, size = c["START_BYTE"] - 1, c["BYTES"]
            text = row[start:start + size].decode()
            if c["DATA_TYPE"] == "CHARACTER":
                assert row[start - 1:start] == b'"' and row[start + size:start + size + 1] == b'"'
            elif c["DATA_TYPE"] == "ASCII_REAL":
                decimals = int(c["FORMAT"].split(".")[1])
                assert len(text.strip().split(".")[1]) == decimals
            values[c["NAME"]] = text.strip()
        product = pvl.load(str(out / values["FILE_SPECIFICATION_NAME"]))
        projection = product["IMAGE_MAP_PROJECTION"]
        assert values["PRODUCT_ID"] == product["PRODUCT_ID"] and values["VOLUME_ID"] == "DEMO_0001"
        for key in ("MAXIMUM_LATITUDE", "MINIMUM_LATITUDE", "WESTERNMOST_LONGITUDE", "EASTERNMOST_LONGITUDE"):
            assert float(values[key]) == pytest.approx(float(projection[key].value), abs=1e-12), key
    data = pdr.read(str(out / "INDEX" / "INDEX.LBL"))  # an independent reader of the table
    frame = data["INDEX_TABLE"]
    assert len(frame) == 2
    assert sorted(frame["PRODUCT_ID"].str.strip()) == ["DTEEC_008669_1705_009025_1705_U01",
                                                       "PSP_008669_1705_RED_C_01_ORTHO"]
    assert frame["LINES"].tolist() == [320, 320]
    voldesc = pvl.load(str(out / "VOLDESC.CAT"))
    assert voldesc["VOLUME"]["VOLUME_ID"] == "DEMO_0001"
    assert voldesc["VOLUME"]["DATA_SET_ID"] == "MRO-M-HIRISE-5-DTM-V1.0"
    subprocess.run(["md5sum", "-c", "--quiet", "MD5SUMS.TXT"], cwd=out, check=True)
    report = validate_paths([out])
    assert [f for f in report.findings if f.severity == "error"] == []
    placeholders = [f for f in report.findings if f.rule == "DLV-006"]
    assert {Path(f.file).name for f in placeholders} == {"VOLDESC.CAT", "AAREADME.TXT"}


def _made_labels(root: Path) -> list[Path]:
    labels = []
    for path in root.rglob("*.xml"):
        text = path.read_text()
        if any(f"<product_class>{c}</product_class>" in text for c in MADE_CLASSES):
            labels.append(path)
    return labels


def test_pds4_bundle_schema_and_schematron_valid(demo_products, tmp_path):
    out = tmp_path / "bundle"
    result = make_delivery(demo_products, out, dialect="both", volume_id="DEMO_0001",
                           bundle_lid="urn:nasa:pds:demo_dtm")
    schema = etree.XMLSchema(etree.parse(str(PDS_XSD)))
    labels = _made_labels(out)
    assert len(labels) == 1 + 4 + 13 + 2 + 1  # bundle, collections, browse, documents, the manifest's label
    for label in labels:
        assert schema.validate(etree.parse(str(label))), (label.name, schema.error_log)
        assert validate_label(label) == [], label.name  # XSD + Schematron (Saxon) + content
    for product in ("DTEEC_008669_1705_009025_1705_U01.xml", "PSP_008669_1705_RED_C_01_ORTHO.xml"):
        text = (out / "DATA" / product).read_text()
        assert "<logical_identifier>urn:nasa:pds:demo_dtm:data:" in text
        assert [f for f in validate_label(out / "DATA" / product) if f.severity == "error"] == []
    inventories = {}
    for name in ("DATA/collection_data_inventory.csv", "EXTRAS/collection_browse_inventory.csv",
                 "DOCUMENT/collection_document_inventory.csv"):
        with open(out / name, newline="") as stream:
            rows = list(csv.reader(stream))
        assert all(status == "P" and "::" in lidvid for status, lidvid in rows)
        inventories[name.split("/")[0]] = [lidvid for _, lidvid in rows]
    assert len(inventories["DATA"]) == 2 and len(inventories["EXTRAS"]) == 13 and len(inventories["DOCUMENT"]) == 2
    import pds4_tools  # an independent PDS4 reader of the collection label and its inventory table

    table = pds4_tools.read(str(out / "DATA" / "collection_data.xml"), quiet=True)[0]
    assert sorted(str(v) for v in table.fields[1]) == sorted(inventories["DATA"])
    browse = etree.parse(str(out / "EXTRAS" / "DTEEC_008669_1705_009025_1705_U01.br.xml"))
    target = browse.findtext(".//pds:Internal_Reference/pds:lidvid_reference", namespaces=PDS_NS)
    assert target == "urn:nasa:pds:demo_dtm:data:dteec_008669_1705_009025_1705_u01::1.0" in inventories["DATA"]
    bundle = etree.parse(str(out / "bundle_demo_dtm.xml"))
    members = bundle.findall(".//pds:Bundle_Member_Entry/pds:lidvid_reference", namespaces=PDS_NS)
    assert sorted(m.text for m in members) == ["urn:nasa:pds:demo_dtm:browse::1.0", "urn:nasa:pds:demo_dtm:data::1.0",
                                               "urn:nasa:pds:demo_dtm:document::1.0",
                                               "urn:nasa:pds:demo_dtm:miscellaneous::1.0"]
    manifest = etree.parse(str(out / "MD5SUMS.xml"))  # the manifest's label gives its MD5; no manifest lists it
    digest = subprocess.run(["md5sum", "MD5SUMS.TXT"], cwd=out, capture_output=True, text=True).stdout.split()[0]
    assert manifest.findtext(".//pds:File/pds:md5_checksum", namespaces=PDS_NS) == digest
    assert "MD5SUMS.xml" not in (out / "MD5SUMS.TXT").read_text()
    assert result.bundle_version == "1.0"
    subprocess.run(["md5sum", "-c", "--quiet", "MD5SUMS.TXT"], cwd=out, check=True)
    assert _errors(out) == []


def test_rerun_versions_what_changed_and_leaves_nothing_stale(demo_products, tmp_path):
    source = _copy(demo_products, tmp_path)
    out = tmp_path / "bundle"
    make_delivery(source, out, dialect="both", volume_id="DEMO_0001", bundle_lid="urn:nasa:pds:demo_dtm")
    with open(source / "extras" / "README.TXT", "a") as stream:
        stream.write("One more line.\r\n")
    (source / "extras" / "DTEEC_008669_1705_009025_1705_U01.th.jpg").unlink()
    (out / ".released").touch()  # versions advance only once a delivery is released (issue 44)
    again = make_delivery(source, out, dialect="both")  # volume id and bundle LID from the delivery
    assert again.volume_id == "DEMO_0001" and again.bundle_lid == "urn:nasa:pds:demo_dtm"
    assert again.bundle_version == "2.0"
    assert "urn:nasa:pds:demo_dtm:document:readme::2.0" in again.changed
    assert not any(":data:" in lidvid for lidvid in again.changed)
    assert not (out / "EXTRAS" / "DTEEC_008669_1705_009025_1705_U01.th.jpg").exists()
    assert not (out / "EXTRAS" / "DTEEC_008669_1705_009025_1705_U01.th.xml").exists()
    browse = (out / "EXTRAS" / "collection_browse_inventory.csv").read_text()
    assert ".th::" not in browse and len(browse.splitlines()) == 12
    assert "<version_id>2.0</version_id>" in (out / "DOCUMENT" / "collection_document.xml").read_text()
    assert "<version_id>1.0</version_id>" in (out / "DATA" / "collection_data.xml").read_text()
    assert "VERSION 2" in (out / "VOLDESC.CAT").read_text()
    assert list(tmp_path.glob(".bundle.*")) == []  # no work directory left
    subprocess.run(["md5sum", "-c", "--quiet", "MD5SUMS.TXT"], cwd=out, check=True)
    assert _errors(out) == []
    third = make_delivery(source, out, dialect="both")  # nothing changed: nothing re-versioned
    assert third.changed == [] and third.bundle_version == "2.0"
    for preview in (source / "extras").glob("*.QLOOK.JP2"):
        preview.unlink()
    for preview in (source / "extras").glob("*.jpg"):
        preview.unlink()
    (out / ".released").touch()
    fourth = make_delivery(source, out, dialect="both")  # the browse collection goes: a new bundle version
    assert fourth.bundle_version == "3.0" and not (out / "EXTRAS" / "collection_browse.xml").exists()
    assert "browse" not in (out / "bundle_demo_dtm.xml").read_text()


def test_in_place_delivery_moves_products_into_the_layout(demo_products, tmp_path):
    source = _copy(demo_products, tmp_path)
    (source / "notes.txt").write_text("kept\n")
    (source / ".hidden").mkdir()
    (source / ".hidden" / "state").write_text("kept too\n")
    make_delivery(source, dialect="pds3", volume_id="DEMO_0002")
    assert (source / ".hidden" / "state").read_text() == "kept too\n"
    assert (source / "DATA" / "DTEEC_008669_1705_009025_1705_U01.IMG").is_file()
    assert not (source / "DTEEC_008669_1705_009025_1705_U01.IMG").exists()
    assert (source / "notes.txt").read_text() == "kept\n"  # a file of no product stays, listed
    assert "notes.txt" in (source / "MD5SUMS.TXT").read_text()
    make_delivery(source, dialect="pds3")  # again, on the delivery itself
    assert _errors(source) == []


def _seed(out: Path, relative: str, old: str, new: str) -> None:
    path = out / relative
    data = path.read_bytes()
    assert old.encode() in data, (relative, old)
    path.write_bytes(data.replace(old.encode(), new.encode(), 1))


@pytest.fixture
def delivery(demo_products, tmp_path) -> Path:
    out = tmp_path / "bundle"
    make_delivery(demo_products, out, dialect="both", volume_id="DEMO_0001", bundle_lid="urn:nasa:pds:demo_dtm")
    return out


def test_seeded_index_row_value_differs(delivery):
    row = (delivery / "INDEX" / "INDEX.TAB").read_bytes().decode().split("\r\n")[0]
    fields = row.split(",")
    latitude = fields[10]  # MAXIMUM_LATITUDE, one degree off, same width
    digit = latitude.strip()[1]
    fields[10] = latitude.replace("-" + digit, "-" + str((int(digit) + 1) % 10), 1)
    _seed(delivery, "INDEX/INDEX.TAB", row, ",".join(fields))
    found = _errors(delivery, "DLV-004")
    assert len(found) == 1 and found[0].keyword == "MAXIMUM_LATITUDE" and found[0].line == 1


def test_seeded_product_missing_from_index_and_row_naming_missing_file(delivery):
    rows = (delivery / "INDEX" / "INDEX.TAB").read_bytes().split(b"\r\n")
    (delivery / "INDEX" / "INDEX.TAB").write_bytes(rows[1] + b"\r\n")
    found = _errors(delivery, "DLV-002", "DLV-001")
    assert any(f.rule == "DLV-002" and f.file.endswith("DTEEC_008669_1705_009025_1705_U01.IMG") for f in found)
    assert any(f.rule == "DLV-001" and "ROWS = 2" in f.message for f in found)
    (delivery / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.LBL").rename(delivery / "DATA" / "MOVED.LBL")
    assert [f.rule for f in _errors(delivery, "DLV-003")] == ["DLV-003"]


def test_seeded_inventory_defects(delivery):
    inventory = "DATA/collection_data_inventory.csv"
    first = (delivery / inventory).read_bytes().decode().split("\r\n")[0]
    _seed(delivery, inventory, first + "\r\n", "")
    assert [f.rule for f in _errors(delivery, "DLV-011")] == ["DLV-011"]  # a product absent from it
    with open(delivery / inventory, "a", newline="") as stream:
        stream.write("P,urn:nasa:pds:demo_dtm:data:ghost::1.0\r\n")
    found = _errors(delivery, "DLV-010")
    assert len(found) == 1 and "ghost" in found[0].message  # an entry without a product


def test_seeded_duplicated_lidvid(delivery):
    _seed(delivery, "EXTRAS/DTEEC_008669_1705_009025_1705_U01.th.xml",
          "urn:nasa:pds:demo_dtm:browse:dteec_008669_1705_009025_1705_u01.th<",
          "urn:nasa:pds:demo_dtm:browse:dteec_008669_1705_009025_1705_u01.br<")
    assert any(f.rule == "DLV-012" for f in _errors(delivery, "DLV-012"))


def test_entry_repeated_within_one_inventory_is_reported_once(delivery):
    """The inventory's own check (PDS4-056) reports it; the delivery check does not repeat it."""
    inventory = delivery / "DATA" / "collection_data_inventory.csv"
    rows = inventory.read_bytes().split(b"\r\n")
    assert len(rows) >= 3 and rows[-1] == b""
    inventory.write_bytes(b"\r\n".join(rows[:-2] + [rows[0], b""]))  # the last entry becomes the first again
    report = validate_paths([delivery])
    rules = [f.rule for f in report.findings if f.file.endswith("collection_data_inventory.csv")
             or f.file.endswith("collection_data.xml")]
    assert rules.count("PDS4-056") == 1 and "DLV-012" not in rules, rules


def test_seeded_browse_pointing_at_missing_product(delivery):
    _seed(delivery, "EXTRAS/PSP_008669_1705_RED_C_01_ORTHO.browse.xml",
          "urn:nasa:pds:demo_dtm:data:psp_008669_1705_red_c_01_ortho::1.0",
          "urn:nasa:pds:demo_dtm:data:psp_000000_0000_red_c_01_ortho::1.0")
    found = [f for f in validate_paths([delivery]).findings if f.rule == "DLV-014"]  # a warning, as NASA's
    assert len(found) == 1 and found[0].file.endswith("PSP_008669_1705_RED_C_01_ORTHO.browse.xml")


def test_seeded_file_changed_after_manifest(delivery):
    with open(delivery / "DATA" / "JP2INFO.TXT", "a") as stream:
        stream.write("edited\n")
    (delivery / "EXTRA_FILE.TXT").write_text("x\n")
    assert subprocess.run(["md5sum", "-c", "--quiet", "MD5SUMS.TXT"], cwd=delivery,
                          capture_output=True).returncode != 0
    found = {(f.rule, Path(f.file).name) for f in _errors(delivery, "DLV-020", "DLV-021")}
    assert found == {("DLV-020", "JP2INFO.TXT"), ("DLV-021", "EXTRA_FILE.TXT")}
    above = {(f.rule, Path(f.file).name) for f in _errors(delivery.parent, "DLV-020", "DLV-021")}
    assert above == found  # a delivery found under the directory given


def test_dlv_rules_configurable_and_listed(delivery):
    from pdsgen.validate.config import RuleSettings

    with open(delivery / "DATA" / "JP2INFO.TXT", "a") as stream:
        stream.write("edited\n")
    report = validate_paths([delivery], settings=RuleSettings(ignore=frozenset({"DLV-020"})))
    assert not any(f.rule == "DLV-020" for f in report.findings)
    listing = run_cli("validate", "--list-rules").stdout
    assert all(f"DLV-0{n}" in listing for n in ("01", "04", "10", "14", "20", "21"))
    json_report = run_cli("validate", str(delivery), "--format", "json")
    assert json_report.returncode == 1 and '"DLV-020"' in json_report.stdout


def test_hrsc_products_delivered_in_both_dialects(tmp_path):
    source = tmp_path / "products"
    heights = write_raster(tmp_path / "h.tif", elevation_array(30, 40, seed=12), HRSC_SINUSOIDAL,
                           Affine(50, 0, 100000, 0, -50, 300000))
    product = write_dtm(heights, source, profile="hrsc", product_id="h1234_0000", precision=0.5, label="both")
    make_extras([product.path], source / "extras")
    out = tmp_path / "delivery"
    result = make_delivery(source, out, dialect="both", volume_id="HRSC_0001", bundle_lid="urn:nasa:pds:hrsc_l4")
    assert result.products == 1 and result.previews > 0
    rows = (out / "INDEX" / "INDEX.TAB").read_text().splitlines()
    assert len(rows) == 1 and '"DATA/h1234_0000_dt4.img' in rows[0]
    assert "SINUSOIDAL" in rows[0]
    for label in _made_labels(out):
        assert validate_label(label) == [], label.name
    subprocess.run(["md5sum", "-c", "--quiet", "MD5SUMS.TXT"], cwd=out, check=True)
    assert _errors(out) == []


def test_two_products_with_one_product_id_are_refused_and_nothing_is_lost(demo_products, tmp_path):
    """One PRODUCT_ID would be one index row and one LID: the second label would vanish from the
    delivery (and, in place, from the disk)."""
    source = tmp_path / "products"
    name = "DTEEC_008669_1705_009025_1705_U01"
    for copy in ("a", "b"):
        (source / copy).mkdir(parents=True)
        for suffix in (".IMG", ".xml"):
            shutil.copy(demo_products / f"{name}{suffix}", source / copy / f"{name}{suffix}")
    before = sorted(p.relative_to(source) for p in source.rglob("*"))
    for out in ([], ["-o", str(tmp_path / "out")]):
        refused = run_cli("deliver", str(source), *out, "--both", "--volume-id", "DEMO_0001",
                          "--bundle-lid", "urn:nasa:pds:demo_dtm")
        assert refused.returncode == 2 and refused.stderr.count("\n") == 1, refused.stderr
        assert f"a/{name}" in refused.stderr and f"b/{name}" in refused.stderr and "product ID" in refused.stderr
        assert sorted(p.relative_to(source) for p in source.rglob("*")) == before
    assert not (tmp_path / "out").exists() and list(tmp_path.glob(".*")) == []


def test_an_output_that_cannot_be_made_is_one_line(demo_products, tmp_path):
    a_file = tmp_path / "file"
    a_file.write_text("not a directory")
    refused = run_cli("deliver", str(demo_products), "-o", str(a_file / "out"), "--pds3", "--volume-id", "DEMO_0001")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1, refused.stderr
    assert "Traceback" not in refused.stderr and str(a_file / "out") in refused.stderr


def test_cli_deliver_and_bad_input(demo_products, tmp_path):
    out = tmp_path / "vol"
    done = run_cli("deliver", str(demo_products), "-o", str(out), "--pds3", "--volume-id", "DEMO_0001")
    assert done.returncode == 0, done.stderr
    assert "CHECK    pdsgen validate" in done.stdout and (out / "MD5SUMS.TXT").is_file()
    check = run_cli("validate", str(out))
    assert check.returncode == 0, check.stdout
    missing = run_cli("deliver", str(demo_products), "-o", str(tmp_path / "v2"), "--pds3")
    assert missing.returncode == 2 and missing.stderr.count("\n") == 1 and "--volume-id" in missing.stderr
    assert not (tmp_path / "v2").exists()
    pds3_only = tmp_path / "pds3_only"
    pds3_only.mkdir()
    for name in ("DTEEC_008669_1705_009025_1705_U01.IMG",):
        shutil.copy(demo_products / name, pds3_only / name)
        os.truncate(pds3_only / name, (pds3_only / name).stat().st_size - 4)  # migration refuses it
    refused = run_cli("deliver", str(pds3_only), "-o", str(tmp_path / "b"), "--pds4",
                      "--bundle-lid", "urn:nasa:pds:x")
    assert refused.returncode == 2 and "truncated" in refused.stderr and "Traceback" not in refused.stderr
    assert not (tmp_path / "b").exists() and list(tmp_path.glob(".b.*")) == []
    inside = run_cli("deliver", str(out / "DATA"), "-o", str(out), "--volume-id", "DEMO_0001")
    assert inside.returncode == 2 and "inside the delivery" in inside.stderr
    assert (out / "EXTRAS" / "README.TXT").is_file()  # the delivery is as it was
    bad_lid = run_cli("deliver", str(demo_products), "-o", str(tmp_path / "c"), "--pds4", "--bundle-lid", "nasa:X")
    assert bad_lid.returncode == 2 and "urn:nasa:pds:NAME" in bad_lid.stderr


def test_imars_products_refused_with_the_reason(tmp_path):
    """iMars products (GeoTIFF + PVL + GeoJSON) carry no PDS3 or PDS4 label: refused, nothing written."""
    from pdsgen.products.dtm import write_dtm

    south_polar = "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs"
    heights = write_raster(tmp_path / "in.tif", elevation_array(40, 30, seed=11), south_polar,
                           Affine(100.0, 0, -20000.0, 0, -100.0, 150000.0))
    product = write_dtm(heights, tmp_path / "imars", profile="imars", product_id="h0022_0000")
    refused = run_cli("deliver", str(tmp_path / "imars"), "-o", str(tmp_path / "out"), "--both",
                      "--volume-id", "IMARS_0001", "--bundle-lid", "urn:nasa:pds:imars")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1
    assert product.pvl_path.name in refused.stderr and "neither a PDS3 nor a PDS4 label" in refused.stderr
    assert not (tmp_path / "out").exists()


def test_readme_delivery_examples_run_as_written(tmp_path):
    import re
    import shlex
    import sys

    import numpy as np

    from helpers import ORIGINS

    crs, transform = ORIGINS["equirectangular"]
    write_raster(tmp_path / "my_dtm.tif", elevation_array(40, 30, seed=3), crs, transform)
    write_raster(tmp_path / "ortho_red.tif", np.random.default_rng(5).integers(1, 255, (40, 30)).astype("uint8"),
                 crs, transform)
    import docs_text
    docs_text.walkthrough_params(tmp_path)  # the params.toml the examples name, as the walk-through writes it
    body = docs_text.section("Preparing a delivery")
    examples = [line for block in re.findall(r"```sh\n(.*?)```", body, re.S) for line in block.splitlines()
                if line.startswith("pdsgen ")]
    assert len(examples) == 5
    for example in examples:
        result = subprocess.run([sys.executable, "-m", "pdsgen", *shlex.split(example)[1:]], cwd=tmp_path,
                                capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, f"{example}\n{result.stdout}{result.stderr}"
    printed = subprocess.run([sys.executable, "-m", "pdsgen", *shlex.split(examples[3])[1:]], cwd=tmp_path,
                             capture_output=True, text=True, timeout=300).stdout
    assert printed.splitlines()[0] in body  # the summary as the README shows it (a re-run: same counts)
    assert (tmp_path / "delivery" / "bundle_my_dtms.xml").is_file()


def test_progress_on_a_terminal_only(demo_products, tmp_path):
    import sys

    args = [sys.executable, "-m", "pdsgen", "deliver", str(demo_products), "-o", str(tmp_path / "tty"),
            "--volume-id", "DEMO_0001"]
    returncode, text = stderr_on_a_terminal(*args[3:])
    assert returncode == 0 and "100%" in text and " products" in text and text.endswith("\r\033[K")
    piped = subprocess.run(args[:-4] + ["-o", str(tmp_path / "piped"), "--volume-id", "DEMO_0001"],
                           capture_output=True, text=True)
    assert piped.returncode == 0 and piped.stderr == ""


def test_pds4_alone_and_pds3_alone_validate_clean(demo_products, tmp_path):
    bundle = make_delivery(demo_products, tmp_path / "pds4", dialect="pds4", bundle_lid="urn:nasa:pds:demo_dtm")
    assert not (bundle.path / "INDEX").exists() and not (bundle.path / "VOLDESC.CAT").exists()
    assert _errors(bundle.path) == []
    volume = make_delivery(demo_products, tmp_path / "pds3", dialect="pds3", volume_id="DEMO_0001")
    assert not list(volume.path.glob("bundle_*.xml")) and not (volume.path / "DOCUMENT").exists()
    assert _errors(volume.path) == []
    (volume.path / "INDEX" / "INDEX.LBL").unlink()
    assert [f.rule for f in _errors(volume.path, "DLV-002")] == ["DLV-002"]


def test_a_replaced_product_and_its_previews_get_the_next_version(tmp_path):
    """A DTM made again from other heights: its LIDVID and its previews' go to 2.0, the collection and
    bundle follow; the orthoimage keeps 1.0. In place: the products move into DATA/ and stay there."""
    crs, transform = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs", Affine(1.0, 0, 0, 0, -1.0, 0)
    source = tmp_path / "products"
    heights = elevation_array(30, 20, seed=4)
    write_dtm(write_raster(tmp_path / "a.tif", heights, crs, transform), source, product_id="A_DTM", label="both")
    write_dtm(write_raster(tmp_path / "b.tif", heights, crs, transform), source, product_id="B_DTM", label="both")
    make_extras([source / "A_DTM.IMG"], source / "extras")
    make_delivery(source, dialect="pds4", bundle_lid="urn:nasa:pds:two")
    assert (source / "DATA" / "A_DTM.IMG").is_file() and not (source / "A_DTM.IMG").exists()
    write_dtm(write_raster(tmp_path / "a2.tif", heights + 5.0, crs, transform), source / "DATA", product_id="A_DTM",
              label="both", overwrite=True)
    make_extras([source / "DATA" / "A_DTM.IMG"], source / "EXTRAS", overwrite=True)  # its Extras, remade with it
    (source / ".released").touch()  # versions advance only once a delivery is released (issue 44)
    again = make_delivery(source, dialect="pds4")
    assert "urn:nasa:pds:two:data:a_dtm::2.0" in again.changed
    assert "urn:nasa:pds:two:browse:a_dtm.br::2.0" in again.changed
    assert not any(lidvid.startswith("urn:nasa:pds:two:data:b_dtm") for lidvid in again.changed)
    assert again.bundle_version == "2.0"
    inventory = (source / "DATA" / "collection_data_inventory.csv").read_text()
    assert "urn:nasa:pds:two:data:a_dtm::2.0" in inventory and "urn:nasa:pds:two:data:b_dtm::1.0" in inventory
    assert "::1.0" not in inventory.split("a_dtm")[1].splitlines()[0]
    label = (source / "DATA" / "A_DTM.xml").read_text()
    assert "<version_id>2.0</version_id>" in label and "urn:nasa:pds:two:data:a_dtm<" in label
    assert _errors(source) == []


def test_verbose_tells_what_was_found_and_written(demo_products, tmp_path):
    told = run_cli("deliver", str(demo_products), "-o", str(tmp_path / "v"), "--volume-id", "DEMO_0001", "-v")
    assert told.returncode == 0
    assert "2 data product(s), 13 preview(s), 2 document(s)" in told.stderr
    assert "INDEX/INDEX.TAB: 2 row(s)" in told.stderr and "MD5SUMS.TXT: MD5 of" in told.stderr


def test_seeded_volume_and_bundle_defects(delivery):
    """VOLUME_ID disagreeing, an index label whose ROW_BYTES the rows do not have, a bundle missing a
    collection, an inventory member under another collection's LID: each its DLV rule."""
    voldesc = (delivery / "VOLDESC.CAT").read_bytes().decode()
    _seed(delivery, "VOLDESC.CAT", 'VOLUME_ID            = "DEMO_0001"', 'VOLUME_ID            = "DEMO_0009"')
    assert {f.rule for f in _errors(delivery, "DLV-005")} == {"DLV-005"}
    (delivery / "VOLDESC.CAT").write_bytes(voldesc.encode())
    row_bytes = len((delivery / "INDEX" / "INDEX.TAB").read_bytes().split(b"\r\n")[0]) + 2
    _seed(delivery, "INDEX/INDEX.LBL", f"ROW_BYTES           = {row_bytes}", f"ROW_BYTES           = {row_bytes + 1}")
    assert any("ROW_BYTES" in f.message for f in _errors(delivery, "DLV-001"))
    bundle = etree.parse(str(delivery / "bundle_demo_dtm.xml"))
    entry = bundle.find(".//pds:Bundle_Member_Entry", PDS_NS)
    entry.getparent().remove(entry)
    bundle.write(str(delivery / "bundle_demo_dtm.xml"), xml_declaration=True, encoding="UTF-8")
    assert [f.rule for f in _errors(delivery, "DLV-015")] == ["DLV-015"]
    with open(delivery / "DATA" / "collection_data_inventory.csv", "a", newline="") as stream:
        stream.write("P,urn:nasa:pds:demo_dtm:browse:dteec_008669_1705_009025_1705_u01.br::1.0\r\n")
    found = _errors(delivery, "DLV-013")
    assert len(found) == 1 and "not under the collection's LID urn:nasa:pds:demo_dtm:data" in found[0].message


def test_index_table_found_through_its_label_pointer(delivery):
    """The validator reads the table INDEX.LBL points at, not a name of its own."""
    (delivery / "INDEX" / "INDEX.TAB").rename(delivery / "INDEX" / "PRODUCTS.TAB")
    _seed(delivery, "INDEX/INDEX.LBL", '^INDEX_TABLE          = "INDEX.TAB"', '^INDEX_TABLE          = "PRODUCTS.TAB"')
    assert _errors(delivery, "DLV-001", "DLV-002", "DLV-003", "DLV-004") == []
    _seed(delivery, "INDEX/PRODUCTS.TAB", '"DEMO_0001"', '"DEMO_0002"')
    assert [f.rule for f in _errors(delivery, "DLV-005")] == ["DLV-005"]


def test_pds4_labels_named_lblx_are_products_of_the_bundle(demo_products, tmp_path):
    """.lblx is the PDS4 standard's own label extension: such a label makes a product of the
    bundle like an .xml one, and the delivery checks read it."""
    source = _copy(demo_products, tmp_path)
    xml = source / "DTEEC_008669_1705_009025_1705_U01.xml"
    xml.rename(xml.with_suffix(".lblx"))
    out = tmp_path / "bundle"
    result = make_delivery(source, out, dialect="pds4", bundle_lid="urn:nasa:pds:demo_dtm")
    assert result.products == 2
    lblx = out / "DATA" / "DTEEC_008669_1705_009025_1705_U01.lblx"
    assert not list(out.rglob("DTEEC_008669_1705_009025_1705_U01.xml"))
    lid = etree.parse(str(lblx)).findtext("pds:Identification_Area/pds:logical_identifier", namespaces=PDS_NS)
    assert lid == "urn:nasa:pds:demo_dtm:data:dteec_008669_1705_009025_1705_u01"  # given the bundle's LID
    with open(out / "DATA" / "collection_data_inventory.csv", newline="") as stream:
        assert lid in [row[1].split("::")[0] for row in csv.reader(stream)]
    assert _errors(out) == []
    ortho_lid = "urn:nasa:pds:demo_dtm:data:psp_008669_1705_red_c_01_ortho"
    lblx.write_text(lblx.read_text().replace(lid + "<", ortho_lid + "<"))
    assert any(f.rule == "DLV-012" for f in _errors(out, "DLV-012"))  # the .lblx label is among those compared


@pytest.mark.parametrize("jobs", [1, 2])
def test_file_checks_and_their_progress_start_before_the_delivery_checks(delivery, monkeypatch, jobs, tmp_path):
    """A delivery is checked whole when the first report asks for its findings (with workers:
    after a first pass reading each file, in a process of its own), so the count of files checked
    moves from the start; the findings are the same. Events are told through a file, which the
    checking process writes too."""
    from pdsgen.validate.families import delivery_rules

    expected = {(f.rule, f.file) for f in validate_paths([delivery]).findings if f.rule.startswith("DLV")}
    log = tmp_path / "events"
    checked = delivery_rules.check_delivery

    def event(name: str) -> None:
        with open(log, "a") as stream:
            stream.write(name + "\n")

    def recorded(root, labels_only=False):
        event("delivery")
        return checked(root, labels_only)

    monkeypatch.setattr(delivery_rules, "check_delivery", recorded)
    with open(delivery / "DATA" / "JP2INFO.TXT", "a") as stream:  # one DLV finding to carry
        stream.write("edited\n")
    report = validate_paths([delivery], jobs=jobs, progress=lambda done, total: event("file"))
    events = log.read_text().split()
    assert events[0] == "file" and events.count("delivery") == 1
    found = {(f.rule, f.file) for f in report.findings if f.rule.startswith("DLV")}
    assert found - expected == {("DLV-020", str(delivery / "DATA" / "JP2INFO.TXT"))}


def test_a_pointer_to_several_files_brings_every_one_into_the_delivery(tmp_path):
    """^ASCII_DOCUMENT = {"NFREDR4.H", "NFREDR41.C"} (a Galileo Probe software label): both files
    belong to the product, as the validator reads the pointer."""
    from pdsgen.archive.scan import pointed_files
    from pdsgen.label.parser import parse_label

    text = ('PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\n^ASCII_DOCUMENT = {"NFREDR4.H", "NFREDR41.C"}\r\n'
            '^TABLE = ("NFR.TAB", 2)\r\nEND\r\n')
    for name in ("NFREDR4.H", "NFREDR41.C", "NFR.TAB"):
        (tmp_path / name).write_text("x\r\n")
    root = parse_label(text).root
    assert pointed_files(root, tmp_path) == ["NFREDR4.H", "NFREDR41.C", "NFR.TAB"]


def test_browse_and_collection_labels_a_delivery_makes_are_never_taken_as_products(tmp_path):
    """A delivery remakes its own Product_Browse/Collection/Bundle/Document labels, whichever of
    the two PDS4 label names they have in the source."""
    from pdsgen.archive.scan import is_made_by_delivery

    head = ('<?xml version="1.0" encoding="UTF-8"?>\n<Product_Browse xmlns="http://pds.nasa.gov/pds4/pds/v1">\n'
            '<Identification_Area><product_class>Product_Browse</product_class></Identification_Area>\n'
            '</Product_Browse>\n')
    for name in ("X.browse.xml", "X.browse.lblx", "X.browse.LBLX"):
        (tmp_path / name).write_text(head)
        assert is_made_by_delivery(tmp_path / name, Path(name)), name
    (tmp_path / "X.lblx").write_text(head.replace("Product_Browse", "Product_Observational"))
    assert not is_made_by_delivery(tmp_path / "X.lblx", Path("X.lblx"))


def test_a_label_without_product_id_is_named_by_its_file_and_deliver_says_so(demo_products, tmp_path):
    """Issue 49: deliver invents no identifier without saying so. The DTM's PRODUCT_ID replaced by
    a comment of the same length: its index row (read by pdr through INDEX.LBL) takes the file's
    name, and one warning line names the label - on stderr and in --json's warnings; the same
    product with its PRODUCT_ID is delivered without one."""
    import json
    import re

    import pdr

    name = "DTEEC_008669_1705_009025_1705_U01"
    stated, unstated = tmp_path / "stated", tmp_path / "unstated"
    for source in (stated, unstated):
        source.mkdir()
        shutil.copy(demo_products / f"{name}.IMG", source / f"{name}.IMG")
    label = unstated / f"{name}.IMG"
    data = label.read_bytes()
    statement = re.search(rb"PRODUCT_ID += \"?\w+\"?", data)
    assert statement is not None
    label.write_bytes(data.replace(statement.group(0), b"/* no identifier */".ljust(len(statement.group(0))), 1))
    quiet = run_cli("deliver", str(stated), "-o", str(tmp_path / "v1"), "--pds3", "--volume-id", "DEMO_0001", "-q")
    assert quiet.returncode == 0 and quiet.stderr == "", quiet.stderr
    done = run_cli("deliver", str(unstated), "-o", str(tmp_path / "v2"), "--pds3", "--volume-id", "DEMO_0001",
                   "--json")
    assert done.returncode == 0, done.stderr
    said = (f"{label}: no PRODUCT_ID in the label; the delivery names the product {name} after its file name "
            "(its index row and identifiers); state PRODUCT_ID in the label to choose it")
    assert done.stderr.splitlines() == [f"warning: {said}"]
    assert json.loads(done.stdout)["warnings"] == [said]
    frame = pdr.read(str(tmp_path / "v2" / "INDEX" / "INDEX.LBL"))["INDEX_TABLE"]
    assert frame["PRODUCT_ID"].str.strip().tolist() == [name]
    assert {f.rule for f in validate_paths([tmp_path / "v2"]).findings if f.severity == "warning"} >= {"IDN-001"}
