"""Include pointers (^STRUCTURE, ^..._CATALOG) resolved as a reader resolves them, walked once,
inside the trusted tree; files named by reference pointers that are missing (PTR-010).

Where a format file is looked for is the PDS3 rule NASA's PDS3 tools implement
(NASA-PDS/pds3-product-tools, StandardPathResolver: beside the label, else the volume's LABEL
folder for a structure pointer, CATALOG for a catalog pointer, DOCUMENT for ^DESCRIPTION);
the loops are NASA's own test labels (IncludePointerTest: circular1.lbl <-> circular2.lbl,
selfpointer.lbl; tests/data/corpus/pds3_product_tools) or volumes made here.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import sys
import time
from pathlib import Path

import pytest

from pdsgen.label import includes
from pdsgen.validate import validate_paths

# A name climbing from DATA/X/ to the volume's LABEL/ directory, all inside tmp_path.
UP_TWO = "/".join([os.pardir] * 2)
TABLE_LABEL = (b'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\n^TABLE = "A.TAB"\r\n'
               b'OBJECT = TABLE\r\n  ROWS = 1\r\n  ROW_BYTES = 4\r\n  COLUMNS = 1\r\n  INTERFACE_FORMAT = ASCII\r\n'
               b'  ^STRUCTURE = "%s"\r\nEND_OBJECT = TABLE\r\nEND\r\n')


def _format(includes_name: str) -> bytes:
    return (b'OBJECT = COLUMN\r\n  NAME = X\r\n  DATA_TYPE = ASCII_INTEGER\r\n  START_BYTE = 1\r\n  BYTES = 2\r\n'
            b'END_OBJECT = COLUMN\r\n^STRUCTURE = "%s"\r\n' % includes_name.encode())


def _volume(tmp_path, structure: str = "T.FMT"):
    """VOL/DATA/X/A.LBL (+ A.TAB) naming T.FMT, kept in VOL/LABEL/ with U.FMT; T includes U, U includes T."""
    volume = tmp_path / "VOL"
    data = volume / "DATA" / "X"
    data.mkdir(parents=True)
    (volume / "LABEL").mkdir()
    (data / "A.LBL").write_bytes(TABLE_LABEL % structure.encode())
    (data / "A.TAB").write_bytes(b"12\r\n")
    (volume / "LABEL" / "T.FMT").write_bytes(_format("U.FMT"))
    (volume / "LABEL" / "U.FMT").write_bytes(_format("T.FMT"))
    return volume, data / "A.LBL"


def _hits(report, rule):
    return [f for f in report.findings if f.rule == rule]


@pytest.mark.parametrize("labels_only", [False, True])
def test_nasa_circular_includes_are_reported_with_labels_only_too(corpus_dir, tmp_path, labels_only):
    for name in ("circular1.lbl", "circular2.lbl", "selfpointer.lbl", "valid.lbl"):
        shutil.copy(corpus_dir / "pds3_product_tools" / name, tmp_path / name)
    report = validate_paths([tmp_path / "circular1.lbl", tmp_path / "selfpointer.lbl"], labels_only=labels_only)
    loops = {f.message for f in _hits(report, "PTR-007")}
    assert loops == {"^STRUCTURE include loop: circular1.lbl -> circular2.lbl -> circular1.lbl",
                     "^STRUCTURE include loop: selfpointer.lbl -> selfpointer.lbl"}
    assert all(f.severity == "error" and f.line == 3 for f in _hits(report, "PTR-007"))


def test_format_files_are_found_in_the_volume_label_directory(tmp_path):
    volume, label = _volume(tmp_path)
    report = validate_paths([volume])
    [loop] = _hits(report, "PTR-007")
    assert loop.message == "^STRUCTURE include loop: A.LBL -> T.FMT -> U.FMT -> T.FMT" and loop.line == 9
    assert _hits(report, "PTR-010") == []


def test_a_relative_path_to_the_label_directory_is_followed(tmp_path):
    volume, label = _volume(tmp_path, f"{UP_TWO}/LABEL/T.FMT")
    assert [f.message for f in _hits(validate_paths([volume]), "PTR-007")] == [
        "^STRUCTURE include loop: A.LBL -> T.FMT -> U.FMT -> T.FMT"]


def test_outside_the_trusted_tree_nothing_is_followed(tmp_path):
    """The label given alone: its tree is its own directory, so the volume's LABEL/ is not
    searched; the format file is reported missing (a warning under --labels-only), no loop."""
    volume, label = _volume(tmp_path)
    report = validate_paths([label], labels_only=True)
    assert _hits(report, "PTR-007") == []
    [missing] = _hits(report, "PTR-010")
    assert missing.severity == "warning" and "T.FMT" in missing.message
    relative = _volume(tmp_path / "b", f"{UP_TWO}/LABEL/T.FMT")[1]
    report = validate_paths([relative])
    assert _hits(report, "PTR-007") == [] and [f.rule for f in _hits(report, "PTR-009")] == ["PTR-009"]


def test_each_included_file_is_read_once(tmp_path, monkeypatch):
    """Fifteen format files, each including the next four times: 4^14 paths, 15 reads."""
    for n in range(15):
        text = b"".join(b'^STRUCTURE = "F%d.FMT"\r\n' % (n + 1) for _ in range(4))
        (tmp_path / f"F{n}.FMT").write_bytes(text)
    (tmp_path / "F14.FMT").write_bytes(b'^STRUCTURE = "F0.FMT"\r\n')  # and a loop at the bottom
    label = tmp_path / "A.LBL"
    label.write_bytes(b'PDS_VERSION_ID = PDS3\r\n^STRUCTURE = "F0.FMT"\r\nEND\r\n')
    reads: list[str] = []
    real = includes.LabelFile.read

    def counted(path):
        if str(path).endswith(".FMT"):
            reads.append(str(path))
        return real(path)

    monkeypatch.setattr(includes.LabelFile, "read", staticmethod(counted))
    started = time.monotonic()
    report = validate_paths([label], labels_only=True)
    assert time.monotonic() - started < 10
    assert len(reads) == len(set(reads)) == 15
    assert [f.message.split(": ")[0] for f in _hits(report, "PTR-007")] == ["^STRUCTURE include loop"]


def test_a_missing_format_file_is_an_error_in_a_volume_given_whole(tmp_path):
    """The table's format file is not there: no reader can read its columns. An error in a volume
    given whole (VOLDESC.CAT), a warning for the product checked without its volume."""
    volume = tmp_path / "VOL"
    (volume / "DATA").mkdir(parents=True)
    label = volume / "DATA" / "A.LBL"
    label.write_bytes(TABLE_LABEL % b"T.FMT")
    (volume / "DATA" / "A.TAB").write_bytes(b"12\r\n")
    [alone] = _hits(validate_paths([label]), "PTR-010")
    assert (alone.severity, alone.line, alone.keyword) == ("warning", 9, "^STRUCTURE")
    assert alone.message.endswith("which is not beside the label or in a LABEL directory of its volume")
    (volume / "VOLDESC.CAT").write_bytes(b"PDS_VERSION_ID = PDS3\r\nEND\r\n")
    [whole] = [f for f in _hits(validate_paths([volume]), "PTR-010") if f.file == str(label)]
    assert whole.severity == "error"


def test_a_missing_description_is_a_warning(tmp_path):
    """^DESCRIPTION = "JP2INFO.TXT" not there (a migrated orthoimage without it): a warning; found
    beside the label or in the volume's DOCUMENT/ directory, nothing."""
    volume = tmp_path / "VOL"
    data = volume / "DATA" / "X"
    data.mkdir(parents=True)
    label = data / "A.LBL"
    label.write_bytes(b'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\n^TABLE = "A.TAB"\r\n'
                      b'^DESCRIPTION = "JP2INFO.TXT"\r\n^DATA_SET_MAP_PROJECTION = "DSMAP.CAT"\r\n'
                      b'OBJECT = TABLE\r\n  ROWS = 1\r\n  ROW_BYTES = 4\r\n'
                      b'  COLUMNS = 0\r\n  INTERFACE_FORMAT = ASCII\r\nEND_OBJECT = TABLE\r\nEND\r\n')
    (data / "A.TAB").write_bytes(b"12\r\n")
    [alone] = _hits(validate_paths([label]), "PTR-010")  # DSMAP.CAT: kept in the volume's CATALOG/
    assert (alone.severity, alone.line, alone.keyword) == ("warning", 4, "^DESCRIPTION")
    (volume / "VOLDESC.CAT").write_bytes(b"PDS_VERSION_ID = PDS3\r\nEND\r\n")
    found = {f.keyword: f.severity for f in _hits(validate_paths([volume]), "PTR-010") if f.file == str(label)}
    assert found == {"^DESCRIPTION": "warning", "^DATA_SET_MAP_PROJECTION": "info"}  # no CATALOG/ at all
    (volume / "CATALOG").mkdir()
    found = {f.keyword: f.severity for f in _hits(validate_paths([volume]), "PTR-010") if f.file == str(label)}
    assert found == {"^DESCRIPTION": "warning", "^DATA_SET_MAP_PROJECTION": "warning"}  # CATALOG/ without it
    (data / "JP2INFO.TXT").write_text("about the JP2 files\r\n")
    (volume / "CATALOG" / "DSMAP.CAT").write_bytes(b"PDS_VERSION_ID = PDS3\r\nEND\r\n")
    assert _hits(validate_paths([volume]), "PTR-010") == []
    (data / "JP2INFO.TXT").unlink()
    (volume / "DOCUMENT").mkdir()
    (volume / "DOCUMENT" / "JP2INFO.TXT").write_text("about the JP2 files\r\n")
    assert _hits(validate_paths([volume]), "PTR-010") == []


