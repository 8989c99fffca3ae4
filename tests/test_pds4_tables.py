"""PDS4 content checks on genuine cases of NASA's validator regression suite (copied with
provenance to tests/data/nasa_validate, see SOURCES.md there): pdsgen reaches NASA's
verdict on each failing case through the rule that owns the problem, and finds nothing
of the kind in the passing twin."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from pdsgen.validate import validate_paths
from pdsgen.validate.pds4.label_checks import validate_pds4
from pdsgen.validate.pds4.table_checks import PATTERNS, _split

from helpers import run_cli

CASES = Path(__file__).parent / "data" / "nasa_validate"
CONTENT = {"PDS4-050", "PDS4-051", "PDS4-052", "PDS4-053", "PDS4-055", "PDS4-056", "PDS4-057", "PDS4-058", "PDS4-062",
           "PDS4-060", "PDS4-061"}


def _content_errors(label: Path, labels_only: bool = False) -> list[tuple[str, str]]:
    """Content findings (schema findings aside: these labels use IM versions of all ages)."""
    return [(f.rule, f.message) for f in validate_pds4(label, labels_only=labels_only) if f.rule in CONTENT]


def test_character_table_read_with_the_wrong_delimiter():
    """292-7: the label says Line-Feed records of 59 bytes, the file has CR LF records of 60."""
    found = _content_errors(CASES / "github292/table_character/invalid/minimal_test_product_lf.xml")
    assert {rule for rule, _ in found} == {"PDS4-051", "PDS4-052"}
    assert any("does not end with the record delimiter" in m for _, m in found)
    assert _content_errors(CASES / "github292/table_character/valid/minimal_test_product_lf.xml") == []


def test_value_with_more_decimals_than_its_validation_format():
    """681-2: '.222' in a field whose validation_format is %4.2f."""
    found = _content_errors(CASES / "github681/ff_char_fail.xml")
    assert [rule for rule, _ in found] == ["PDS4-058"] and "'.222' has 3 decimals" in found[0][1]
    assert _content_errors(CASES / "github681/ff_char.xml") == []


def test_inventory_with_more_records_than_stated(tmp_path):
    """1234-1: the inventory states 6 records and holds 7; collection7 states 7."""
    found = _content_errors(CASES / "github1234/collection6.xml")
    assert [rule for rule, _ in found] == ["PDS4-051"] and "holds 7" in found[0][1]
    assert _content_errors(CASES / "github1234/collection7.xml") == []
    shutil.copytree(CASES / "github1234", tmp_path / "c")
    csv = tmp_path / "c" / "collection_document.csv"
    lines = csv.read_bytes().split(b"\r\n")
    csv.write_bytes(b"\r\n".join([lines[0], lines[0].replace(b"P,", b"X,"), *lines[2:]]))  # a twin, a bad status
    found = [m for rule, m in _content_errors(tmp_path / "c" / "collection7.xml") if rule == "PDS4-056"]
    assert len(found) == 2
    assert "record 2: member status 'X'" in found[0] and "record 2: urn:" in found[1] and "listed again" in found[1]


def test_objects_of_a_file_must_not_overlap():
    """480-3: a table whose offset falls inside the table before it (label only)."""
    found = _content_errors(CASES / "github480/test_fail_table_offset.xml", labels_only=True)
    assert [rule for rule, _ in found] == ["PDS4-057"] and "starts inside" in found[0][1]
    assert _content_errors(CASES / "github480/test_success.xml", labels_only=True) == []


def test_overlapping_bit_fields():
    """392-2: a bit field starting at bit 6 inside the one before it (bits 1-5 ... 8)."""
    found = _content_errors(CASES / "github392/test1_invalid.xml")
    assert [rule for rule, _ in found] == ["PDS4-050"] and "inside bit field" in found[0][1]
    assert _content_errors(CASES / "github392/test1_valid.xml") == []


def test_double_quote_inside_a_double_quoted_delimited_value():
    """298-2: 43 values such as "has ""double quote inside double quote"" and" (RFC 4180's
    escape, which PDS DSV 1 does not have): 43 errors, as NASA's 43 invalid_field_value;
    298-1, the same table without them, passes."""
    found = [m for rule, m in _content_errors(CASES / "github298/invalid/sentences.xml") if rule == "PDS4-055"]
    assert len(found) == 6 and sum(m.endswith("and 38 more like these") for m in found) == 1, found
    assert any("record 2, field sentence: a double-quoted value holds a double quote" in m for m in found)
    assert _content_errors(CASES / "github298/valid/sentences.xml") == []


def test_file_specification_names_in_an_aip_transfer_manifest(tmp_path):
    """299-2: the AIP's transfer manifest (inside Information_Package_Component) names
    _158.xml, 158.tab_ and _.tab: three errors, as NASA's three data_type mismatches (the
    Standards Reference's file names neither begin nor end with '_', '-' or '.')."""
    label = CASES / "github299/invalid/gbo_ast_fieber-beyer_spectra_v2.0_20210211_aip_v1.0.xml"
    found = [m for rule, m in _content_errors(label) if rule == "PDS4-052"]
    assert [m.split("'")[1].rsplit("/", 1)[1] for m in found] == ["_158.xml", "158.tab_", "_.tab"], found
    copy = Path(shutil.copytree(label.parent, tmp_path / "aip")) / label.name
    manifest = copy.with_name("gbo_ast_fieber-beyer_spectra_v2.0_20210211_transfer_manifest_v1.0.tab")
    data = manifest.read_bytes()
    for bad, good in ((b"/_158.xml", b"/a158.xml"), (b"/158.tab_", b"/158.tab1"), (b"/_.tab  ", b"/1.tab  ")):
        data = data.replace(bad, good)
    manifest.write_bytes(data)
    assert _content_errors(copy) == []


