"""REC-008: records FILE_RECORDS counts that no object describes.

An end-of-file record no object describes, in a file that really has it, misleads no
reader (GDAL reads the image as the label says): a warning. Where the file does not have
the records the label counts, the arithmetic was broken by an edit: an error.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import rasterio
from rasterio.errors import NotGeoreferencedWarning

from pdsgen.validate import validate_paths

RECORD = 80
IMAGE = np.arange(2 * RECORD, dtype=np.uint8).reshape(2, RECORD)


def _label(file_records: int, pointer: str) -> bytes:
    lines = ["PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", f"RECORD_BYTES = {RECORD}",
             f"FILE_RECORDS = {file_records}", *(["LABEL_RECORDS = 4"] if pointer == "5" else []),
             f"^IMAGE = {pointer}", "OBJECT = IMAGE", "  LINES = 2", f"  LINE_SAMPLES = {RECORD}",
             "  SAMPLE_TYPE = MSB_UNSIGNED_INTEGER", "  SAMPLE_BITS = 8", "END_OBJECT = IMAGE", "END"]
    return ("\r\n".join(lines) + "\r\n").encode("ascii")


def _attached(tmp_path, file_records: int, records_in_file: int):
    label = _label(file_records, "5")
    label += b" " * (4 * RECORD - len(label))
    body = IMAGE.tobytes() + b"\0" * RECORD * (records_in_file - 6)
    path = tmp_path / "PRODUCT.IMG"
    path.write_bytes(label + body)
    return path


def _rec_008(path):
    return [f for f in validate_paths([path]).findings if f.rule == "REC-008"]


def test_an_end_of_file_record_the_file_has_is_a_warning(tmp_path):
    path = _attached(tmp_path, file_records=7, records_in_file=7)  # 4 label + 2 image + 1 spare
    found = _rec_008(path)
    assert len(found) == 1 and found[0].severity == "warning" and "the file has them" in found[0].message
    assert not [f for f in validate_paths([path]).findings if f.severity == "error"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotGeoreferencedWarning)
        with rasterio.open(path) as dataset:  # GDAL reads the image where the label says
            assert (dataset.read(1) == IMAGE).all()


def test_records_the_file_does_not_have_are_an_error(tmp_path):
    path = _attached(tmp_path, file_records=9, records_in_file=7)  # LINES edited, or records cut
    found = _rec_008(path)
    assert len(found) == 1 and found[0].severity == "error"
    assert f"has {7 * RECORD} bytes, not {9 * RECORD}" in found[0].message


@pytest.mark.parametrize("records_in_file, severity", [(3, "warning"), (4, "error")])
def test_detached_label_judged_by_its_data_file(tmp_path, records_in_file, severity):
    (tmp_path / "PRODUCT.LBL").write_bytes(_label(3, '("PRODUCT.DAT", 1)'))
    (tmp_path / "PRODUCT.DAT").write_bytes(IMAGE.tobytes() + b"\0" * RECORD * (records_in_file - 2))
    found = _rec_008(tmp_path / "PRODUCT.LBL")
    assert [f.severity for f in found] == [severity]


def test_objects_filling_the_records_are_not_reported(tmp_path):
    assert _rec_008(_attached(tmp_path, file_records=6, records_in_file=6)) == []


def _severities(path, **options):
    return [(f.severity, f.message) for f in validate_paths([path], **options).findings if f.rule == "REC-008"]


def test_detached_label_without_its_data_file_is_a_warning_that_says_so(tmp_path):
    """PDS3 permits records no object describes; without the file no reader can be shown misled."""
    (tmp_path / "PRODUCT.LBL").write_bytes(_label(4, '("PRODUCT.DAT", 1)'))
    found = _severities(tmp_path / "PRODUCT.LBL")
    assert [s for s, _ in found] == ["warning"]
    assert "could not be looked at (not found beside the label)" in found[0][1]


@pytest.mark.parametrize("records_in_file", [7, 9])
def test_labels_only_is_a_warning_whatever_the_file_holds(tmp_path, records_in_file):
    path = _attached(tmp_path, file_records=8, records_in_file=records_in_file)
    found = _severities(path, labels_only=True)
    assert [s for s, _ in found] == ["warning"] and "(--labels-only)" in found[0][1]
    assert [s for s, _ in _severities(path)] == ["error"]  # with the data looked at: as before


def test_label_only_copy_of_an_attached_label_is_a_warning(tmp_path):
    label = _label(7, "5")
    (tmp_path / "COPY.IMG").write_bytes(label + b" " * (4 * RECORD - len(label)))  # the label, no data
    found = _severities(tmp_path / "COPY.IMG")
    assert [s for s, _ in found] == ["warning"] and "(a label-only copy)" in found[0][1]
