"""`pdsgen validate` as CI uses it: exit codes, JSON and JUnit read back, rule list, jobs."""

from __future__ import annotations

import json
import os
import threading

import pytest
from affine import Affine
from click.testing import CliRunner
from lxml import etree

from pdsgen.cli import main
from pdsgen.errors import PdsgenError
from pdsgen.validate import discover, rules, validate_paths
from test_validate_support import make_dtm, replace_in_label

from helpers import elevation_array, write_raster


def _run(*args: str):
    return CliRunner().invoke(main, ["validate", *map(str, args)])


def _broken_copy(tmp_path, clean):
    broken = tmp_path / "broken" / "BROKEN.IMG"
    broken.parent.mkdir()
    broken.write_bytes(clean.read_bytes())
    replace_in_label(broken, b"  OFFSET           =", b"  SCALING_FACTOR   =")
    return broken


def test_exit_codes(tmp_path):
    clean = make_dtm(tmp_path)
    assert _run(clean).exit_code == 0
    assert _run(_broken_copy(tmp_path, clean)).exit_code == 1
    missing = _run(tmp_path / "missing.lbl")
    assert missing.exit_code == 2
    expected = f"pdsgen: error: {tmp_path / 'missing.lbl'}: no such file or directory"
    assert missing.output.strip().splitlines() == [expected]
    assert _run().exit_code == 2
    assert _run("--format", "xml", clean).exit_code == 2


def test_strict_fails_on_warnings(tmp_path):
    label = tmp_path / "LF.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\nEND\n")  # LF-only detached label: a warning
    result = _run(label)
    assert result.exit_code == 0 and "[FILE-003]" in result.output
    assert _run("--strict", label).exit_code == 1


def test_json_report_reads_back(tmp_path):
    clean = make_dtm(tmp_path)
    broken = _broken_copy(tmp_path, clean)
    result = _run("--format", "json", clean, broken)
    data = json.loads(result.output)
    assert result.exit_code == 1
    assert [f["path"] for f in data["files"]] == [str(clean), str(broken)]
    assert data["files"][0]["passed"] is True and data["files"][1]["passed"] is False
    finding = next(f for f in data["files"][1]["findings"] if f["rule"] == "SYNTAX-004")
    assert finding["severity"] == "error" and finding["keyword"] == "SCALING_FACTOR"
    assert isinstance(finding["line"], int) and finding["message"]
    assert data["summary"]["files"] == 2 and data["summary"]["errors"] >= 1
    assert data["summary"]["exit_code"] == 1


def test_junit_report_reads_back(tmp_path):
    clean = make_dtm(tmp_path)
    broken = _broken_copy(tmp_path, clean)
    out = tmp_path / "report.xml"
    result = _run("--format", "junit", "--output", out, clean, broken)
    assert result.exit_code == 1
    root = etree.parse(str(out)).getroot()
    suite = root.find("testsuite")
    assert suite.get("tests") == "2" and suite.get("failures") == "1"
    cases = {c.get("name"): c for c in suite.findall("testcase")}
    assert cases[str(clean)].find("failure") is None
    failure = cases[str(broken)].find("failure")
    assert failure is not None and "SYNTAX-004" in failure.text


def test_list_rules_prints_every_rule():
    result = CliRunner().invoke(main, ["validate", "--list-rules"])
    assert result.exit_code == 0
    for rule_id, rule in rules().items():
        assert rule_id in result.output
        assert rule.severity in ("error", "warning", "info")
    families = {rule_id.split("-")[0] for rule_id in rules()}
    assert families == {"FILE", "SYNTAX", "DICT", "PTR", "REC", "IMG", "MAP", "GEO", "HRSC", "SET", "IMARS", "PDS4",
                        "IDN", "DLV"}


