"""The validator on archive labels it did not write: tests/data/corpus (copies of public files; SOURCES.md there).

real/ holds genuine mission labels cut at END (no data), so it is checked label-only.
Every error that remains there from the FILE/SYNTAX/PTR/REC/MAP families is listed
below with the defect it is; the test fails if one disappears or a new one appears.
"""

from __future__ import annotations

from collections import defaultdict

import pytest

from pdsgen.validate import validate_paths

STRICT_FAMILIES = ("FILE", "SYNTAX", "PTR", "REC", "MAP")

# (file, rule) -> the real defect behind each remaining error on real/ labels
KNOWN_DEFECTS = {
    ("DTEEC_008669_1705_009025_1705_A01__gdal_pds_3177.lbl", "REC-005"):
        "GDAL's test puts a 15 x 20 image at byte 3 of a 300-byte file (RECORD_BYTES 15 x "
        "FILE_RECORDS 20): the image ends 2 bytes past the declared records",
    ("DTEEC_008669_1705_009025_1705_A01__gdal_pds_3177.lbl", "MAP-008"):
        "LINE/SAMPLE_LAST_PIXEL 26376/8211 are the real DTM's, the test IMAGE is 20 x 15",
    ("DTEEC_008669_1705_009025_1705_A01__gdal_pds_3177.lbl", "MAP-002"):
        "A_AXIS_RADIUS 3396.036 km but MAP_RESOLUTION implies 3396.19 km (the HiRISE "
        "inconsistency the project notes describe)",
    ("DTEEC_008669_1705_009025_1705_A01__gdal_pds_3177.lbl", "MAP-003"):
        "the HiRISE DTM's bounds are 23 px (latitude) and ~23300 px (longitude) from the raster "
        "its offsets and 3396.036 km radius define",
    ("EN1072174528M.lbl", "REC-003"):
        "label text (7945 bytes) does not fit LABEL_RECORDS 7 x 1024: this copy is not the "
        "attached label of the file its pointers describe",
    ("EN1072174528M.lbl", "PTR-004"): "^IMAGE = record 8 (byte 7169) lies inside the 7945-byte label",
    ("H6541_0000_IR4_cropped.img.lbl", "PTR-004"):
        "ISIS re-serialised the cropped label: ^IMAGE = 5594 <BYTES> points inside the label text",
    ("H6541_0000_IR4_cropped.img.lbl", "REC-003"):
        "LABEL_RECORDS 7 x 1708 bytes end at byte 11956 but ^IMAGE says 5594",
    ("H6541_0000_IR4_cropped.img.lbl", "MAP-008"):
        "cropped to 1 line but LINE_LAST_PIXEL is still the original 5126",
    ("H6541_0000_IR4_cropped.img.lbl", "MAP-003"):
        "bounds (MINIMUM_LATITUDE -90, longitudes 0..360) are copied from the input cube, "
        "tens of thousands of pixels from the raster",
    ("H6541_0000_IR4_cropped.img.lbl", "FILE-002"): "the last line (End) ends in LF, the rest in CR LF",
    ("LDEM_4_cropped.img.lbl", "MAP-008"): "cropped to 1 line but LINE_LAST_PIXEL is still 720",
    ("LDEM_4_cropped.img.lbl", "PTR-004"): "^IMAGE = byte 2904 lies inside the 2924-byte label",
    ("LDEM_4_cropped.img.lbl", "FILE-002"): "the last line ends in LF, the rest in CR LF",
    ("MC02_truncated.img.lbl", "MAP-003"):
        "truncated to 1 line with MINIMUM_LATITUDE still 30 (2239.5 px), and MOC's offsets are "
        "lat*res / lon*res, half a pixel from the PDS3 standard (corner convention)",
    ("T1865_MRRDE_70N185_0256_1_cropped.lbl", "REC-005"):
        "cropped to 10 lines (39200 bytes) but FILE_RECORDS still 9 (35280 bytes)",
    ("T1865_MRRDE_70N185_0256_1_cropped.lbl", "MAP-008"): "cropped to 10 lines, LINE_LAST_PIXEL still 1280",
    ("T1865_MRRDE_70N185_0256_1_cropped.lbl", "MAP-003"):
        "CRISM's SAMPLE_PROJECTION_OFFSET is longitude x MAP_RESOLUTION without the cos(standard "
        "parallel) of equirectangular x (6031 px), plus the corner convention (0.5 px)",
}


def _errors_by_file(report, families=STRICT_FAMILIES) -> dict[str, set[str]]:
    found: dict[str, set[str]] = defaultdict(set)
    for f in report.findings:
        if f.severity == "error" and f.rule.split("-")[0] in families:
            found[f.file.rsplit("/", 1)[-1]].add(f.rule)
    return found


