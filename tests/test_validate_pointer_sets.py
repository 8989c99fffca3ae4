"""A pointer may name several files: a set (or sequence) of file names, as the Galileo Probe
archive's software labels do (^ASCII_DOCUMENT = {"NFREDR4.H", "NFREDR41.C"}); NASA's PDS3
label tools read it as one reference to each file. It is not an attached object either."""

from __future__ import annotations

import pvl
import pytest

from pdsgen.validate import validate_paths

LABEL = """PDS_VERSION_ID = PDS3\r
RECORD_TYPE = STREAM\r
^ASCII_DOCUMENT = {value}\r
OBJECT = ASCII_DOCUMENT\r
  DOCUMENT_NAME = "NFR EDR READER"\r
  DOCUMENT_FORMAT = TEXT\r
  PUBLICATION_DATE = 1998-01-01\r
  INTERCHANGE_FORMAT = ASCII\r
END_OBJECT = ASCII_DOCUMENT\r
END\r
"""


@pytest.mark.parametrize("value", ['{"NFREDR4.H", "NFREDR41.C"}', '("NFREDR4.H", "NFREDR41.C")'])
def test_a_pointer_to_several_files_is_a_pds3_pointer(tmp_path, value):
    path = tmp_path / "NFREDR.LBL"
    path.write_text(LABEL.format(value=value), newline="")
    for name in ("NFREDR4.H", "NFREDR41.C"):
        (tmp_path / name).write_text("/* reader */\r\n", newline="")
    assert set(pvl.load(str(path))["^ASCII_DOCUMENT"]) == {"NFREDR4.H", "NFREDR41.C"}
    rules = {f.rule: f for f in validate_paths([path]).findings}
    assert "PTR-001" not in rules, rules
    # no attached object: nothing read after the label, no label-only copy reported
    assert not {"PTR-008", "PTR-004", "FILE-003"} & set(rules), rules


def test_a_pointer_set_with_a_number_is_still_refused(tmp_path):
    path = tmp_path / "BAD.LBL"
    path.write_text(LABEL.format(value='{"NFREDR4.H", 12}'), newline="")
    found = [f for f in validate_paths([path]).findings if f.rule == "PTR-001"]
    assert found and found[0].severity == "error"


@pytest.mark.parametrize("value", ['{"NFREDR4.H", "NFREDR41.C"}', '("NFREDR4.H", "NFREDR41.C")'])
def test_each_file_of_a_pointer_set_must_exist_with_its_case(tmp_path, value):
    path = tmp_path / "NFREDR.LBL"
    path.write_text(LABEL.format(value=value), newline="")
    (tmp_path / "NFREDR4.H").write_text("/* reader */\r\n", newline="")
    missing = [f for f in validate_paths([path]).findings if f.rule == "PTR-002"]
    assert [(f.severity, "NFREDR41.C" in f.message) for f in missing] == [("error", True)]
    (tmp_path / "nfredr41.c").write_text("/* reader */\r\n", newline="")
    rules = {f.rule: f for f in validate_paths([path]).findings}
    assert "PTR-002" not in rules and "nfredr41.c" in rules["PTR-003"].message