def test_jobs_give_the_same_report(tmp_path):
    for i in range(4):
        make_dtm(tmp_path, ["equirectangular", "polar", "sinusoidal", "polar"][i], name=f"d{i}")
    one = json.loads(_run("--format", "json", tmp_path).output)
    two = json.loads(_run("--format", "json", "--jobs", "2", tmp_path).output)
    assert one == two and one["summary"]["files"] == 4


def test_directory_search_skips_data_files(tmp_path):
    clean = make_dtm(tmp_path)
    (clean.parent / "notes.txt").write_text("not a label")
    (clean.parent / "raw.img").write_bytes(b"\x00" * 64)
    data = json.loads(_run("--format", "json", clean.parent).output)
    assert [f["path"] for f in data["files"]] == [str(clean)]
    again = json.loads(_run("--format", "json", clean.parent, clean).output)
    assert [f["path"] for f in again["files"]] == [str(clean)]


def test_garbage_never_tracebacks(tmp_path):
    cases = {
        "binary.lbl": bytes(range(256)) * 4,
        "quote.lbl": b'PDS_VERSION_ID = PDS3\r\nA = "never closed\r\n',
        "nested.lbl": b"PDS_VERSION_ID = PDS3\r\nA = ((((((1\r\nEND\r\n",
        "pointer.lbl": b"PDS_VERSION_ID = PDS3\r\n^IMAGE = (1, 2, 3)\r\nOBJECT = IMAGE\r\nLINES = -5\r\n"
                       b"LINE_SAMPLES = x\r\nSAMPLE_TYPE = PC_REAL\r\nSAMPLE_BITS = 7\r\nEND\r\n",
        "map.lbl": b"PDS_VERSION_ID = PDS3\r\nOBJECT = IMAGE_MAP_PROJECTION\r\nMAP_PROJECTION_TYPE = "
                   b"SINUSOIDAL\r\nA_AXIS_RADIUS = 0\r\nMAP_SCALE = 0\r\nEND_OBJECT\r\nEND\r\n",
        "empty.lbl": b"",
    }
    for name, content in cases.items():
        (tmp_path / name).write_bytes(content)
    result = _run("--format", "json", tmp_path)
    assert result.exception is None or isinstance(result.exception, SystemExit)
    data = json.loads(result.output)
    assert data["summary"]["files"] == len(cases)
    assert all(not f["passed"] for f in data["files"])
    assert not any("could not run" in g["message"] for f in data["files"] for g in f["findings"])


def test_extra_dictionary_option(tmp_path):
    label = tmp_path / "X.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nMY_COUNT = 12\r\nEND\r\n")
    assert "[DICT-001]" in _run(label).output
    dictionary = tmp_path / "local.full"
    dictionary.write_text("OBJECT = ELEMENT_DEFINITION\n  NAME = MY_COUNT\n  GENERAL_DATA_TYPE = INTEGER\n"
                          "  UNIT_ID = NONE\n  STANDARD_VALUE_TYPE = RANGE\n  MAXIMUM = 10\n"
                          "END_OBJECT = ELEMENT_DEFINITION\n")
    result = _run("--dictionary", dictionary, label)
    assert "[DICT-001]" not in result.output and "[DICT-003]" in result.output
    assert _run("--dictionary", tmp_path / "none.full", label).exit_code == 2


def _usage_error_line(result) -> str:
    """The one stderr line of a usage error (exit 2, nothing on stdout)."""
    assert result.exit_code == 2, result.output
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    return lines[0]


