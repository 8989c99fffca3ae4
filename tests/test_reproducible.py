"""Products are byte-reproducible: the same input makes the same bytes on any day.

Every date pdsgen writes comes from one clock (pdsgen/clock.py) that honours SOURCE_DATE_EPOCH,
the reproducible-builds convention. These tests move the wall clock in-process (every reader of
it in the `time` module, which pdsgen's clock and pyshp's .dbf header both go through) instead of
waiting for another day, and check that the moved clock does reach what pdsgen writes when
SOURCE_DATE_EPOCH is not set - so the byte-identical comparison cannot pass by never moving.
"""

from __future__ import annotations

import ast
import datetime as dt
import os
import time
from pathlib import Path

import numpy as np
import pytest
from affine import Affine
from click.testing import CliRunner
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pdsgen import clock
from pdsgen.cli import main
from pdsgen.errors import ParamsError

from helpers import CRS_EQUIRECTANGULAR, elevation_array, write_raster

SRC = Path(__file__).resolve().parents[1] / "src" / "pdsgen"
EPOCH = 1700000000  # 2023-11-14T22:13:20Z
DAY = 86400
SINUSOIDAL = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"


def _moved_clock(monkeypatch: pytest.MonkeyPatch, seconds: float) -> None:
    """Every wall-clock reader of the `time` module, `seconds` later than the real clock."""
    real_time, real_localtime, real_gmtime, real_strftime = time.time, time.localtime, time.gmtime, time.strftime
    monkeypatch.setattr(time, "time", lambda: real_time() + seconds)
    monkeypatch.setattr(time, "time_ns", lambda: int((real_time() + seconds) * 1e9))
    monkeypatch.setattr(time, "localtime", lambda s=None: real_localtime(real_time() + seconds if s is None else s))
    monkeypatch.setattr(time, "gmtime", lambda s=None: real_gmtime(real_time() + seconds if s is None else s))
    monkeypatch.setattr(time, "strftime", lambda f, t=None: real_strftime(f, time.localtime() if t is None else t))


def _inputs(root: Path) -> dict[str, Path]:
    heights = elevation_array(24, 20, seed=5)
    image = np.linspace(0.05, 0.25, 24 * 20, dtype=np.float32).reshape(24, 20)
    eqc = Affine(1.0, 0, 6123456.0, 0, -1.0, -563210.0)
    sinu = Affine(50.0, 0, 4150000.0, 0, -50.0, -1000000.0)
    return {"dtm": write_raster(root / "dtm.tif", heights, CRS_EQUIRECTANGULAR, eqc),
            "ortho": write_raster(root / "ortho.tif", image, CRS_EQUIRECTANGULAR, eqc),
            "hrsc_dtm": write_raster(root / "h_dtm.tif", heights, SINUSOIDAL, sinu)}