def test_nasa_include_pointer_cases_agree_in_the_parity_bench(corpus_dir, tmp_path):
    """bench/pds3_parity.py on NASA's IncludePointerTest labels and the include of
    ElementValidatorTest.testUnknownValueWInclude: every case agrees (the loops reported,
    problems of an included file not reported on the including label)."""
    root = Path(__file__).resolve().parents[1]
    spec = importlib.util.spec_from_file_location("pds3_parity_includes", root / "bench" / "pds3_parity.py")
    assert spec is not None and spec.loader is not None
    bench = importlib.util.module_from_spec(spec)
    sys.modules["pds3_parity_includes"] = bench
    spec.loader.exec_module(bench)
    labels = tmp_path / "src" / "test-data" / "labels"
    labels.mkdir(parents=True)
    names = ("circular1.lbl", "circular2.lbl", "selfpointer.lbl", "valid.lbl", "parent.lbl", "child.lbl",
             "newValueWInclude.lbl", "includeForNV.lbl")
    for name in names:
        shutil.copy(corpus_dir / "pds3_product_tools" / name, labels / name)
    shutil.copy(corpus_dir / "reference" / "testdd.full", labels.parent / "testdd.full")
    shutil.copy(Path(__file__).parent / "data" / "pds3_product_tools" / "pdsdd_excerpt.full",
                labels.parent / "pdsdd.full")
    _, cases = bench.read_cases()
    chosen = [c for c in cases if c.label in names]
    assert {c.id.split(".")[0] for c in chosen} >= {"IncludePointerTest"} and len(chosen) >= 4
    outcomes, lines, _ = bench.run_all(tmp_path, chosen)
    assert [(o.case.id, o.status) for o in outcomes if o.status != "agree"] == []


