"""Label forms genuine archives use that are ODL/PDS (SFDU wrappers of every CCSDS form),
and one that is not (a real number without a decimal point)."""

from __future__ import annotations

from pathlib import Path

import pvl
import pytest

from pdsgen.label.parser import parse_label, sfdu_problem
from pdsgen.validate import validate_paths

GENUINE = Path(__file__).parent / "data" / "genuine_pds3"
BODY = "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\nEND\r\n"


@pytest.mark.parametrize("sfdu", [
    "CCSD3ZF0000100000001NJPL3IF0PDS200000001",  # Voyager/Galileo CD-ROMs: end-of-file delimited
    "CCSD3ZF0000100000001NJPL3KS0PDSX##mark##",  # Magellan gravity: a K-class label ended by a marker
    "CCSD3ZS00001$$MARKERNJPL3KS0PDSX$$MARKER",  # both delimited by a marker
    "CCSD3ZA00001000001234NJPL3IA0PDS300000999"[:20] + "NJPL3IA0PDS300000999",  # ASCII lengths
    "CCSD1Z000001000001234"[:20] + "NJPL1I00PDS300000999",  # version 1: ASCII lengths, spare bytes
    "CCSD3ZF0000100000001NJPL3KS0PDSX##mark##NJPL3IF0PDS300000001",  # a third label
])
def test_ccsds_sfdu_label_forms_are_accepted(tmp_path, sfdu):
    assert sfdu_problem(sfdu) is None
    path = tmp_path / "X.LBL"
    path.write_bytes((sfdu + "\r\n" + BODY).encode())
    rules = {f.rule for f in validate_paths([path]).findings}
    assert "FILE-006" not in rules and "SYNTAX-001" not in rules, rules


@pytest.mark.parametrize("sfdu, problem", [
    ("CCSD3ZF0000100000001NJPL3IF0PDS20000001", "20 each"),  # a character short
    ("CCSD3ZQ0000100000001NJPL3KS0PDSX##mark##", "delimitation Q"),
    ("CCSD3ZF0000100000001NJPL3KA0PDSX##mark##", "not 8 ASCII digits"),  # ASCII length, not a marker
    ("CCSD2ZF0000100000001NJPL3KS0PDSX##mark##", "binary length"),
    ("CCSD3ZF00001000000010JPL3KS0PDSX##mark##"[:20] + "NJPL3KS1PDSX##mark##", "not an SFDU label"),
    ("CCSD3KS0PDSX##mark##CCSD3ZF0000100000001", "Z-class"),
    ("CCSD3ZF0000l0000000lNJPL3IF0PDSX0000000m", "not an SFDU label"),  # 'l' for '1', and a length 'm'
])
def test_malformed_sfdu_labels_are_file_006_errors(tmp_path, sfdu, problem):
    assert problem in (sfdu_problem(sfdu) or "")
    path = tmp_path / "X.LBL"
    path.write_bytes((sfdu + "\r\n" + BODY).encode())
    found = [f for f in validate_paths([path]).findings if f.rule == "FILE-006"]
    assert found and found[0].severity == "error" and problem in found[0].message


def test_genuine_marker_delimited_sfdu_label():
    """Magellan's gravity label (CCSD Z-class, then an NJPL K-class label ended by ##mark##)."""
    label = GENUINE / "arael" / "shgj180u_README.txt"
    assert label.read_bytes().startswith(b"CCSD3ZF0000100000001NJPL3KS0PDSX##mark##")
    findings = validate_paths([label]).findings
    assert not [f for f in findings if f.severity == "error"], findings
    # pvl (which knows no SFDU) reads the same label once the wrapper line is taken off
    wrapped = label.read_text(encoding="ascii").split("\n", 1)[1]
    assert pvl.loads(wrapped)["PRODUCT_ID"] == "RS-SHGJ180U.A01"


@pytest.mark.parametrize("statement, written, suggested, line", [
    ("MISSING = 1e+30", "1e+30", "1.0e+30", 2),
    ("RANGE = (1e+30, 2.5) <KM>", "1e+30", "1.0e+30", 2),
    ("RANGE = (0.0,\r\n   -3E5) <M>", "-3E5", "-3.0E5", 3),  # the line the number is on
])
def test_a_real_without_a_decimal_point_is_a_warning(tmp_path, statement, written, suggested, line):
    path = tmp_path / "X.LBL"
    path.write_bytes(f"PDS_VERSION_ID = PDS3\r\n{statement}\r\nEND\r\n".encode())
    found = [f for f in validate_paths([path]).findings if f.rule == "SYNTAX-016"]
    assert len(found) == 1 and found[0].severity == "warning" and found[0].line == line
    assert written in found[0].message and suggested in found[0].message
    value = parse_label(path.read_text()).root.value(statement.split()[0])
    assert value is not None and pytest.approx(float(written)) in [v.number for v in value.scalars()]


@pytest.mark.parametrize("value", ["1.0e+30", "1.E5", ".5E-3", "100", "-2.5", "16#FF#"])
def test_odl_numbers_are_not_reported(tmp_path, value):
    path = tmp_path / "X.LBL"
    path.write_bytes(f"PDS_VERSION_ID = PDS3\r\nA = {value}\r\nEND\r\n".encode())
    assert not [f for f in validate_paths([path]).findings if f.rule == "SYNTAX-016"]
