"""Hostile inputs that try to exhaust pdsgen (issue 38, items 6 and 7's reports and batches).

Each case is made at test time and run as a user would run it, in a fresh process whose time
and peak memory are measured from outside: the run ends within its bound, holds under 1 GB,
shows no traceback, and one bad file is a finding (or a one-line refusal) while the run goes
on with the others.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

SECONDS = 60
PEAK_BYTES = 1 << 30
# A ceiling on the child's data (not its address space: the Schematron engine reserves tens of
# gigabytes it never uses), so a case that does blow up fails its test (with a MemoryError)
# instead of taking the shared machine down with it.
DATA_LIMIT = 6 << 30


@dataclass
class Run:
    returncode: int
    stdout: str
    stderr: str
    seconds: float
    peak_bytes: int


def _limit_child() -> None:
    resource.setrlimit(resource.RLIMIT_DATA, (DATA_LIMIT, DATA_LIMIT))


def run_bounded(*args: object, cwd: Path | None = None, seconds: float = SECONDS) -> Run:
    """`python -m pdsgen ARGS` in a fresh process, killed after `seconds`: what it printed,
    its exit status, how long it ran and its peak resident memory (from wait4)."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.perf_counter()
        process = subprocess.Popen([sys.executable, "-m", "pdsgen", *map(str, args)], stdout=out,
                                   stderr=err, stdin=subprocess.DEVNULL, cwd=cwd,
                                   preexec_fn=_limit_child)
        timer = threading.Timer(seconds, process.kill)
        timer.start()
        try:
            _, status, usage = os.wait4(process.pid, 0)
        finally:
            timer.cancel()
        process.returncode = os.waitstatus_to_exitcode(status)
        elapsed = time.perf_counter() - start
        out.seek(0)
        err.seek(0)
        return Run(process.returncode, out.read().decode("utf-8", "replace"),
                   err.read().decode("utf-8", "replace"), elapsed, usage.ru_maxrss * 1024)


def assert_bounded(run: Run, seconds: float = SECONDS) -> None:
    """The run ended by itself, in time, under the memory bound, without a traceback."""
    assert run.returncode >= 0, f"killed (signal {-run.returncode}) after {run.seconds:.1f} s"
    assert run.seconds < seconds, run.seconds
    assert run.peak_bytes < PEAK_BYTES, f"peak {run.peak_bytes / 2**20:.0f} MiB"
    assert "Traceback" not in run.stderr + run.stdout, run.stderr[-3000:]
    assert "RecursionError" not in run.stderr + run.stdout
    assert "ValueError" not in run.stderr + run.stdout


def image_label(**overrides: str) -> str:
    """A small detached PDS3 image label; `overrides` replace or add top-level statements."""
    top = {"PDS_VERSION_ID": "PDS3", "RECORD_TYPE": "FIXED_LENGTH", "RECORD_BYTES": "4",
           "FILE_RECORDS": "4", "^IMAGE": '"IMAGE.IMG"', "PRODUCT_ID": '"P1"'}
    top.update(overrides)
    lines = [f"{key} = {value}" for key, value in top.items()]
    lines += ["OBJECT = IMAGE", "  LINES = 4", "  LINE_SAMPLES = 4", "  SAMPLE_BITS = 8",
              "  SAMPLE_TYPE = UNSIGNED_INTEGER", "END_OBJECT = IMAGE", "END", ""]
    return "\r\n".join(lines)


def two_products(root: Path, hostile_text: str) -> tuple[Path, Path]:
    """A directory with one hostile label and one plain one beside it (each with its data)."""
    good = image_label(PRODUCT_ID='"GOOD"')
    for name, text in (("BAD", hostile_text), ("GOOD", good)):
        product = root / name
        product.mkdir(parents=True)
        text = text.replace('"IMAGE.IMG"', f'"{name}.IMG"')
        (product / f"{name}.LBL").write_text(text, encoding="latin-1", newline="")
        (product / f"{name}.IMG").write_bytes(bytes(range(16)))
    return root / "BAD" / "BAD.LBL", root / "GOOD" / "GOOD.LBL"


# -- integers longer than Python's int-string limit ------------------------------------------

