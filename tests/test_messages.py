"""Each interface speaks its own words: the library's errors name Python parameters
(`product_id`, `overwrite=True`), the command line's name its options (--product-id,
--overwrite), translated by the one table in pdsgen.cli._messages."""

from __future__ import annotations

import re
from pathlib import Path

import click
import numpy as np
import pytest
from affine import Affine

from pdsgen import write_dtm
from pdsgen.cli import COMMANDS, main
from pdsgen.cli._messages import LIBRARY_TO_OPTION, in_cli_words
from pdsgen.errors import PdsgenError, param
from pdsgen.extras import make_extras
from test_extras_helpers import crater_field, write_geotiff

from helpers import elevation_array, run_cli, write_raster

SRC = Path(__file__).resolve().parent.parent / "src" / "pdsgen"
EQC = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs"
GRID = Affine(1.0, 0, 1000.0, 0, -1.0, 2000.0)
PYTHON_REFERENCE = re.compile(r"`[a-z_]+(=[^`]*)?`")


def _one_line_error(result) -> str:
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr, result.stderr
    assert not PYTHON_REFERENCE.search(result.stderr), result.stderr
    return result.stderr


@pytest.fixture
def heights(tmp_path):
    return write_raster(tmp_path / "in.tif", elevation_array(20, 16, seed=2), EQC, GRID)


def test_missing_product_id_names_the_parameter_in_python_and_the_option_on_the_command_line(tmp_path):
    source = write_raster(tmp_path / "___.tif", elevation_array(20, 16), EQC, GRID)
    with pytest.raises(PdsgenError) as raised:
        write_dtm(source, tmp_path / "api")
    assert str(raised.value).endswith("give `product_id`") and "--" not in str(raised.value)
    stderr = _one_line_error(run_cli("dtm", source, "-o", tmp_path / "cli"))
    assert stderr.rstrip().endswith("give --product-id")
    assert not (tmp_path / "cli").exists() or not list((tmp_path / "cli").iterdir())


def test_hirise_source_ids_and_institution_in_each_interfaces_words(tmp_path, heights):
    with pytest.raises(PdsgenError, match=r"two `source_product_ids` \(got 1\); or give `product_id`$"):
        write_dtm(heights, tmp_path / "api", profile="hirise", source_product_ids=["PSP_001_002"],
                  institution="U")
    stderr = _one_line_error(run_cli("dtm", heights, "-o", tmp_path / "cli", "--profile", "hirise",
                                     "--source-product-id", "PSP_001_002", "--institution", "U"))
    assert "two --source-product-id (got 1); or give --product-id" in stderr


def test_an_existing_output_asks_for_overwrite_true_or_the_overwrite_flag(tmp_path, heights):
    write_dtm(heights, tmp_path / "out", product_id="ONE")
    with pytest.raises(PdsgenError, match=r"use `overwrite=True` to replace it$"):
        write_dtm(heights, tmp_path / "out", product_id="ONE")
    stderr = _one_line_error(run_cli("dtm", heights, "-o", tmp_path / "out", "--product-id", "ONE"))
    assert stderr.rstrip().endswith("use --overwrite to replace it")


def test_hrsc_reproject_and_areoid_options(tmp_path, heights):
    with pytest.raises(PdsgenError, match=r"rerun with `reproject_input=True`$"):
        write_dtm(heights, tmp_path / "api", profile="hrsc", product_id="h0001_0000")
    stderr = _one_line_error(run_cli("dtm", heights, "-o", tmp_path / "cli", "--profile", "hrsc",
                                     "--product-id", "h0001_0000"))
    assert stderr.rstrip().endswith("rerun with --reproject")
    with pytest.raises(PdsgenError, match=r"give an areoid raster as `areoid` to convert, or "
                                          r"`vertical_datum='sphere'`$"):
        write_dtm(heights, tmp_path / "api", profile="hrsc", product_id="h0001_0000", kind="dt4",
                  vertical_datum="areoid", reproject_input=True)
    stderr = _one_line_error(run_cli("dtm", heights, "-o", tmp_path / "cli", "--profile", "hrsc",
                                     "--product-id", "h0001_0000", "--vertical-datum", "areoid", "--reproject"))
    assert "give an areoid raster as --areoid to convert, or --vertical-datum sphere" in stderr


def test_extras_that_cannot_tell_the_kind_ask_for_kind(tmp_path):
    values = (crater_field(40, 50) + 4500.0).astype(np.float32)  # neither reflectance nor below zero
    tif = write_geotiff(tmp_path / "unknown.tif", values)
    with pytest.raises(PdsgenError, match=r"give `kind='dtm'` or `kind='ortho'`$"):
        make_extras([tif], tmp_path / "api")
    stderr = _one_line_error(run_cli("extras", tif, "-o", tmp_path / "cli"))
    assert stderr.rstrip().endswith("give --kind dtm or --kind ortho") and "unknown.tif" in stderr


def test_references_become_options_with_their_values():
    assert in_cli_words(f"give {param('product_id')}") == "give --product-id"
    assert in_cli_words(f"use {param('overwrite', True)}") == "use --overwrite"
    assert in_cli_words(f"use {param('label', 'both')}") == "use --label both"
    assert in_cli_words(f"{param('value_range')} needs MIN < MAX") == "--range needs MIN < MAX"
    assert in_cli_words(f"{param('bits', 12)} does not apply") == "--bits 12 does not apply"
    # text in back-quotes that is no parameter of the command line is left as written
    assert in_cli_words("the label says `END`") == "the label says `END`"


def _library_references() -> set[str]:
    """Every parameter name a library message passes to param(), read from the source."""
    names = set()
    for path in SRC.rglob("*.py"):
        if "cli" in path.relative_to(SRC).parts:
            continue
        names |= set(re.findall(r"""\bparam\(\s*["']([a-z_]+)["']""", path.read_text()))
    return names


def _command_options() -> set[str]:
    options = set()
    for name in COMMANDS:
        command = main.get_command(click.Context(main), name)
        assert command is not None
        options |= {opt for p in command.params if isinstance(p, click.Option) for opt in p.opts}
    return options


def test_the_table_covers_every_parameter_a_message_names_and_each_option_exists():
    referenced = _library_references()
    assert {"product_id", "overwrite", "kind", "reproject_input"} <= referenced  # the scan finds them
    assert referenced <= set(LIBRARY_TO_OPTION), referenced - set(LIBRARY_TO_OPTION)
    options = _command_options()
    assert set(LIBRARY_TO_OPTION.values()) <= options, set(LIBRARY_TO_OPTION.values()) - options


# Text that rightly names options: the validator's findings and rule notes (reports
# read alike by both interfaces, about `pdsgen validate`), the shell command the demo
# prints for the user to run, and a Dask worker's own --resources option.
NAMES_OPTIONS_ON_PURPOSE = ("cli", "validate", "pds4/rules.py", "validate/pds4/label_checks.py",
                            "validate/pds4/catalog.py", "demo.py", "batch/cluster.py")


def test_library_messages_name_no_command_line_options():
    """No string in the library outside the places above names a --flag."""
    offenders = []
    for path in SRC.rglob("*.py"):
        relative = path.relative_to(SRC).as_posix()
        if any(relative == place or relative.startswith(place + "/") for place in NAMES_OPTIONS_ON_PURPOSE):
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            code = line.split("#")[0]
            if re.search(r"""["'][^"']*--[a-z]""", code) and not code.strip().startswith(("\"\"\"", "`")):
                offenders.append(f"{path.relative_to(SRC)}:{number}: {line.strip()}")
    assert offenders == []