@pytest.mark.parametrize(("data_type", "good", "bad"), [
    ("ASCII_File_Name", ["a.txt", "A-1_b.2.IMG", "x.c"], ["_a.txt", "a.txt_", "README", "a b.txt", "a."]),
    ("ASCII_File_Specification_Name", ["data/a.xml", "/data/sub_1/a.xml", "a.xml"],
     ["data/_a.xml", "data_/a.xml", "/data//a.xml", "data/"]),
    ("ASCII_Directory_Path_Name", ["data", "data/sub-1/", "/a/b"], ["_data", "data-/x", "a//b"]),
])
def test_file_and_directory_name_types(data_type, good, bad):
    pattern = PATTERNS[data_type]
    assert all(pattern.match(v) for v in good), [v for v in good if not pattern.match(v)]
    assert not any(pattern.match(v) for v in bad), [v for v in bad if pattern.match(v)]


def test_bundle_member_named_twice():
    """467-1: the LIDVID document::1.0 listed twice, the LID document twice: two duplicates."""
    found = _content_errors(CASES / "github476/bundle_mars2020_spice_v003.xml", labels_only=True)
    assert [rule for rule, _ in found] == ["PDS4-056", "PDS4-056"]


def test_document_pdf_must_be_pdf_a():
    """164-1: a plain PDF in a document product; 164-2: a PDF/A."""
    found = _content_errors(CASES / "github164/invalid/document_test_1_pdf.xml")
    assert [rule for rule, _ in found] == ["PDS4-061"]
    assert _content_errors(CASES / "github164/valid/document_pdfa_valid.xml") == []


def test_two_labels_describing_one_file_in_a_run():
    """681-1: ff_char.xml and ff_del.xml both describe ff_test.csv: one error, on the second."""
    report = validate_paths([CASES / "github681/ff_char.xml", CASES / "github681/ff_del.xml"])
    shared = [f for f in report.findings if f.rule == "PDS4-060"]
    assert len(shared) == 1 and shared[0].file.endswith("ff_del.xml") and "ff_char.xml" in shared[0].message
    alone = validate_paths([CASES / "github681/ff_del.xml"])
    assert "PDS4-060" not in {f.rule for f in alone.findings}
    ignored = run_cli("validate", "--offline", "--ignore", "PDS4-060", "--format", "json",
                      CASES / "github681/ff_char.xml", CASES / "github681/ff_del.xml")
    assert '"PDS4-060"' not in ignored.stdout


def test_document_files_may_be_shared_by_two_labels(tmp_path):
    """905-1/905-2: two editions of one document (two Product_Document labels) name the same
    seven figures; NASA's validator passes them (it reports a shared file only when one of the
    labels describes it as observational data). Likewise three labels naming one PDF."""
    editions = sorted((CASES / "github905").glob("*.xml"))
    report = validate_paths(editions, labels_only=True)
    assert "PDS4-060" not in {f.rule for f in report.findings}, [f.message for f in report.findings]
    label = (CASES / "github164/valid/document_pdfa_valid.xml").read_text()
    shutil.copy(CASES / "github164/valid/test1_pdfa.pdf", tmp_path / "test1_pdfa.pdf")
    for name in "abc":
        (tmp_path / f"{name}.xml").write_text(label)
    report = validate_paths([tmp_path / "a.xml", tmp_path / "b.xml", tmp_path / "c.xml"], labels_only=True)
    assert "PDS4-060" not in {f.rule for f in report.findings}