LONG_INTEGER = "7" * 5000


def test_a_5000_digit_integer_is_a_finding_in_validate(tmp_path):
    bad, good = two_products(tmp_path / "d", image_label(RECORD_BYTES=LONG_INTEGER))
    run = run_bounded("validate", "--no-config", tmp_path / "d")
    assert_bounded(run)
    assert run.returncode == 1, run.stderr
    assert "BAD.LBL" in run.stdout and "2 file(s) checked" in run.stdout
    assert "5000 digits" in run.stdout


def test_a_5000_digit_integer_anywhere_is_a_finding(tmp_path):
    for name, label in (("based", image_label(PRODUCT_ID="16#" + "F" * 5000 + "#")),
                        ("seq", image_label(PRODUCT_ID=f"(1, {LONG_INTEGER})")),
                        ("negative", image_label(FILE_RECORDS="-" + LONG_INTEGER))):
        two_products(tmp_path / name, label)
        run = run_bounded("validate", "--no-config", tmp_path / name)
        assert_bounded(run)
        assert run.returncode == 1, (name, run.stderr)


def test_a_5000_digit_integer_does_not_stop_migrate(tmp_path):
    bad, good = two_products(tmp_path / "d", image_label(RECORD_BYTES=LONG_INTEGER))
    run = run_bounded("migrate", bad, good, "-o", tmp_path / "out")
    assert_bounded(run)
    assert run.returncode in (0, 1, 2), run.stderr
    assert any(path.name.upper().startswith("GOOD") and path.suffix == ".xml"
               for path in (tmp_path / "out").rglob("*")), run.stderr


def test_a_5000_digit_integer_does_not_stop_review(tmp_path):
    two_products(tmp_path / "d", image_label(RECORD_BYTES=LONG_INTEGER))
    page = tmp_path / "review.html"
    run = run_bounded("review", tmp_path / "d", "-o", page)
    assert_bounded(run)
    assert page.is_file(), run.stderr


# -- nesting ------------------------------------------------------------------------------------

DEPTH = 100_000


def test_a_value_nested_100000_parentheses_deep_is_a_finding(tmp_path):
    deep = "(" * DEPTH + "1" + ")" * DEPTH
    two_products(tmp_path / "d", image_label(PRODUCT_ID=deep))
    run = run_bounded("validate", "--no-config", tmp_path / "d")
    assert_bounded(run)
    assert run.returncode == 1
    assert "2 file(s) checked" in run.stdout and "nested" in run.stdout
    assert len(run.stdout) < 100_000  # one finding, not one per bracket


def test_objects_nested_100000_deep_are_a_finding_in_validate_and_review(tmp_path):
    opening = "".join("OBJECT = O\r\n" for _ in range(DEPTH))
    closing = "".join("END_OBJECT = O\r\n" for _ in range(DEPTH))
    label = image_label().replace("END\r\n", opening + closing + "END\r\n")
    two_products(tmp_path / "d", label)
    run = run_bounded("validate", "--no-config", tmp_path / "d")
    assert_bounded(run)
    assert run.returncode == 1
    assert "2 file(s) checked" in run.stdout and "nested" in run.stdout
    page = tmp_path / "review.html"
    run = run_bounded("review", tmp_path / "d", "-o", page)
    assert_bounded(run)
    assert page.is_file(), run.stderr


# -- ^STRUCTURE includes ---------------------------------------------------------------------

TABLE_LABEL = "\r\n".join([
    "PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", "RECORD_BYTES = 8", "FILE_RECORDS = 2",
    '^TABLE = "T.DAT"', 'PRODUCT_ID = "T"', "OBJECT = TABLE", "  INTERCHANGE_FORMAT = BINARY",
    "  ROWS = 2", "  ROW_BYTES = 8", "  COLUMNS = 1", '  ^STRUCTURE = "F0.FMT"', "END_OBJECT = TABLE",
    "END", ""])
COLUMN = "\r\n".join(["OBJECT = COLUMN", "  NAME = X", "  DATA_TYPE = MSB_INTEGER", "  START_BYTE = 1",
                      "  BYTES = 4", "END_OBJECT = COLUMN", ""])


