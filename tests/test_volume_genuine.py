"""`pdsgen migrate VOLUME_DIR` on a small volume assembled from genuine parts of one data set
(EAR-A-I0046-3-FBIRTFSPEC-V3.0, SBN delivery volume SBN_0233: lower-case names on disk, an index
naming 53 products of which 3 are here, catalog and document files, attached TEXT labels;
provenance in tests/data/volume_fbirtfspec/PROVENANCE.md).

References that do not share the code's assumptions: the volume's own index/checksum.tab (MD5 of
every file as the data provider published it), pdr reading the PDS3 products, pds4_tools reading
the PDS4 labels, and the bundle label's facts as the data set catalog states them."""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

from pdsgen.migrate.volume import migrate_volume
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.label_checks import validate_pds4

from helpers import run_cli

pdr = pytest.importorskip("pdr")
pds4_tools = pytest.importorskip("pds4_tools")

VOLUME = Path(__file__).parent / "data" / "volume_fbirtfspec"
PDS = "{http://pds.nasa.gov/pds4/pds/v1}"
PRODUCTS = ("data/fieberbeyer2010/1358", "data/fieberbeyer2010/335", "data/fieberbeyer_gaffey2015/1447")


@pytest.fixture(scope="module")
def migrated(tmp_path_factory):
    out = tmp_path_factory.mktemp("genuine") / "bundle"
    result = migrate_volume(VOLUME, out, bundle_lid="urn:nasa:pds:fbirtfspec")
    return out, result


def _published_md5() -> dict[str, str]:
    """The MD5 of each file as the volume's own checksum table gives it."""
    rows = (VOLUME / "index" / "checksum.tab").read_text(encoding="ascii").splitlines()
    return {path: digest for digest, path in (row.split() for row in rows)}


def test_every_file_is_copied_as_published(migrated):
    out, _ = migrated
    published = _published_md5()
    here = [p.relative_to(VOLUME).as_posix() for p in VOLUME.rglob("*") if p.is_file() and p.name != "PROVENANCE.md"]
    assert len([name for name in here if name in published]) == len(here) - 2  # all but checksum.lbl/.tab
    for name in here:
        copy = out / name
        assert copy.is_file(), name
        if name in published:
            assert hashlib.md5(copy.read_bytes()).hexdigest() == published[name], name


def test_the_index_rows_of_absent_products_are_reported_and_nothing_else(migrated):
    _, result = migrated
    assert result.index == "index/index.tab"
    assert result.unindexed == []
    assert len(result.missing) == 53 - len(PRODUCTS)
    assert not [m for m in result.missing if any(p.upper() in m for p in PRODUCTS)]
    assert result.refused == () and result.collisions == []


def test_products_read_by_pds4_tools_equal_pdr_reading_the_pds3_labels(migrated):
    out, _ = migrated
    for product in PRODUCTS:
        pds3 = pdr.read(str(out / f"{product}.lbl"))["TABLE"]
        pds4 = pds4_tools.read(str(out / f"{product}.xml"), quiet=True)[0].data
        assert list(pds4.dtype.names) == ["WAVELENGTH", "REFLECTANCE", "UNCERTAINTY"]
        assert len(pds4) == len(pds3) > 100
        for column in pds4.dtype.names:
            assert np.array_equal(np.asarray(pds4[column], dtype=float), pds3[column].to_numpy(dtype=float)), column
    index3 = pdr.read(str(out / "index" / "index.lbl"))["INDEX_TABLE"]
    index4 = pds4_tools.read(str(out / "index" / "index.xml"), quiet=True)[0].data
    assert [str(v).strip() for v in index4["PRODUCT_ID"]] == [str(v).strip() for v in index3["PRODUCT_ID"]]


def test_every_catalog_and_document_file_is_a_product_document(migrated):
    out, _ = migrated
    described = {}
    for label in out.rglob("*.xml"):
        root = etree.parse(str(label)).getroot()
        for name in root.iter(f"{PDS}file_name"):
            described[(label.parent / name.text).relative_to(out).as_posix()] = root.tag.removeprefix(PDS)
    documents = ["voldesc.cat", "aareadme.txt", "catalog/catinfo.txt", "catalog/dataset.cat", "catalog/mission.cat",
                 "catalog/i0046inst.cat", "catalog/obs376t3host.cat", "catalog/targets/1447_utra.cat",
                 "document/ads.asc", "document/ads.lbl", "document/docinfo.txt", "index/indxinfo.txt"]
    for name in documents:
        assert described.get(name) == "Product_Document", name
    ads = etree.parse(str(out / "document" / "ads.xml")).getroot()
    assert [e.text for e in ads.iter(f"{PDS}file_name")] == ["ads.asc", "ads.lbl"]  # the document and its label


