"""References that leave the directory checked, with the severities of NASA's validator.

NASA-PDS/validate (ReferentialIntegrityUtil, BundleReferentialIntegrityRule,
CollectionReferentialIntegrityRule @ df054fd) reports a LID/LIDVID reference to a product
of the bundle that is not in the target as a warning (reference_not_found): the product
may be delivered apart. A primary member of a bundle or collection that is not there is an
error (member_not_found); a secondary member is another collection's and is not looked for.

The bundle is suite case 482's bundle2 (copied with provenance to tests/data/nasa_validate):
NASA finds 3 unresolved references and no error (482-4).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from pdsgen.validate import validate_paths

BUNDLE = Path(__file__).parent / "data" / "nasa_validate" / "github482" / "bundle2"
MEMBER = "<lidvid_reference>urn:nasa:pds:kaguya_grs_spectra:data_spectra::1.0</lidvid_reference>"


@pytest.fixture
def bundle(tmp_path: Path) -> Path:
    return Path(shutil.copytree(BUNDLE, tmp_path / "bundle2"))


def _dlv(path: Path) -> list[tuple[str, str, str]]:
    report = validate_paths([path], labels_only=True)
    return sorted((f.rule, f.severity, Path(f.file).name) for f in report.findings if f.rule.startswith("DLV"))


def test_references_to_documents_delivered_apart_are_warnings(bundle):
    """482-4: the bundle's and a product's Reference_List name two documents of the bundle
    that are not in the directory: three warnings, as NASA's three reference_not_found."""
    assert _dlv(bundle) == [("DLV-014", "warning", "bundle_kaguya_derived.xml")] * 2 + [
        ("DLV-014", "warning", "kgrs_calibrated_spectra_per1.xml")]


def _seed(path: Path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8")
    assert old in text
    path.write_text(text.replace(old, new), encoding="utf-8")


def test_a_missing_primary_member_is_an_error_a_secondary_one_is_not_looked_for(bundle):
    label = bundle / "bundle_kaguya_derived.xml"
    _seed(label, MEMBER, MEMBER.replace("data_spectra::1.0", "data_raw::1.0"))
    errors = [f for f in _dlv(bundle) if f[1] == "error"]
    # the collection present is no longer listed, and the one listed is absent
    assert errors == [("DLV-015", "error", "bundle_kaguya_derived.xml")] * 2
    _seed(label, "<member_status>Primary</member_status>", "<member_status>Secondary</member_status>")
    assert [f for f in _dlv(bundle) if f[1] == "error"] == [("DLV-015", "error", "bundle_kaguya_derived.xml")]


def test_inventory_primary_members_must_be_present_secondary_ones_need_not(bundle):
    inventory = bundle / "data_spectra" / "spectra_data_collection_inventory.csv"
    first = inventory.read_bytes()
    elsewhere = "urn:nasa:pds:other_bundle:data:product_1::1.0"
    inventory.write_bytes(first + f"S,{elsewhere}\r\n".encode())
    assert not [f for f in _dlv(bundle) if f[1] == "error"]
    inventory.write_bytes(first + b"P,urn:nasa:pds:kaguya_grs_spectra:data_spectra:per9::1.0\r\n")
    assert [f for f in _dlv(bundle) if f[1] == "error"] == [
        ("DLV-010", "error", "spectra_data_collection_inventory.csv")]


def test_a_primary_member_without_version_is_an_error(bundle):
    """230-1: primary members named by LID alone (error.integrity.missing_version for NASA)."""
    inventory = bundle / "data_spectra" / "spectra_data_collection_inventory.csv"
    inventory.write_bytes(inventory.read_bytes().replace(b"_per1::1.0", b"_per1"))
    errors = [f for f in validate_paths([bundle], labels_only=True).findings if f.severity == "error"]
    assert [(f.rule, "has no version" in f.message) for f in errors] == [("DLV-010", True)], errors