def test_real_labels_only_named_defects(corpus_dir):
    report = validate_paths([corpus_dir / "real"], labels_only=True)
    assert len(report.files) == 17
    found = {(name, rule) for name, rules in _errors_by_file(report).items() for rule in rules}
    assert found == set(KNOWN_DEFECTS), (found - set(KNOWN_DEFECTS), set(KNOWN_DEFECTS) - found)
    # LINES edited in these copies (B10: to 400 while FILE_RECORDS counts 24576 image lines; the
    # LROC NAC EDR M103595705LE: 400 of 52224): with the labels only, REC-008 cannot know whether
    # the file has the records, so it warns and says so
    edited = {f.file.rsplit("/", 1)[-1] for f in report.findings if f.rule == "REC-008"
              and f.severity == "warning" and "could not be looked at (--labels-only)" in f.message}
    assert {"B10_013341_1010_XN_79S172W.lbl", "M103595705LE.lbl"} <= edited
    # nothing failed inside a check (a crash would be reported as "could not run")
    assert not [f for f in report.findings if "could not run" in f.message]


def test_real_labels_conventions_detected(corpus_dir):
    report = validate_paths([corpus_dir / "real"], labels_only=True)
    by_rule = defaultdict(set)
    for f in report.findings:
        by_rule[f.rule].add(f.file.rsplit("/", 1)[-1])
    assert "MEGT90N000CB.LBL" in by_rule["MAP-005"]  # MOLA MEGDR: the older convention
    assert "ESP_013951_1955_RED.LBL" in by_rule["MAP-005"]  # HiRISE RDR likewise
    assert {"LDEM_4.LBL", "LDEM_4_cropped.img.lbl"} <= by_rule["MAP-004"]  # LOLA: standard


def test_real_directory_with_data_checks_does_not_crash(corpus_dir):
    report = validate_paths([corpus_dir / "real", corpus_dir / "products"], jobs=2)
    assert len(report.files) == 22
    assert not [f for f in report.findings if "could not run" in f.message]


def test_every_bad_file_gets_an_error(corpus_dir):
    report = validate_paths([corpus_dir / "bad"])
    assert len(report.files) == 16
    for file_report in report.files:
        assert file_report.count("error") >= 1, file_report.path


# file -> [(rule, line)] from EXPECTED.md, for the rules implemented here (line None: any)
EXPECTED = {
    "attachedPadded.lbl": [("FILE-005", 4), ("FILE-005", 5)],
    "attachedPaddedWWhite.lbl": [("FILE-005", 4), ("FILE-005", 5), ("PTR-006", 6)],
    "attachedPaddedInvalid.lbl": [("PTR-005", 6)],
    "attachedBlankFill.lbl": [("FILE-004", 3)],
    "attachedBlankFillInvalid.lbl": [("PTR-005", 6)],
    "attachedBlankFillWWhite.lbl": [("FILE-004", 3), ("PTR-006", 6)],
    "attachedBlankFillNoPointer.lbl": [("FILE-004", 3)],
    "attachedStream.lbl": [("FILE-004", 3)],
    "detachedStream.lbl": [("FILE-004", 3)],
    "detachedFixedNoRecordLength.lbl": [("REC-001", 2), ("FILE-004", 3)],
    "badLineEndings.img": [("FILE-002", 2), ("FILE-002", 9)],
    "emptyLabel.lbl": [("FILE-011", None)],
    "missingVersion.lbl": [("FILE-006", 1)],
    "SFDULabel.lbl": [("FILE-006", 1)],
    "missingEquals.lbl": [("SYNTAX-001", 2), ("SYNTAX-001", 4), ("SYNTAX-001", 6)],
    "missingKey.lbl": [("SYNTAX-001", 4)],
    "missingValue.lbl": [("SYNTAX-009", 2), ("SYNTAX-013", 4)],  # "" is a warning: archives have it
    "setValue.lbl": [("SYNTAX-001", 5), ("DICT-010", 4)],  # FILTER_NAME values are DYNAMIC
    "sequenceValue.lbl": [("DICT-002", 4)],
    "newValue.lbl": [("DICT-010", 3)],  # VOLUME_SET_NAME values are DYNAMIC: information
    "newValueWInclude.lbl": [("DICT-010", 3)],
    "invalidValue.lbl": [("DICT-004", 5)],
    "skipValue.lbl": [("DICT-008", None)],
    "unknownUnits.lbl": [("DICT-007", 7), ("DICT-007", 10)],
    "unknownDefinition.lbl": [("DICT-001", 4)],
    "numberExceedsMax.lbl": [("DICT-003", None)],
    "numberLessThanMin.lbl": [("DICT-003", None)],
    "shortValue.lbl": [("DICT-006", None)],
    "longValue.lbl": [("DICT-006", None)],
    "badCastValue.lbl": [("DICT-002", None)],
    "typeMismatch.lbl": [("DICT-009", None)],  # reported as information here: readers accept it
    "datetime.lbl": [("SYNTAX-008", n) for n in range(29, 41)] + [("DICT-002", 41), ("SYNTAX-008", 49)],
    "selfpointer.lbl": [("PTR-007", None)],
    "circular1.lbl": [("PTR-007", None)],
    "circular2.lbl": [("PTR-007", None)],
    "nonDecimal.lbl": [("SYNTAX-007", n) for n in (5, 6, 8, 9, 10, 11, 12, 13, 14, 17, 18, 19)],
}
# EXPECTED.md lists no problems of these kinds for these files
CLEAN = {
    "valid.lbl": ("FILE", "SYNTAX", "PTR", "REC", "DICT"),
    "attachedMultiplePointers.lbl": ("FILE", "SYNTAX", "PTR"),
    "probPastEnd.lbl": ("FILE", "SYNTAX"),
    "parent.lbl": ("FILE", "SYNTAX", "PTR"),  # includes child.lbl, whose long line is not its own
    "newValueWInclude.lbl": ("PTR",),
}


