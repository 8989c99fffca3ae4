"""The validator lists each directory once per run, not once per label in it (N labels in one
directory used to cost N listings of N names: minutes at 10,000 products), and still finds a
file that appears between two labels' checks as it did when each label listed its directory."""

from __future__ import annotations

import os
import time
from collections import Counter
from pathlib import Path

import pytest

from pdsgen.validate import runner
from pdsgen.validate.runner import iter_reports

PRODUCTS = 300

# A detached PDS3 label of an 8 x 8 unsigned byte image (PDS3 Standards Reference, ch. 5, 14)
_LABEL = """PDS_VERSION_ID = PDS3
RECORD_TYPE = FIXED_LENGTH
RECORD_BYTES = 8
FILE_RECORDS = 8
^IMAGE = "{data}"
PRODUCT_ID = "{pid}"
OBJECT = IMAGE
  LINES = 8
  LINE_SAMPLES = 8
  SAMPLE_TYPE = UNSIGNED_INTEGER
  SAMPLE_BITS = 8
END_OBJECT = IMAGE
END
"""


def _write(directory: Path, pid: str, data_name: str | None = None) -> Path:
    label = directory / f"{pid}.LBL"
    label.write_text(_LABEL.format(pid=pid, data=data_name or f"{pid}.IMG").replace("\n", "\r\n"))
    return label


def _settle(directory: Path) -> None:
    """Date the directory's last change a minute back: a listing made within a second of a
    change is not trusted (timestamp granularity), as after a delivery is just written."""
    past = time.time() - 60
    os.utime(directory, (past, past))


@pytest.fixture
def listings(monkeypatch: pytest.MonkeyPatch) -> Counter[str]:
    """Every os.listdir and os.scandir in this process, by directory."""
    counts: Counter[str] = Counter()
    real_listdir, real_scandir = os.listdir, os.scandir

    def listdir(path: str | os.PathLike[str] = ".") -> list[str]:
        counts[str(Path(os.fspath(path)).resolve())] += 1
        return real_listdir(path)

    def scandir(path: str | os.PathLike[str] = "."):  # type: ignore[no-untyped-def]
        counts[str(Path(os.fspath(path)).resolve())] += 1
        return real_scandir(path)

    monkeypatch.setattr(os, "listdir", listdir)
    monkeypatch.setattr(os, "scandir", scandir)
    return counts


def test_a_directory_of_labels_is_listed_a_constant_number_of_times(tmp_path: Path, listings: Counter[str]) -> None:
    data = tmp_path / "DATA"
    data.mkdir()
    for i in range(PRODUCTS):
        pid = f"P{i:04d}"
        _write(data, pid)
        (data / f"{pid}.IMG").write_bytes(bytes(64))
    # one label names its data file in the wrong case: the look-up still finds it, and says so
    _write(data, "PCASE", "pcase.img")
    (data / "PCASE.IMG").write_bytes(bytes(64))
    _settle(data)
    listings.clear()
    reports = list(iter_reports([tmp_path]))
    assert len(reports) == PRODUCTS + 1
    assert listings[str(data.resolve())] <= 4, listings
    case = next(r for r in reports if Path(r.path).name == "PCASE.LBL")
    assert any("case" in f.message.lower() for f in case.findings), [f.message for f in case.findings]
    clean = next(r for r in reports if Path(r.path).name == "P0000.LBL")
    assert not [f for f in clean.findings if f.severity == "error"], [f.message for f in clean.findings]


def test_a_file_that_appears_during_a_run_is_found(tmp_path: Path) -> None:
    label = _write(tmp_path, "LATE")
    _write(tmp_path, "OTHER")
    (tmp_path / "OTHER.IMG").write_bytes(bytes(64))
    _settle(tmp_path)

    def errors() -> list[str]:
        report, _ = runner.validate_file(label)
        return [f.message for f in report.findings if f.severity == "error"]

    runner.validate_file(tmp_path / "OTHER.LBL")  # the directory's listing is now held
    missing = errors()
    assert any("LATE.IMG" in m for m in missing), missing
    (tmp_path / "LATE.IMG").write_bytes(bytes(64))  # appears while the run goes on
    assert errors() == []
    (tmp_path / "LATE.IMG").unlink()
    assert errors() == missing


def test_the_html_page_of_a_label_set_lists_each_directory_a_constant_number_of_times(
        tmp_path: Path, listings: Counter[str]) -> None:
    """`validate --format html` looks for each product's previews beside its label: once per
    directory for the whole page, not once per label (a directory of N labels: N x N names)."""
    from pdsgen.review.collect import review_reports

    data = tmp_path / "DATA"
    extras = tmp_path / "EXTRAS"
    data.mkdir()
    extras.mkdir()
    for i in range(PRODUCTS):
        pid = f"P{i:04d}"
        _write(data, pid)
        (data / f"{pid}.IMG").write_bytes(bytes(64))
    for name in ("P0007.thumb.jpg", "P0007.browse.jpg"):  # one product has a preview
        (extras / name).write_bytes(b"\xff\xd8\xff\xd9")
    _settle(data)
    _settle(extras)
    reports = list(iter_reports([data]))
    listings.clear()
    review = review_reports(reports, tmp_path, "labels")
    assert len(review.products) == PRODUCTS
    assert listings[str(data.resolve())] <= 4 and listings[str(extras.resolve())] <= 4, listings
    with_previews = [e for e in review.products if e.previews]
    assert [e.product_id for e in with_previews] == ["P0007"]