def test_a_named_structure_pointer_is_an_include(tmp_path):
    """^TABLE_STRUCTURE (a pointer ending in _STRUCTURE, an include by NASA's rule) is followed."""
    (tmp_path / "A.LBL").write_bytes(b'PDS_VERSION_ID = PDS3\r\n^TABLE_STRUCTURE = "T.FMT"\r\nEND\r\n')
    (tmp_path / "T.FMT").write_bytes(b'^STRUCTURE = "A.LBL"\r\n')
    assert [f.message for f in _hits(validate_paths([tmp_path / "A.LBL"], labels_only=True), "PTR-007")] == [
        "^TABLE_STRUCTURE include loop: A.LBL -> T.FMT -> A.LBL"]


def test_labels_only_leaves_out_a_missing_document_but_not_a_missing_format_file(tmp_path):
    """--labels-only (a repository of labels, its data and documents elsewhere): a ^DESCRIPTION
    file that is not there is not reported; a ^STRUCTURE file is a label and still is."""
    label = tmp_path / "A.LBL"
    label.write_bytes(b'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\n^TABLE = "A.TAB"\r\n'
                      b'^DESCRIPTION = "JP2INFO.TXT"\r\n'
                      b'OBJECT = TABLE\r\n  ROWS = 1\r\n  ROW_BYTES = 4\r\n  COLUMNS = 1\r\n'
                      b'  INTERFACE_FORMAT = ASCII\r\n  ^STRUCTURE = "T.FMT"\r\nEND_OBJECT = TABLE\r\nEND\r\n')
    found = {f.keyword for f in _hits(validate_paths([label], labels_only=True), "PTR-010")}
    assert found == {"^STRUCTURE"}
    found = {f.keyword for f in _hits(validate_paths([label]), "PTR-010")}
    assert found == {"^STRUCTURE", "^DESCRIPTION"}