@pytest.fixture(scope="module")
def product_tools(corpus_dir):
    report = validate_paths([corpus_dir / "pds3_product_tools"])
    found = defaultdict(list)
    for f in report.findings:
        found[f.file.rsplit("/", 1)[-1]].append(f)
    return found


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_pds3_product_tools_expected(product_tools, name):
    got = {(f.rule, f.line) for f in product_tools[name]}
    rules = {f.rule for f in product_tools[name]}
    for rule, line in EXPECTED[name]:
        assert ((rule, line) in got) if line is not None else (rule in rules), (rule, line, sorted(got))


@pytest.mark.parametrize("name", sorted(CLEAN))
def test_pds3_product_tools_clean(product_tools, name):
    bad = [f"{f.rule} {f.line} {f.message}" for f in product_tools[name]
           if f.severity != "info" and f.rule.split("-")[0] in CLEAN[name]]
    assert bad == []


# Per-type checks of pds3-product-tools run against its test dictionary (testdd.full),
# given with --dictionary: TYPE_MISMATCH/INVALID_TYPE -> DICT-002, OOR -> DICT-003,
# SHORT_VALUE/EXCESSIVE_VALUE_LENGTH -> DICT-006.
TESTDD_EXPECTED = {
    "alphaNumeric.lbl": [("DICT-006", 3), ("DICT-006", 4), ("DICT-002", 6)],
    "alphabetic.lbl": [("DICT-006", 3), ("DICT-006", 4), ("DICT-002", 5), ("DICT-002", 6)],
    "double.lbl": [("DICT-002", 3), ("DICT-003", 6), ("DICT-003", 7)],
    "integer.lbl": [("DICT-002", 3), ("DICT-003", 4), ("DICT-003", 5), ("DICT-002", 6)],
    "real.lbl": [("DICT-002", 3), ("DICT-003", 4), ("DICT-003", 5)],
    "nonDecimal.lbl": [("DICT-002", 3), ("DICT-003", 15), ("DICT-003", 16)],
}


@pytest.mark.parametrize("name", sorted(TESTDD_EXPECTED))
def test_pds3_product_tools_with_their_test_dictionary(corpus_dir, name):
    report = validate_paths([corpus_dir / "pds3_product_tools" / name],
                            dictionaries=[corpus_dir / "reference" / "testdd.full"])
    got = {(f.rule, f.line) for f in report.findings}
    for expected in TESTDD_EXPECTED[name]:
        assert expected in got, (expected, sorted(got))


def test_labels_that_describe_no_data(corpus_dir, product_tools):
    """SET-005 on the corpus: valid.lbl (PDS_VERSION_ID and END only) alone describes nothing;
    in its directory circular1.lbl includes it (^STRUCTURE), as parent.lbl includes child.lbl,
    so both are fragments there. Real mission labels all describe their data."""
    alone = validate_paths([corpus_dir / "pds3_product_tools" / "valid.lbl"])
    assert [(f.rule, f.severity, f.line) for f in alone.findings] == [("SET-005", "warning", 1)]
    flagged = {name for name, findings in product_tools.items() if any(f.rule == "SET-005" for f in findings)}
    assert "attachedBlankFillNoPointer.lbl" in flagged  # attached data, but nothing describes them
    assert not flagged & {"valid.lbl", "child.lbl", "includeForNV.lbl", "ITEMS.LBL", "parent.lbl",
                          "attachedPadded.lbl", "probPastEnd.lbl"}
    real = validate_paths([corpus_dir / "real", corpus_dir / "products"], labels_only=True)
    assert "SET-005" not in real.rule_ids()