def include_fan_out(root: Path, levels: int = 20, fan: int = 4) -> Path:
    """A table whose format files each include the next `fan` times: fan**(levels-1) paths."""
    root.mkdir()
    (root / "T.LBL").write_text(TABLE_LABEL, newline="")
    (root / "T.DAT").write_bytes(bytes(16))
    for level in range(levels):
        body = COLUMN if level == levels - 1 else f'^STRUCTURE = "F{level + 1}.FMT"\r\n' * fan
        (root / f"F{level}.FMT").write_text(body + "END\r\n", newline="")
    return root / "T.LBL"


def test_an_include_fan_out_is_walked_once_per_file_in_validate(tmp_path):
    label = include_fan_out(tmp_path / "d")
    run = run_bounded("validate", "--no-config", label, seconds=30)
    assert_bounded(run, seconds=30)
    assert run.returncode in (0, 1), run.stderr


def test_an_include_fan_out_is_refused_or_bounded_in_migrate(tmp_path):
    label = include_fan_out(tmp_path / "d")
    run = run_bounded("migrate", label, "-o", tmp_path / "out", seconds=30)
    assert_bounded(run, seconds=30)
    assert run.returncode == 2 and "T.LBL" in run.stderr, run.stderr
    assert len(run.stderr.strip().splitlines()) == 1, run.stderr


def test_a_structure_including_itself_is_refused_in_migrate(tmp_path):
    label = include_fan_out(tmp_path / "d", levels=2, fan=1)
    (tmp_path / "d" / "F1.FMT").write_text('^STRUCTURE = "F0.FMT"\r\nEND\r\n', newline="")
    run = run_bounded("migrate", label, "-o", tmp_path / "out", seconds=30)
    assert_bounded(run, seconds=30)
    assert run.returncode == 2 and "includes itself" in run.stderr, run.stderr


def test_an_include_loop_is_still_reported_once_walked_once(tmp_path):
    label = include_fan_out(tmp_path / "d", levels=3, fan=2)
    (tmp_path / "d" / "F2.FMT").write_text('^STRUCTURE = "F1.FMT"\r\nEND\r\n', newline="")
    run = run_bounded("validate", "--no-config", label, seconds=30)
    assert_bounded(run, seconds=30)
    assert "include loop: T.LBL -> F0.FMT -> F1.FMT -> F2.FMT -> F1.FMT" in run.stdout, run.stdout


# -- files that are no regular files -----------------------------------------------------------

def test_a_fifo_named_like_a_label_is_refused_by_extras(tmp_path):
    fifo = tmp_path / "DTM.LBL"
    os.mkfifo(fifo)
    run = run_bounded("extras", fifo, "-o", tmp_path / "out", seconds=30)
    assert_bounded(run, seconds=30)
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "DTM.LBL" in lines[0] and "regular file" in lines[0], run.stderr


def test_a_fifo_named_like_an_image_is_refused_by_extras(tmp_path):
    fifo = tmp_path / "DTM.IMG"
    os.mkfifo(fifo)
    run = run_bounded("extras", fifo, "-o", tmp_path / "out", seconds=30)
    assert_bounded(run, seconds=30)
    assert run.returncode == 2, run.stderr
    assert "DTM.IMG" in run.stderr and len(run.stderr.strip().splitlines()) == 1, run.stderr


def test_a_fifo_in_a_delivery_does_not_block_validate_or_review(tmp_path):
    two_products(tmp_path / "d", image_label())
    os.mkfifo(tmp_path / "d" / "BAD" / "PIPE.LBL")
    run = run_bounded("validate", "--no-config", tmp_path / "d", seconds=30)
    assert_bounded(run, seconds=30)
    assert "2 file(s) checked" in run.stdout or "3 file(s) checked" in run.stdout, run.stdout
    run = run_bounded("review", tmp_path / "d", "-o", tmp_path / "review.html", seconds=30)
    assert_bounded(run, seconds=30)
    assert (tmp_path / "review.html").is_file(), run.stderr