def _make_everything_dated(root: Path, inputs: dict[str, Path]) -> dict[str, bytes]:
    """The products that carry a day of making - an iMars DTM (ProcessingDate, the footprint
    .dbf header), a delivery as PDS3 volume and PDS4 bundle (publication dates, citation
    years, index creation times), its review page, a migrated volume - as {path: bytes}."""
    hirise = ["--profile", "hirise"]
    commands = [
        ["dtm", str(inputs["hrsc_dtm"]), "-o", "out/imars", "--profile", "imars", "--product-id", "h1234_0000"],
        ["dtm", str(inputs["dtm"]), "-o", "out/hirise", *hirise, "--source-product-id", "PSP_008669_1705",
         "--source-product-id", "PSP_009025_1705", "--institution", "U", "--label", "both"],
        ["ortho", str(inputs["ortho"]), "-o", "out/hirise", *hirise, "--observation-id", "PSP_008669_1705",
         "--label", "both"],
        ["deliver", "out/hirise", "-o", "out/delivery", "--label", "both", "--volume-id", "PDSGEN_0001",
         "--bundle-lid", "urn:nasa:pds:pdsgen_test"],
        ["review", "out/delivery"],
        ["deliver", "out/hirise", "-o", "out/volume", "--label", "pds3", "--volume-id", "PDSGEN_0002"],
        ["migrate", "out/volume", "-o", "out/bundle", "--bundle-lid", "urn:nasa:pds:pdsgen_migrated"],
    ]
    root.mkdir(parents=True, exist_ok=True)
    here = os.getcwd()
    os.chdir(root)  # the commands as a user types them, with paths relative to the work directory
    try:
        for command in commands:
            done = CliRunner().invoke(main, [*command, "-q"], catch_exceptions=False)
            assert done.exit_code == 0, f"pdsgen {' '.join(command)}: {done.output}"
    finally:
        os.chdir(here)
    out = root / "out"
    return {p.relative_to(out).as_posix(): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return _inputs(tmp_path_factory.mktemp("inputs"))


def test_the_same_input_makes_the_same_bytes_a_day_and_a_year_later(tmp_path, inputs, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(EPOCH))
    made = []
    for shift in (0, DAY, 366 * DAY):
        with monkeypatch.context() as moved:
            _moved_clock(moved, shift)
            made.append(_make_everything_dated(tmp_path / f"moved_{shift}", inputs))
    assert made[0].keys() == made[1].keys() == made[2].keys()
    assert any(name.endswith(".dbf") for name in made[0]) and any("VOLDESC" in n for n in made[0])
    differing = sorted(name for name in made[0] if not made[0][name] == made[1][name] == made[2][name])
    assert differing == []


def test_without_source_date_epoch_the_moved_clock_reaches_the_products(tmp_path, inputs, monkeypatch):
    """The control for the test above: the in-process clock move is what pdsgen reads."""
    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    later = 3 * 366 * DAY
    with monkeypatch.context() as moved:
        _moved_clock(moved, later)
        made = _make_everything_dated(tmp_path, inputs)
    day = dt.datetime.fromtimestamp(time.time() + later, dt.timezone.utc).date()
    dbf = next(content for name, content in made.items() if name.endswith(".dbf"))
    # dBASE III header: byte 0 the version, bytes 1-3 the date of last update (year - 1900, month, day).
    assert tuple(dbf[1:4]) == (day.year - 1900, day.month, day.day)
    assert day.isoformat().encode() in made["delivery/VOLDESC.CAT"]


def test_the_dbf_header_states_the_day_of_source_date_epoch(tmp_path, inputs, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(EPOCH))
    made = _make_everything_dated(tmp_path, inputs)
    dbf = next(content for name, content in made.items() if name.endswith(".dbf"))
    assert dbf[0] == 3 and tuple(dbf[1:4]) == (2023 - 1900, 11, 14)
    assert b"2023-11-14" in made["delivery/VOLDESC.CAT"]


@pytest.mark.parametrize("value", ["abc", "-5", "1e9", "17000000000000000", " 12 34", "١٢٣"])
def test_a_malformed_source_date_epoch_is_refused_in_one_line(value, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", value)
    with pytest.raises(ParamsError, match="SOURCE_DATE_EPOCH"):
        clock.now()


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(st.text(st.characters(blacklist_characters="\x00"), max_size=40)
       | st.integers(min_value=-10**30, max_value=10**30).map(str))
@example("253402300799")
@example("253402300800")
@example("0")
def test_any_source_date_epoch_is_a_time_of_making_or_one_refusal(text):
    """The variable is outside input: whatever it holds (an environment variable holds no NUL),
    the clock gives a time within the four-digit years or refuses it in one line naming it -
    never another exception."""
    os.environ["SOURCE_DATE_EPOCH"] = text
    try:
        made = clock.now()
    except ParamsError as refused:
        assert str(refused).startswith("SOURCE_DATE_EPOCH=") and "\n" not in str(refused)
    else:
        assert text.strip() == "" or made.timestamp() == int(text)
        assert made.year <= 9999
    finally:
        del os.environ["SOURCE_DATE_EPOCH"]


def test_a_malformed_source_date_epoch_is_exit_2_at_the_command_line(tmp_path, inputs, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "yesterday")
    done = CliRunner().invoke(main, ["dtm", str(inputs["hrsc_dtm"]), "-o", str(tmp_path / "imars"),
                                     "--profile", "imars", "--product-id", "h1234_0000"])
    assert done.exit_code == 2
    assert "SOURCE_DATE_EPOCH='yesterday' is not a whole number of seconds" in done.output
    assert not (tmp_path / "imars").exists() or not any((tmp_path / "imars").iterdir())


def test_a_file_time_after_the_epoch_is_clamped_to_it(monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(EPOCH))
    assert clock.no_later_than_epoch(EPOCH + 5000).timestamp() == EPOCH
    assert clock.no_later_than_epoch(EPOCH - 5000.7).timestamp() == EPOCH - 5001
    monkeypatch.delenv("SOURCE_DATE_EPOCH")
    assert clock.no_later_than_epoch(EPOCH + 5000).timestamp() == EPOCH + 5000


# The readers of the wall clock that give a date; pdsgen/clock.py is their one user.
_WALL_CLOCK_CALLS = {"now", "today", "utcnow", "utcfromtimestamp", "localtime", "gmtime", "ctime", "asctime"}
_WALL_CLOCK_MODULE_CALLS = {("time", "strftime")}


def _wall_clock_reads(path: Path) -> list[str]:
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
            continue
        receiver = node.func.value
        owner = receiver.id if isinstance(receiver, ast.Name) else getattr(receiver, "attr", "")
        if owner == "clock":
            continue
        if node.func.attr in _WALL_CLOCK_CALLS or (owner, node.func.attr) in _WALL_CLOCK_MODULE_CALLS:
            found.append(f"{path.relative_to(SRC)}:{node.lineno} {owner}.{node.func.attr}()")
    return found


def test_only_the_clock_reads_the_wall_clock_for_a_date():
    reads = [read for path in sorted(SRC.rglob("*.py")) if path.name != "clock.py" for read in _wall_clock_reads(path)]
    assert reads == []
