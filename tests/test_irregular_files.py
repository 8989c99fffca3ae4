"""A tree's files are never trusted to be files: FIFOs, and line-oriented text of any size.

A delivery handed to `pdsgen validate` (a CI pull request, a bucket staged to disk) may hold a
FIFO under any name - a label, its data, MD5SUMS.TXT, an inventory, README.TXT, JP2INFO.TXT,
INDEX.TAB, AAREADME.TXT. Opening one for reading waits for a writer that never comes: before
this, a FIFO in place of almost any file of a delivery hung validate for ever (the delivery's
checks and IDN-004's look at every file opened them plainly). Every such read now goes through
pdsgen/bounded.py (open_regular, the one such open, and text_lines): a FIFO is named (DLV-030) and never opened, and a
line-oriented file is streamed a line at a time, whatever its size or its lines' length.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pdsgen.bounded import NotRegularFile, open_regular, text_lines
from pdsgen.errors import InputError

from helpers import demo_products

pytestmark = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are a POSIX file kind")

# One file of each kind a delivery's checks read, each replaced by a FIFO in turn
KINDS = ("AAREADME.TXT", "MD5SUMS.TXT", "INDEX/INDEX.TAB", "DATA/JP2INFO.TXT", "EXTRAS/README.TXT",
         "DATA/collection_data_inventory.csv", "DATA/{dtm}.IMG", "DATA/{dtm}.xml")


@pytest.fixture(scope="module")
def delivery(tmp_path_factory) -> tuple[Path, str]:
    root = tmp_path_factory.mktemp("irregular")
    products = demo_products(root)
    dtm = next(products.glob("*.IMG")).stem
    out = root / "delivery"
    subprocess.run([sys.executable, "-m", "pdsgen", "deliver", str(products), "-o", str(out), "--label", "both",
                    "--volume-id", "TEST_0001", "--bundle-lid", "urn:nasa:pds:test", "-q"], check=True)
    return out, dtm


@pytest.mark.parametrize("kind", KINDS)
def test_a_fifo_in_a_delivery_is_named_and_never_waited_on(delivery, tmp_path, kind):
    source, dtm = delivery
    tree = tmp_path / "d"
    shutil.copytree(source, tree)
    fifo = tree / kind.format(dtm=dtm)
    assert fifo.is_file()
    fifo.unlink()
    os.mkfifo(fifo)
    run = subprocess.run([sys.executable, "-m", "pdsgen", "validate", str(tree)], capture_output=True, text=True,
                         timeout=120)
    assert run.returncode in (0, 1), run.stderr
    assert f"{fifo}: error [DLV-030] is not a regular file of the delivery" in run.stdout
    assert "Traceback" not in run.stderr


def test_open_regular_refuses_a_fifo_without_waiting(tmp_path):
    fifo = tmp_path / "MD5SUMS.TXT"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match="is a FIFO, not a regular manifest"):
        text_lines(fifo, "manifest")
    with pytest.raises(NotRegularFile, match="is a FIFO"):
        open_regular(fifo)
    with pytest.raises(NotRegularFile, match="is a directory"):
        open_regular(tmp_path)


@settings(max_examples=150, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.binary(max_size=600), limit=st.integers(min_value=1, max_value=80))
def test_text_lines_streams_what_the_bytes_hold(tmp_path, data, limit):
    """Each line as the bytes hold it (LF or CR LF ended, the last one possibly not), a line
    longer than the limit cut there and its rest skipped - never more than one line held."""
    path = tmp_path / "lines.txt"
    path.write_bytes(data)
    segments = data.split(b"\n")
    ended = [segment + b"\n" for segment in segments[:-1]] + ([segments[-1]] if segments[-1] else [])
    expected = [line[:limit].rstrip(b"\r\n").decode("latin-1") for line in ended]
    assert list(text_lines(path, line_limit=limit)) == expected


def test_a_huge_line_is_cut_not_held(tmp_path):
    path = tmp_path / "README.TXT"
    with path.open("wb") as stream:
        stream.write(b"x" * (8 << 20) + b"\nProduct ID: A\n")
    lines = list(text_lines(path, line_limit=1024))
    assert lines == ["x" * 1024, "Product ID: A"]


def test_a_fifo_named_like_a_preview_has_no_size(tmp_path):
    """DLV-027's JPEG frame walk opens a preview through the one regular-file open."""
    from pdsgen.formats.jpeg_size import jpeg_size

    fifo = tmp_path / "P.br.jpg"
    os.mkfifo(fifo)
    assert jpeg_size(fifo) is None
