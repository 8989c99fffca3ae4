"""A bundle directory that keeps its release history: each version of the bundle and of a
collection is checked against its own members and inventory.

Archives such as NASA's SPICE bundles keep every release in one directory (validate's suite
case github597: bundle versions 1-3, collection_spice_kernels v001-v003 with their
inventories). An older version is complete for its own release only: bundle 1.0 does not
list the collection versions made after it, and a version 1.0 inventory does not list the
products added in 2.0. A product's membership follows the latest collection version that
lists it (a newer inventory names the older products again as secondary members, S).

The bundle here is written by the test from the PDS4 Standards' own definitions
(Product_Bundle with Bundle_Member_Entry, Product_Collection with File_Area_Inventory, an
inventory of P/S,LIDVID records in PDS DSV 1), not by pdsgen's writer: two bundle versions
and three versions of one collection. Bundle 1.0 names collection 1.0 by LIDVID; bundle 2.0
names the collection by LID (every version). The consistent history passes `pdsgen validate`;
each genuine membership error planted in it is reported, and nothing else.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

BUNDLE = "urn:nasa:pds:release_history"
COLLECTION = f"{BUNDLE}:document"
HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n'
        '<?xml-model href="https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.sch" '
        'schematypens="http://purl.oclc.org/dsdl/schematron"?>\n')
ROOT = ('xmlns="http://pds.nasa.gov/pds4/pds/v1" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" '
        'xsi:schemaLocation="http://pds.nasa.gov/pds4/pds/v1 https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.xsd"')

# The collection's releases: (version, inventory records). Each release names the products it
# adds as primary members (P) and those of the releases before it as secondary ones (S).
RELEASES = [
    ("1.0", [("P", "doc_a::1.0")]),
    ("2.0", [("S", "doc_a::1.0"), ("P", "doc_b::1.0")]),
    ("3.0", [("S", "doc_a::1.0"), ("S", "doc_b::1.0"), ("P", "doc_a::2.0"), ("P", "doc_c::1.0")]),
]
PRODUCTS = ["doc_a::1.0", "doc_b::1.0", "doc_a::2.0", "doc_c::1.0"]


def _identification(lid: str, version: str, title: str, product_class: str) -> str:
    return (f"  <Identification_Area>\n"
            f"    <logical_identifier>{lid}</logical_identifier>\n"
            f"    <version_id>{version}</version_id>\n"
            f"    <title>{title}</title>\n"
            f"    <information_model_version>1.24.0.0</information_model_version>\n"
            f"    <product_class>{product_class}</product_class>\n"
            f"    <Citation_Information>\n"
            f"      <publication_year>2026</publication_year>\n"
            f"      <description>{title}, version {version}.</description>\n"
            f"    </Citation_Information>\n"
            f"  </Identification_Area>\n")


def _bundle_label(version: str, member: tuple[str, str]) -> str:
    """A Product_Bundle whose one Bundle_Member_Entry names the collection (tag, value)."""
    tag, value = member
    return (HEAD + f"<Product_Bundle {ROOT}>\n"
            + _identification(BUNDLE, version, "Release history test bundle", "Product_Bundle")
            + "  <Bundle>\n    <bundle_type>Archive</bundle_type>\n  </Bundle>\n"
              "  <Bundle_Member_Entry>\n"
              f"    <{tag}>{value}</{tag}>\n"
              "    <member_status>Primary</member_status>\n"
              "    <reference_type>bundle_has_document_collection</reference_type>\n"
              "  </Bundle_Member_Entry>\n"
              "</Product_Bundle>\n")


def _collection_label(version: str, inventory: str, records: int) -> str:
    """A Product_Collection with its inventory: a PDS DSV 1 table of (Member_Status, LIDVID_LID)."""
    return (HEAD + f"<Product_Collection {ROOT}>\n"
            + _identification(COLLECTION, version, "Release history test documents", "Product_Collection")
            + "  <Collection>\n    <collection_type>Document</collection_type>\n  </Collection>\n"
              "  <File_Area_Inventory>\n"
              f"    <File>\n      <file_name>{inventory}</file_name>\n    </File>\n"
              "    <Inventory>\n"
              '      <offset unit="byte">0</offset>\n'
              "      <parsing_standard_id>PDS DSV 1</parsing_standard_id>\n"
              f"      <records>{records}</records>\n"
              "      <record_delimiter>Carriage-Return Line-Feed</record_delimiter>\n"
              "      <field_delimiter>Comma</field_delimiter>\n"
              "      <Record_Delimited>\n"
              "        <fields>2</fields>\n"
              "        <groups>0</groups>\n"
              "        <Field_Delimited>\n"
              "          <name>Member Status</name>\n"
              "          <field_number>1</field_number>\n"
              "          <data_type>ASCII_String</data_type>\n"
              "          <maximum_field_length unit=\"byte\">1</maximum_field_length>\n"
              "        </Field_Delimited>\n"
              "        <Field_Delimited>\n"
              "          <name>LIDVID_LID</name>\n"
              "          <field_number>2</field_number>\n"
              "          <data_type>ASCII_LIDVID_LID</data_type>\n"
              "          <maximum_field_length unit=\"byte\">255</maximum_field_length>\n"
              "        </Field_Delimited>\n"
              "      </Record_Delimited>\n"
              "      <reference_type>inventory_has_member_product</reference_type>\n"
              "    </Inventory>\n"
              "  </File_Area_Inventory>\n"
              "</Product_Collection>\n")


def _document_label(name: str, version: str, text_file: str) -> str:
    """A Product_Document of one plain-text file."""
    return (HEAD + f"<Product_Document {ROOT}>\n"
            + _identification(f"{COLLECTION}:{name}", version, f"Document {name}", "Product_Document")
            + "  <Document>\n"
              "    <publication_date>2026-01-01</publication_date>\n"
              "    <Document_Edition>\n"
              "      <edition_name>English</edition_name>\n"
              "      <language>English</language>\n"
              "      <files>1</files>\n"
              "      <Document_File>\n"
              f"        <file_name>{text_file}</file_name>\n"
              "        <document_standard_id>7-Bit ASCII Text</document_standard_id>\n"
              "      </Document_File>\n"
              "    </Document_Edition>\n"
              "  </Document>\n"
              "</Product_Document>\n")


def _write_inventory(path: Path, records: list[tuple[str, str]]) -> None:
    """PDS DSV 1 records, each ended by CR LF (the record_delimiter the label states)."""
    path.write_bytes(b"".join(f"{status},{COLLECTION}:{member}\r\n".encode() for status, member in records))


def _add_product(directory: Path, member: str) -> None:
    name, version = member.split("::")
    stem = f"{name}_v{version.split('.')[0]}"
    (directory / f"{stem}.txt").write_bytes(f"Document {name}, version {version}.\r\n".encode())
    (directory / f"{stem}.xml").write_text(_document_label(name, version, f"{stem}.txt"), encoding="utf-8")


def _inventory_name(version: str) -> str:
    return f"collection_document_inventory_v{version.split('.')[0]:0>3}.csv"


@pytest.fixture
def history(tmp_path: Path) -> Path:
    """The bundle directory: bundle 1.0 and 2.0 at its root, collection 1.0-3.0 and their
    products under document/."""
    root = tmp_path / "release_history"
    documents = root / "document"
    documents.mkdir(parents=True)
    (root / "bundle_release_history_v001.xml").write_text(
        _bundle_label("1.0", ("lidvid_reference", f"{COLLECTION}::1.0")), encoding="utf-8")
    (root / "bundle_release_history_v002.xml").write_text(
        _bundle_label("2.0", ("lid_reference", COLLECTION)), encoding="utf-8")
    for version, records in RELEASES:
        inventory = _inventory_name(version)
        _write_inventory(documents / inventory, records)
        label = _collection_label(version, inventory, len(records))
        (documents / f"collection_document_v{version.split('.')[0]:0>3}.xml").write_text(label, encoding="utf-8")
    for member in PRODUCTS:
        _add_product(documents, member)
    return root


def _validate(directory: Path) -> tuple[int, list[tuple[str, str, str]]]:
    """`pdsgen validate DIR` as a user runs it: its exit status and its (rule, severity, file) findings."""
    done = subprocess.run([sys.executable, "-m", "pdsgen", "validate", "--format", "json", "--no-config",
                           str(directory)], capture_output=True, text=True)
    assert done.returncode in (0, 1), done.stderr
    report = json.loads(done.stdout)
    return done.returncode, sorted((f["rule"], f["severity"], Path(entry["path"]).name)
                                   for entry in report["files"] for f in entry["findings"])


def _errors(findings: list[tuple[str, str, str]]) -> list[tuple[str, str, str]]:
    return [finding for finding in findings if finding[1] == "error"]


def test_a_consistent_release_history_passes(history):
    """No version is asked for what was released after it: no DLV finding, no error."""
    status, findings = _validate(history)
    assert [f for f in findings if f[0].startswith("DLV")] == []
    assert _errors(findings) == [] and status == 0


def test_a_product_no_inventory_lists_is_the_one_error(history):
    """A product under the collection's LID that no version's inventory lists."""
    _add_product(history / "document", "doc_d::1.0")
    assert _errors(_validate(history)[1]) == [("DLV-011", "error", "doc_d_v1.xml")]


def test_an_absent_primary_member_of_one_version_is_the_one_error(history):
    """Version 2.0's inventory names a primary member no label of the directory has."""
    records = [*RELEASES[1][1], ("P", "doc_e::1.0")]
    _write_inventory(history / "document" / _inventory_name("2.0"), records)
    label = history / "document" / "collection_document_v002.xml"
    label.write_text(_collection_label("2.0", _inventory_name("2.0"), len(records)), encoding="utf-8")
    assert _errors(_validate(history)[1]) == [("DLV-010", "error", _inventory_name("2.0"))]


def test_a_collection_version_no_bundle_version_lists_is_the_one_error(history):
    """Bundle 2.0 names collection 2.0 by LIDVID: version 3.0 is then in no release of the bundle."""
    (history / "bundle_release_history_v002.xml").write_text(
        _bundle_label("2.0", ("lidvid_reference", f"{COLLECTION}::2.0")), encoding="utf-8")
    assert _errors(_validate(history)[1]) == [("DLV-015", "error", "bundle_release_history_v002.xml")]