def test_a_fifo_named_by_a_label_as_its_data_is_refused_by_extras(tmp_path):
    label = tmp_path / "P.LBL"
    label.write_text(image_label(**{"^IMAGE": '"DATA.IMG"'}), newline="")
    os.mkfifo(tmp_path / "DATA.IMG")
    run = run_bounded("extras", label, "-o", tmp_path / "out", seconds=30)
    assert_bounded(run, seconds=30)
    assert run.returncode == 2, run.stderr
    assert "DATA.IMG" in run.stderr and "regular file" in run.stderr, run.stderr


# -- reports: file names holding control characters -------------------------------------------

FORGED = "::error file=FORGED.LBL,line=1::forged"


def forged_delivery(root: Path) -> Path:
    """A delivery holding a label with findings whose file name holds a line break and a forged
    workflow command (and an escape sequence that would recolour a terminal)."""
    root.mkdir()
    label = root / f"A\n{FORGED}\n\x1b[31mB.LBL"
    label.write_text(image_label(PRODUCT_ID="", **{"^IMAGE": '"NONE.IMG"'}), newline="")
    return label


def test_a_file_name_cannot_forge_report_lines_in_any_format(tmp_path):
    import json

    from lxml import etree

    forged_delivery(tmp_path / "d")
    for fmt in ("text", "github", "json", "sarif", "junit"):
        run = run_bounded("validate", "--no-config", "--format", fmt, tmp_path / "d")
        assert_bounded(run)
        assert run.returncode == 1, (fmt, run.stderr)
        lines = run.stdout.splitlines()
        assert not any(line.startswith(("::error file=FORGED", "\x1b")) for line in lines), (fmt, run.stdout)
        assert "\x1b" not in run.stdout and "\x1b" not in run.stderr, fmt
        if fmt == "text":
            assert all(line.startswith(str(tmp_path)) for line in lines[:-1]), run.stdout
        if fmt in ("json", "sarif"):
            json.loads(run.stdout)
        if fmt == "junit":
            etree.fromstring(run.stdout.encode())


def test_a_file_name_cannot_forge_lines_of_a_refusal(tmp_path):
    label = forged_delivery(tmp_path / "d")
    for command in (("extras", label, "-o", tmp_path / "x"), ("migrate", label, "-o", tmp_path / "m")):
        run = run_bounded(*command)
        assert_bounded(run)
        assert run.returncode == 2, run.stderr
        assert not any(line.startswith("::") for line in run.stderr.splitlines()), run.stderr
        assert "\x1b" not in run.stderr


# -- batch: a job's output stays inside the batch's -o ----------------------------------------

def test_a_batch_job_writing_outside_its_outdir_is_refused(tmp_path):
    escaped = tmp_path / "X"
    base = tmp_path / "a" / "b" / "c"
    base.mkdir(parents=True)
    jobs = [('[[validate]]\nid = "v{n}"\ninputs = ["in"]\noutput = "{where}/report.json"\n', where)
            for where in ("../../../X", str(escaped), "ok/../../X")]
    jobs += [('[[extras]]\nid = "e{n}"\ninputs = ["in/P.LBL"]\noutdir = "{where}"\n', "../../../X")]
    text = "".join(job.format(n=n, where=where) for n, (job, where) in enumerate(jobs))
    (base / "in").mkdir()
    (base / "in" / "P.LBL").write_text(image_label(), newline="")
    manifest = base / "release.toml"
    manifest.write_text(text)
    run = run_bounded("batch", manifest, "-o", base / "out", "--dry-run")
    assert_bounded(run)
    assert run.returncode == 2, run.stdout + run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 4 and all("outside" in line for line in lines), run.stderr
    assert not escaped.exists() and not (base / "out").exists()


def test_a_batch_job_writing_inside_its_outdir_is_taken(tmp_path):
    from pdsgen.batch.manifest import load_manifest

    manifest = tmp_path / "release.toml"
    manifest.write_text('[[validate]]\nid = "v"\ninputs = ["in"]\noutput = "sub/../reports/v.json"\n')
    (job,) = load_manifest(manifest, tmp_path / "out").jobs
    assert Path(job.params["output"]) == tmp_path / "out" / "reports" / "v.json"


# -- JPEG 2000 headers declaring more than memory holds ---------------------------------------