def test_no_labels_found_is_a_usage_error(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    others = tmp_path / "others"
    (others / "sub").mkdir(parents=True)
    (others / "notes.txt").write_text("not a label")
    (others / "sub" / "raw.img").write_bytes(b"\x00" * 64)
    for where in (empty, others):
        for fmt in ("text", "json", "junit"):
            line = _usage_error_line(_run("--format", fmt, where))
            assert line == f"pdsgen: error: no PDS3 or PDS4 label found under {where}"
    both = _usage_error_line(_run(empty, others))
    assert both == f"pdsgen: error: no PDS3 or PDS4 label found under {empty}, {others}"
    # one label anywhere among the paths: the others are simply searched
    make_dtm(others)
    data = json.loads(_run("--format", "json", empty, others).output)
    assert data["summary"]["files"] == 1 and data["summary"]["exit_code"] == 0


def test_no_labels_found_from_python(tmp_path):
    with pytest.raises(PdsgenError, match="no PDS3 or PDS4 label found under"):
        validate_paths([tmp_path])


def test_a_device_is_not_a_label_file(tmp_path):
    line = _usage_error_line(_run("/dev/null"))
    assert line == "pdsgen: error: /dev/null: not a regular file (a character device)"
    fifo = tmp_path / "pipe.lbl"
    os.mkfifo(fifo)
    line = _usage_error_line(_run(fifo))
    assert line == f"pdsgen: error: {fifo}: not a regular file (a FIFO)"


def test_directory_search_skips_special_files(tmp_path):
    """A FIFO inside a searched directory is skipped, never opened (opening one waits forever)."""
    clean = make_dtm(tmp_path)
    os.mkfifo(clean.parent / "pipe.lbl")
    os.mkfifo(clean.parent / "pipe.img")
    found: list = []
    worker = threading.Thread(target=lambda: found.append(discover([clean.parent])), daemon=True)
    worker.start()
    worker.join(timeout=10)
    assert not worker.is_alive(), "discover() blocked on a FIFO"
    assert found == [[clean]]


def test_dictionary_that_is_not_a_psdd_file_is_refused(tmp_path):
    label = tmp_path / "X.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nMY_COUNT = 12\r\nEND\r\n")
    tiff = write_raster(tmp_path / "dem.tif", elevation_array(8, 8), None, Affine.identity())
    empty = tmp_path / "empty.full"
    empty.write_bytes(b"")
    label_as_dictionary = label  # a PDS3 label parses, but defines no elements or units
    for bad in (tiff, empty, label_as_dictionary):
        for fmt in ("text", "json"):
            line = _usage_error_line(_run("--format", fmt, "--dictionary", bad, label))
            assert line == (f"pdsgen: error: {bad}: not a PSDD data dictionary "
                            "(no ELEMENT_DEFINITION or UNIT_LIST object)")
        with pytest.raises(PdsgenError, match="not a PSDD data dictionary"):
            validate_paths([label], dictionaries=[bad])
    unreadable = tmp_path / "locked.full"
    unreadable.write_text("OBJECT = UNIT_LIST\nEND_OBJECT = UNIT_LIST\n")
    unreadable.chmod(0)
    if os.access(unreadable, os.R_OK):  # running as root: permissions do not apply
        return
    line = _usage_error_line(_run("--dictionary", unreadable, label))
    assert line == f"pdsgen: error: {unreadable}: cannot be read (Permission denied)"


def test_real_dictionaries_are_accepted(corpus_dir, tmp_path):
    label = tmp_path / "X.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nANUMERIC = ABCDEF\r\nEND\r\n")
    report = validate_paths([label], dictionaries=[corpus_dir / "reference" / "testdd.full"])
    assert "DICT-006" in report.rule_ids()  # testdd.full's ANUMERIC is 2..4 characters long


def test_dictionary_path_problems_name_the_right_reason(tmp_path):
    label = tmp_path / "X.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\n^IMAGE = \"X.IMG\"\r\nEND\r\n")
    assert _usage_error_line(_run("--dictionary", "/dev/null", label)) == (
        "pdsgen: error: /dev/null: not a regular file (a character device)")
    assert _usage_error_line(_run("--dictionary", tmp_path / "none.full", label)) == (
        f"pdsgen: error: {tmp_path / 'none.full'}: no such dictionary file")
    with pytest.raises(PdsgenError, match="a directory, not a dictionary file"):
        validate_paths([label], dictionaries=[tmp_path])