def test_a_file_shared_with_a_label_of_observational_data_is_reported(tmp_path):
    """Whichever label comes first: a file one label describes as observational data (681's
    ff_test.csv, in ff_char.xml's File_Area_Observational) that a document label also names."""
    for name in ("ff_char.xml", "ff_test.csv"):
        shutil.copy(CASES / "github681" / name, tmp_path / name)
    document = (CASES / "github164/valid/document_pdfa_valid.xml").read_text()
    assert "<file_name>test1_pdfa.pdf</file_name>" in document
    (tmp_path / "doc.xml").write_text(document.replace("<file_name>test1_pdfa.pdf</file_name>",
                                                       "<file_name>ff_test.csv</file_name>"))
    for order in (["doc.xml", "ff_char.xml"], ["ff_char.xml", "doc.xml"]):
        report = validate_paths([tmp_path / name for name in order], labels_only=True)
        shared = [Path(f.file).name for f in report.findings if f.rule == "PDS4-060"]
        assert shared == [order[1]], (order, shared)


def test_a_baseline_keeps_back_findings_across_labels(tmp_path):
    """PDS4-060 is found across the run's labels, after each file's own report: a baseline that
    records it keeps it back on the next run, as it does every other finding."""
    pair = [CASES / "github681/ff_char.xml", CASES / "github681/ff_del.xml"]
    baseline = tmp_path / "baseline.json"
    written = run_cli("validate", "--offline", "--write-baseline", baseline, *pair)
    assert written.returncode == 0 and baseline.is_file(), written.stderr
    assert '"PDS4-060"' in baseline.read_text()
    again = run_cli("validate", "--offline", "--baseline", baseline, "--format", "json", *pair)
    assert '"PDS4-060"' not in again.stdout, again.stdout


@pytest.mark.parametrize(("data_type", "good", "bad"), [
    ("ASCII_Real", ["1", "-1.5", ".5", "1.e3", "6.02E+23", "NaN"], ["1,5", "e3", "1.2.3", "0x10"]),
    ("ASCII_Integer", ["0", "-12", "+7"], ["1.0", "1e3", "twelve"]),
    ("ASCII_NonNegative_Integer", ["0", "12"], ["-1"]),
    ("ASCII_Date_Time_YMD", ["2019-08-06T00:00:00Z", "2019-08-06", "2019-08-06T00:00:00.123"], ["2019-13"]),
    ("ASCII_Date_Time_DOY", ["2019-218T00:00:00Z", "2019"], ["2019-218T25"]),
    ("ASCII_LIDVID", ["urn:nasa:pds:b:c:p::1.0", "urn:esa:psa:b:c::2.10"], ["urn:nasa:pds:b:c:p", "urn:nasa"]),
    ("ASCII_Boolean", ["true", "0"], ["yes"]),
    ("ASCII_Numeric_Base16", ["FF7FFFFB"], ["0xFF"]),
])
def test_ascii_data_types(data_type, good, bad):
    pattern = PATTERNS[data_type]
    assert all(pattern.match(v) for v in good) and not any(pattern.match(v) for v in bad)


def test_delimited_fields_split_with_quotes():
    assert _split(b'a,"b,c", d', b",") == [b"a", b"b,c", b" d"]
    assert _split(b"1|2||", b"|") == [b"1", b"2", b"", b""]


def test_file_names_and_directory_paths():
    """153-1: a file_name with spaces; 349-2: an absolute directory_path_name (349-1: relative)."""
    found = _content_errors(CASES / "github153/3juno_lwr01896_ines_fits_headers.pdfa%.xml", labels_only=True)
    assert [rule for rule, _ in found] == ["PDS4-062"] and "' '" in found[0][1]
    found = _content_errors(CASES / "github349/invalid/datasetbad.xml", labels_only=True)
    assert [rule for rule, _ in found] == ["PDS4-062"] and "'/tmp/01/'" in found[0][1]
    assert _content_errors(CASES / "github349/valid/datasetgood.xml", labels_only=True) == []