def test_the_bundle_label_states_the_data_set_catalog(migrated):
    out, _ = migrated
    root = etree.parse(str(out / "bundle_fbirtfspec.xml")).getroot()
    area = root.find(f"{PDS}Identification_Area")
    assert area.findtext(f"{PDS}title") == "FIEBER-BEYER IRTF MAINBELT ASTEROID SPECTRA V3.0"
    citation = area.find(f"{PDS}Citation_Information")
    assert citation.findtext(f"{PDS}publication_year") == "2015"  # DATA_SET_RELEASE_DATE
    assert citation.findtext(f"{PDS}description").startswith("Fieber-Beyer, S.K.")  # CITATION_DESC
    aliases = {a.findtext(f"{PDS}alternate_id"): a.findtext(f"{PDS}comment") for a in area.iter(f"{PDS}Alias")}
    assert aliases == {"EAR-A-I0046-3-FBIRTFSPEC-V3.0": "PDS3 DATA_SET_ID", "SBN_0233": "PDS3 VOLUME_ID"}
    assert "SpeX" in root.find(f"{PDS}Bundle").findtext(f"{PDS}description")  # ABSTRACT_DESC


@pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")
def test_labels_are_valid_and_the_bundle_validates(migrated):
    out, _ = migrated
    for label in sorted(out.rglob("*.xml")):
        assert [f for f in validate_pds4(label) if f.severity == "error"] == [], label
    checked = run_cli("validate", out)
    assert checked.returncode == 0 and " 0 error(s)" in checked.stdout, checked.stdout


def test_in_place_on_a_copy_leaves_every_published_byte(tmp_path):
    copy = tmp_path / "SBN_0233"
    shutil.copytree(VOLUME, copy)
    made = run_cli("migrate", copy, "--in-place", "--bundle-lid", "urn:nasa:pds:fbirtfspec")
    assert made.returncode == 0, made.stderr
    for name, digest in _published_md5().items():
        if (copy / name).is_file():
            assert hashlib.md5((copy / name).read_bytes()).hexdigest() == digest, name
    assert (copy / "data" / "fieberbeyer2010" / "1358.xml").is_file()


def test_pds4_tools_reads_the_crosswalk_and_the_inventories_as_written(migrated):
    """The crosswalk (Product_Ancillary, Table_Delimited) and each inventory, read by pds4_tools
    through their labels, say what the CSV files hold."""
    out, _ = migrated
    import csv

    table = pds4_tools.read(str(out / "crosswalk.xml"), quiet=True)[0].data
    with open(out / "crosswalk.csv", newline="") as stream:
        rows = [tuple(row) for row in csv.reader(stream)]
    assert [tuple(str(v) for v in row) for row in table] == rows
    lidvid = "urn:nasa:pds:fbirtfspec:data:fieberbeyer2010_1358_tab::1.0"
    assert ("FIEBERBEYER2010_1358_TAB", "data/fieberbeyer2010/1358.lbl", lidvid, "PDS3 label") in rows
    assert ("FIEBERBEYER2010_1358_TAB", "data/fieberbeyer2010/1358.tab", lidvid, "data file") in rows
    # every file of the volume has a row: catalogs and documents too (their Product_Document's LIDVID)
    assert {row[1] for row in rows} == {p.relative_to(VOLUME).as_posix() for p in VOLUME.rglob("*") if p.is_file()}
    documents = {row[1]: row[2] for row in rows if row[3] == "document"}
    assert documents["catalog/dataset.cat"] == "urn:nasa:pds:fbirtfspec:document:dataset::1.0"
    assert "voldesc.cat" in documents and "aareadme.txt" in documents
    for label in out.glob("collection_*.xml"):
        inventory = pds4_tools.read(str(label), quiet=True)[0].data
        written = (out / label.name.replace(".xml", "_inventory.csv")).read_text().splitlines()
        assert [f"{status},{lidvid}" for status, lidvid in inventory] == written