def huge_tile_jp2(path: Path, side: int = 10**6) -> Path:
    """A valid 8 x 8 JP2 whose header is then made to declare one `side` x `side` tile."""
    import struct

    import numpy as np
    import rasterio

    small = path.with_name("small.jp2")
    with rasterio.open(small, "w", driver="JP2OpenJPEG", width=8, height=8, count=1, dtype="uint8",
                       QUALITY=100, REVERSIBLE=True, RESOLUTIONS=1) as dataset:
        dataset.write(np.arange(64, dtype="uint8").reshape(1, 8, 8))
    data = bytearray(small.read_bytes())
    small.unlink()
    siz = data.find(b"\xff\x4f\xff\x51")
    for offset in (8, 12, 24, 28):  # Xsiz, Ysiz, XTsiz, YTsiz
        struct.pack_into(">I", data, siz + offset, side)
    ihdr = data.find(b"ihdr")
    struct.pack_into(">II", data, ihdr + 4, side, side)
    path.write_bytes(bytes(data))
    assert len(data) < 400
    return path


def test_a_jp2_declaring_a_huge_tile_is_refused_by_extras_before_decoding(tmp_path):
    jp2 = huge_tile_jp2(tmp_path / "PSP_005000_1000_RED.NOMAP.JP2")
    for command in (("extras", "--kind", "nomap", jp2, "-o", tmp_path / "n"), ("extras", jp2, "-o", tmp_path / "m")):
        run = run_bounded(*command)
        assert_bounded(run)
        assert run.returncode == 2, run.stderr
        lines = run.stderr.strip().splitlines()
        assert len(lines) == 1 and "JPEG 2000" in lines[0] and jp2.name in lines[0], run.stderr


# -- review: memory per label ------------------------------------------------------------------

def test_review_of_a_label_of_500000_keywords_stays_bounded(tmp_path):
    keywords = "".join(f"K{n:07d} = {n}\r\n" for n in range(500_000))
    two_products(tmp_path / "d", image_label().replace("END\r\n", keywords + "END\r\n"))
    assert (tmp_path / "d" / "BAD" / "BAD.LBL").stat().st_size > 8_000_000
    page = tmp_path / "review.html"
    run = run_bounded("review", tmp_path / "d", "-o", page)
    assert_bounded(run)
    assert page.is_file(), run.stderr
    assert page.stat().st_size < 50_000_000


# -- PDS4 labels: long integers and deep nesting (held by the XML reader) ---------------------

PDS4_TABLE = Path(__file__).resolve().parent / "data" / "nasa_validate" / "github480" / "test_success.xml"


def test_pds4_labels_with_long_integers_or_deep_nesting_are_findings(tmp_path):
    import re

    text = PDS4_TABLE.read_text()
    long_records = re.sub(r"<records>\d+</records>", f"<records>{LONG_INTEGER}</records>", text)
    at = text.index("</Identification_Area>")
    deep = text[:at] + "<a>" * DEPTH + "x" + "</a>" * DEPTH + text[at:]
    for name, label in (("long", long_records), ("deep", deep)):
        (tmp_path / name).mkdir()
        (tmp_path / name / "label.xml").write_text(label)
        (tmp_path / name / "test.tab").write_bytes(b"1,2\r\n3,4\r\n")
        run = run_bounded("validate", "--no-config", "--offline", tmp_path / name)
        assert_bounded(run)
        assert run.returncode == 1 and "label.xml" in run.stdout, (name, run.stdout, run.stderr)
        run = run_bounded("review", tmp_path / name, "-o", tmp_path / f"{name}.html")
        assert_bounded(run)
        assert (tmp_path / f"{name}.html").is_file(), (name, run.stderr)


def test_a_value_typed_on_the_command_line_cannot_forge_lines_of_an_error(tmp_path):
    for command in (("validate", "--config", f"nope\n{FORGED}", tmp_path),
                    ("validate", "--format", f"text\n{FORGED}", tmp_path),
                    ("review", tmp_path / f"nope\n{FORGED}")):
        run = run_bounded(*command)
        assert_bounded(run)
        assert run.returncode == 2, run.stderr
        assert len(run.stderr.strip().splitlines()) == 1, run.stderr
