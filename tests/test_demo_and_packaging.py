"""The demo end to end, the CLI surface, and what a built wheel ships."""

from __future__ import annotations

import json
import os
import shlex
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pvl
import rasterio

from pdsgen import __version__

from helpers import run_cli


def test_demo_writes_inputs_and_a_dtm_gdal_reads(tmp_path):
    """Through the CLI with --json: the summary names files that exist, with their sizes."""
    run = run_cli("demo", tmp_path / "demo", "--json")
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    files = [Path(entry["path"]) for entry in summary["files"] + summary["inputs"]]
    assert all(path.stat().st_size == entry["bytes"]
               for path, entry in zip(files, summary["files"] + summary["inputs"], strict=True))
    dtm = next(p for p in files if p.suffix == ".IMG")
    assert dtm.name == "DTEEC_008669_1705_009025_1705_U01.IMG"
    with rasterio.open(tmp_path / "demo" / "input" / "demo_dtm.tif") as src, rasterio.open(dtm) as out:
        assert (out.width, out.height) == (2000, 3000)
        assert out.transform.almost_equals(src.transform, precision=1e-9)
        source = src.read(1)
        written = out.read(1)
    valid = np.isfinite(source)
    assert 0.001 < (~valid).mean() < 0.2  # the demo has real nodata holes
    assert np.array_equal(written[valid], source[valid])
    assert summary["checks"]["exit_code"] == 0 and summary["checks"]["validate"].endswith("OK")
    label = pvl.load(str(dtm))  # HiRISE states the valid range to two decimals, rounded outwards
    low, high = float(source[valid].min()), float(source[valid].max())
    assert low - 0.01 < label["IMAGE"]["VALID_MINIMUM"] <= low and high <= label["IMAGE"]["VALID_MAXIMUM"] < high + 0.01
    assert f"{label['IMAGE']['VALID_MINIMUM']:.2f}" in dtm.read_bytes()[:20000].decode("ascii", "replace")


def test_demo_summary_names_paths_that_exist_and_a_validate_command_that_runs(tmp_path):
    """As a user reads it: each path in the summary exists, sizes are lines x samples, and
    the CHECK line's command runs as printed (from the same directory; quoted for the shell)."""
    outdir = Path("a demo") / "out"  # relative, nested, with a space
    run = subprocess.run([sys.executable, "-m", "pdsgen", "demo", str(outdir)], capture_output=True, text=True,
                         cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    lines = {line.split()[0]: line for line in run.stdout.splitlines()}
    dtm_path = lines["DTM"].split(maxsplit=1)[1].split(": ")[0]
    jp2_path = lines["ORTHO"].split(maxsplit=1)[1].split(" + ")[0]
    extras_dir = lines["EXTRAS"].split(" in ", 1)[1].split("/ (")[0]
    for path in (dtm_path, jp2_path, extras_dir):
        assert (tmp_path / path).exists(), path
    with rasterio.open(tmp_path / dtm_path) as dtm:
        assert f": {dtm.height} x {dtm.width} posts (lines x samples)" in lines["DTM"]
    command = shlex.split(lines["CHECK"].split(maxsplit=1)[1].rsplit(": ", 2)[0])
    assert command[:3] == ["pdsgen", "validate", "--strict"]
    check = subprocess.run([sys.executable, "-m", "pdsgen", *command[1:]], capture_output=True, text=True,
                           cwd=tmp_path)
    assert check.returncode == 0 and "2 file(s) checked" in check.stdout, check.stdout + check.stderr


def test_cli_help_version_and_every_listed_command_has_help():
    top = run_cli("--help")
    assert top.returncode == 0
    commands = [line.split()[0] for line in top.stdout.split("Commands:")[1].strip().splitlines()]
    assert {"dtm", "demo"} <= set(commands)
    for command in commands:
        assert run_cli(command, "--help").returncode == 0, command
    version = run_cli("--version")
    assert version.returncode == 0 and __version__ in version.stdout


def test_unknown_command_is_a_usage_error():
    result = run_cli("frobnicate")
    assert result.returncode == 2
    assert "No such command" in result.stderr


def test_wheel_ships_templates_and_schemas(tmp_path):
    repo = __import__("pathlib").Path(__file__).resolve().parents[1]
    build = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(tmp_path),
         str(repo)],
        capture_output=True, text=True, timeout=300,
    )
    assert build.returncode == 0, build.stderr
    wheel = next(tmp_path.glob("pdsgen-*.whl"))
    names = set(zipfile.ZipFile(wheel).namelist())
    assert "pdsgen/templates/dtm.lbl.j2" in names
    assert "pdsgen/schemas/params.toml" in names
    assert "pdsgen/cli/__init__.py" in names


def test_shell_completion_script_and_completions():
    """The README's `eval "$(_PDSGEN_COMPLETE=bash_source pdsgen)"` gets a real bash script,
    and that script's callback completes commands and option choices."""
    env = {**os.environ, "_PDSGEN_COMPLETE": "bash_source"}
    script = subprocess.run([sys.executable, "-m", "pdsgen"], env=env, capture_output=True, text=True, timeout=60)
    assert script.returncode == 0, script.stderr
    assert "complete -o nosort -F _pdsgen_completion pdsgen" in script.stdout
    syntax = subprocess.run(["bash", "-n"], input=script.stdout, capture_output=True, text=True, timeout=60)
    assert syntax.returncode == 0, syntax.stderr

    def complete(words: str) -> list[str]:
        env = {**os.environ, "_PDSGEN_COMPLETE": "bash_complete", "COMP_WORDS": words,
               "COMP_CWORD": str(len(words.split()) - (0 if words.endswith(" ") else 1))}
        run = subprocess.run([sys.executable, "-m", "pdsgen"], env=env, capture_output=True, text=True, timeout=60)
        return [line.split(",", 1)[1] for line in run.stdout.splitlines()]

    assert complete("pdsgen d") == ["deliver", "demo", "dtm"]
    assert complete("pdsgen dtm in.tif --profile ") == ["generic", "hirise", "hrsc", "hrsc-ax", "imars"]
