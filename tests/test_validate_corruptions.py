"""One defect at a time in a product pdsgen wrote: each is reported with its rule id, exit 1.

The clean product validates with zero errors and warnings first (strict), so every
finding below comes from the one edit made to it.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.validate import validate_paths
from test_validate_support import label_end, make_dtm, replace_in_label, resize_label_text


def _value(path: Path, keyword: str) -> bytes:
    head = path.read_bytes()[: label_end(path.read_bytes())]
    m = re.search(rb"\r\n *" + keyword.encode() + rb" *= *([^\r <]+)", head)
    assert m, keyword
    return m.group(1)


def _set_value(path: Path, keyword: str, new: str) -> None:
    old = _value(path, keyword)
    head = path.read_bytes()[: label_end(path.read_bytes())]
    line = re.search(rb"\r\n( *" + keyword.encode() + rb" *= *)" + re.escape(old), head)
    resize_label_text(path, line.group(1) + old, line.group(1) + new.encode())


def shift_sample_offset_1px(path: Path) -> None:
    _set_value(path, "SAMPLE_PROJECTION_OFFSET", repr(float(_value(path, "SAMPLE_PROJECTION_OFFSET")) + 1))


def shift_line_offset_half_px(path: Path) -> None:
    _set_value(path, "LINE_PROJECTION_OFFSET", repr(float(_value(path, "LINE_PROJECTION_OFFSET")) + 0.5))


def map_resolution_off(path: Path) -> None:
    _set_value(path, "MAP_RESOLUTION", repr(float(_value(path, "MAP_RESOLUTION")) * 1.001))


def wrong_record_bytes(path: Path) -> None:
    _set_value(path, "RECORD_BYTES", str(int(_value(path, "RECORD_BYTES")) + 4))


def truncate_data(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[:-100])


def lf_line_ends(path: Path) -> None:
    data = path.read_bytes()
    end = label_end(data)
    head = data[:end].replace(b"\r\n", b"\n")
    path.write_bytes(head + b" " * (end - len(head)) + data[end:])


def line_of_81_bytes(path: Path) -> None:
    """Widen one comment line to 79 characters (81 bytes with CR LF), taking the spaces
    from another comment so the label keeps its length whatever its padding."""
    data = path.read_bytes()
    end = label_end(data)
    lines = data[:end].split(b"\r\n")
    comments = [i for i, line in enumerate(lines) if line.rstrip().endswith(b" */")]
    def trailing_spaces(i: int) -> int:
        return len(lines[i][:-2]) - len(lines[i][:-2].rstrip(b" "))

    donor = max(comments, key=trailing_spaces)
    wide = next(i for i in comments if i != donor)
    grow = 79 - len(lines[wide])
    assert trailing_spaces(donor) > grow
    lines[wide] = lines[wide][:-2] + b" " * grow + b"*/"
    lines[donor] = lines[donor][:-2 - grow] + b"*/"
    path.write_bytes(b"\r\n".join(lines) + data[end:])


def valid_maximum_wrong(path: Path) -> None:
    _set_value(path, "VALID_MAXIMUM", repr(float(_value(path, "VALID_MAXIMUM")) + 1.5))


def duplicate_keyword(path: Path) -> None:
    replace_in_label(path, b"  OFFSET           =", b"  SCALING_FACTOR   =")


def unbalanced_object(path: Path) -> None:
    resize_label_text(path, b"END_OBJECT = VIEWING_PARAMETERS\r\n", b"")


CORRUPTIONS = [
    (shift_sample_offset_1px, "MAP-003"),
    (shift_line_offset_half_px, "MAP-003"),
    (map_resolution_off, "MAP-002"),
    (wrong_record_bytes, "REC-002"),
    (truncate_data, "REC-006"),
    (lf_line_ends, "FILE-002"),
    (line_of_81_bytes, "FILE-004"),
    (valid_maximum_wrong, "IMG-007"),
    (duplicate_keyword, "SYNTAX-004"),
    (unbalanced_object, "SYNTAX-005"),
]


@pytest.fixture(scope="module")
def clean_product(tmp_path_factory) -> bytes:
    path = make_dtm(tmp_path_factory.mktemp("clean"), "equirectangular", lines=30, samples=40)
    report = validate_paths([path], strict=True)
    assert [f.rule for f in report.findings if f.severity != "info"] == []
    return path.read_bytes()


@pytest.mark.parametrize(("corrupt", "rule"), CORRUPTIONS, ids=[c.__name__ for c, _ in CORRUPTIONS])
def test_each_defect_is_reported(tmp_path, clean_product, corrupt, rule):
    path = tmp_path / "DTM_EQUIRECTANGULAR.IMG"
    path.write_bytes(clean_product)
    corrupt(path)
    report = validate_paths([path])
    errors = {f.rule for f in report.findings if f.severity == "error"}
    assert rule in errors, [f"{f.rule}: {f.message}" for f in report.findings]
    assert report.exit_code == 1
    result = CliRunner().invoke(main, ["validate", str(path)])
    assert result.exit_code == 1
    assert f"[{rule}]" in result.output


def test_offset_messages_give_residuals_and_expected_values(tmp_path, clean_product):
    path = tmp_path / "DTM_EQUIRECTANGULAR.IMG"
    path.write_bytes(clean_product)
    original = float(_value(path, "LINE_PROJECTION_OFFSET"))
    shift_line_offset_half_px(path)
    finding = next(f for f in validate_paths([path]).findings if f.rule == "MAP-003")
    assert "centre/corner confusion" in finding.message
    assert f"LINE_PROJECTION_OFFSET = {original!r}" in finding.message
    assert "px" in finding.message and finding.line is not None


def test_both_offsets_one_pixel_apart_is_the_older_convention(tmp_path, clean_product):
    path = tmp_path / "DTM_EQUIRECTANGULAR.IMG"
    path.write_bytes(clean_product)
    shift_sample_offset_1px(path)
    _set_value(path, "LINE_PROJECTION_OFFSET", repr(float(_value(path, "LINE_PROJECTION_OFFSET")) + 1))
    report = validate_paths([path])
    assert "MAP-005" in report.rule_ids("warning")
    assert "MAP-003" not in report.rule_ids()
    assert report.exit_code == 0
    assert validate_paths([path], strict=True).exit_code == 1


def test_map_resolution_message_names_expected_value(tmp_path, clean_product):
    path = tmp_path / "DTM_EQUIRECTANGULAR.IMG"
    path.write_bytes(clean_product)
    right = float(_value(path, "MAP_RESOLUTION"))
    map_resolution_off(path)
    finding = next(f for f in validate_paths([path]).findings if f.rule == "MAP-002")
    expected = float(re.search(r"expected MAP_RESOLUTION = (\S+)", finding.message).group(1))
    assert abs(expected - right) <= 1e-9 * right
