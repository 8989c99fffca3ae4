"""The table checks' findings on tables with seeded faults of every kind (tests/table_cases.py)
are those recorded in tests/data/table_checks/findings.json, which the value-at-a-time
checks made before the column-at-a-time rewrite (same rules, messages, lines, order and
first-N limits). Regenerate only for an intended change: PDSGEN_UPDATE_GOLDEN=1."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from lxml import etree

from pdsgen.validate.pds4 import table_checks, table_columns
from pdsgen.validate.pds4.label_tree import Pds4Hits
from table_cases import all_cases

GOLDEN = Path(__file__).parent / "data" / "table_checks" / "findings.json"
UPDATE = os.environ.get("PDSGEN_UPDATE_GOLDEN") == "1"


def _findings(label: Path) -> dict[str, list[list[object]]]:
    report = Pds4Hits(label)
    table_checks.check_tables(report, etree.parse(str(label)))
    return {
        rule: [[hit.message, hit.line, hit.keyword] for hit in hits] for rule, hits in sorted(report.by_rule.items())
    }


@pytest.fixture(scope="module")
def found(tmp_path_factory) -> dict[str, dict[str, list[list[object]]]]:
    directory = tmp_path_factory.mktemp("tables")
    return {case.name: _findings(case.write(directory)) for case in all_cases()}


def test_findings_are_those_recorded(found):
    if UPDATE:
        GOLDEN.write_text(json.dumps(found, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    expected = json.loads(GOLDEN.read_text(encoding="utf-8"))
    assert sorted(found) == sorted(expected)
    for name in expected:
        assert found[name] == expected[name], name


@pytest.mark.parametrize("block_bytes", [1, 1000])
def test_findings_do_not_depend_on_the_block_size(found, tmp_path, block_bytes, monkeypatch):
    """A block of one record, or of a few, gives the findings of one large block: a table is read a block of
    whole records at a time, and no finding (nor its count) depends on where a block ends."""
    monkeypatch.setattr(table_columns, "BLOCK_BYTES", block_bytes)
    for case in all_cases():
        if case.name.startswith(("char_", "bin_")):
            assert _findings(case.write(tmp_path)) == found[case.name], case.name


def test_every_fault_kind_is_seeded(found):
    """The cases reach every rule the table checks report, past the first-N limit, and the clean twins are clean."""
    rules = {rule for findings in found.values() for rule in findings}
    assert rules >= {
        "PDS4-050",
        "PDS4-051",
        "PDS4-052",
        "PDS4-053",
        "PDS4-054",
        "PDS4-055",
        "PDS4-056",
        "PDS4-058",
        "PDS4-059",
    }
    assert any(
        hit[0].endswith("more like these") for findings in found.values() for hits in findings.values() for hit in hits
    )
    assert all(not findings for name, findings in found.items() if "_clean_" in name)


def test_plain_numbers_read_as_float_reads_them():
    """The arithmetic reading of plainly written numbers gives float()'s value bit for bit, recognises
    only values of the data_type's syntax, and counts their decimals as the decimals check does."""
    import random

    import numpy as np

    from pdsgen.validate.pds4.table_checks import _DECIMALS, PATTERNS

    rng = random.Random(7)
    alphabet = "0123456789" * 3 + "+-. eE"
    texts = [f"{rng.uniform(-1e6, 1e6):.{rng.randrange(0, 9)}f}" for _ in range(3000)]
    texts += ["".join(rng.choice(alphabet) for _ in range(rng.randrange(1, 12))) for _ in range(3000)]
    texts += ["-0.00", "+.5", "5.", ".", "-", "9" * 15, "9" * 16, "0.1", "2.675", " 1 2", "1.2.3"]
    width = 18
    block = np.frombuffer(b"".join(t.rjust(width).encode() for t in texts), np.uint8).reshape(len(texts), width)
    for data_type in ("ASCII_Real", "ASCII_Integer", "ASCII_NonNegative_Integer"):
        numbers = table_columns.number_columns(table_columns.by_position(block), data_type)
        assert numbers is not None
        for text, plain, value, decimals in zip(texts, numbers.plain, numbers.values, numbers.decimals, strict=True):
            if plain:
                stripped = text.strip()
                assert PATTERNS[data_type].match(stripped), (data_type, text)
                assert value == float(stripped), (data_type, text, value)
                assert decimals == len(_DECIMALS.match(stripped)["decimals"] or ""), text
    real = table_columns.number_columns(table_columns.by_position(block), "ASCII_Real")
    assert real is not None and real.plain.sum() > 3000  # the formatted numbers are read this way


def test_memory_is_one_block_whatever_the_table_size(tmp_path, monkeypatch):
    """A table twenty times longer takes no more memory to check: records are read a block at a time."""
    import tracemalloc

    from scale_bundle import write_table

    monkeypatch.setattr(table_columns, "BLOCK_BYTES", 1 << 16)
    small = write_table(tmp_path, "small", 1_200)
    large = tmp_path / "large.xml"
    (tmp_path / "large.tab").write_bytes((tmp_path / "small.tab").read_bytes() * 20)
    large.write_text(small.read_text().replace("<records>1200<", "<records>24000<").replace("small.tab", "large.tab"))
    peaks = {}
    for label in (small, large):
        tree = etree.parse(str(label))
        tracemalloc.start()
        report = Pds4Hits(label)
        table_checks.check_tables(report, tree)
        peaks[label.stem] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        assert not report.by_rule
    assert peaks["large"] < peaks["small"] * 1.25 + (1 << 16), peaks
    assert peaks["large"] < (tmp_path / "large.tab").stat().st_size / 3, peaks  # a few blocks, not the table


def test_a_record_length_past_any_file_is_a_finding_not_an_allocation(tmp_path):
    """record_length 10^15 over a file of a few hundred bytes: the file ends in record 1 (nothing the
    size of the claim is read or allocated)."""
    case = next(c for c in all_cases() if c.name == "char_clean_1")
    huge = case.label.replace(">262</record_length>", ">1000000000000000</record_length>")
    assert huge != case.label
    label = tmp_path / "huge.xml"
    label.write_text(huge)
    (tmp_path / case.data_name).write_bytes(case.data[:500])
    findings = _findings(label)
    assert findings["PDS4-051"] == [["Table_Character t: the file ends in record 1 of 120 (records of 1000000000000000 "
                                     "bytes from offset 0)", 6, "records"]]
