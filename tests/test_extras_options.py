"""Numeric options of `pdsgen extras`: nan, inf and out-of-range values are user errors."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.errors import PdsgenError
from pdsgen.extras import make_extras
from test_extras_helpers import crater_field, write_geotiff


@pytest.fixture()
def small_dtm(tmp_path: Path) -> Path:
    (tmp_path / "in").mkdir()
    return write_geotiff(tmp_path / "in" / "small.tif", crater_field(60, 80))


@pytest.mark.parametrize("option, value", [
    ("--azimuth", "inf"), ("--azimuth", "-inf"), ("--azimuth", "nan"),
    ("--altitude", "nan"), ("--altitude", "inf"), ("--altitude", "0"), ("--altitude", "91"),
    ("--exaggeration", "nan"), ("--exaggeration", "inf"), ("--exaggeration", "0"),
    ("--browse-width", "8"), ("--thumb-width", "5000"),
])
def test_bad_numeric_option_is_one_line_exit_2_and_nothing_written(small_dtm: Path,
                                                                   tmp_path: Path, option, value):
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["extras", str(small_dtm), "-o", str(out), option, value])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("pdsgen: error: ") and result.stderr.count("\n") == 1
    assert "Traceback" not in result.output and "Warning" not in result.stderr
    assert not out.exists() or not any(out.iterdir())


@pytest.mark.parametrize("width", ["nan", "inf", "12.5"])
def test_non_integer_widths_are_refused(small_dtm: Path, tmp_path: Path, width):
    for option in ("--browse-width", "--thumb-width"):
        result = CliRunner().invoke(main, ["extras", str(small_dtm), "-o", str(tmp_path / "o"),
                                           option, width])
        assert result.exit_code == 2 and "Traceback" not in result.output


@pytest.mark.parametrize("keyword, value", [
    ("browse_width", float("nan")), ("browse_width", float("inf")), ("browse_width", 100.5),
    ("thumb_width", float("nan")), ("thumb_width", True),
    ("azimuth", float("nan")), ("azimuth", float("inf")),
    ("altitude", float("nan")), ("exaggeration", float("-inf")),
])
def test_python_api_refuses_non_finite_and_non_integer_values(small_dtm: Path, tmp_path: Path,
                                                              keyword, value):
    with pytest.raises(PdsgenError):
        make_extras([small_dtm], tmp_path / "out", **{keyword: value})
    assert not (tmp_path / "out").exists()


def test_azimuth_is_normalised_modulo_360(small_dtm: Path, tmp_path: Path):
    result = CliRunner().invoke(main, ["extras", str(small_dtm), "-o", str(tmp_path / "a"),
                                       "--azimuth", "-45"])
    assert result.exit_code == 0, result.output
    text = " ".join((tmp_path / "a" / "README.TXT").read_text().split())
    assert "azimuth 315 degrees" in text
    make_extras([small_dtm], tmp_path / "b", azimuth=675.0)
    assert (tmp_path / "b" / "README.TXT").read_bytes() == (tmp_path / "a" / "README.TXT").read_bytes()
    for code in ("sb", "ca"):
        assert ((tmp_path / "a" / f"small.{code}.jpg").read_bytes()
                == (tmp_path / "b" / f"small.{code}.jpg").read_bytes())
