"""Issue 10: every user mistake, run through a real `python -m pdsgen`, is one line on stderr
naming the file (or option) and the problem, exit code 2, and nothing written."""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys

import numpy as np
import pytest

from helpers import CRS_EQUIRECTANGULAR, ORIGINS, elevation_array, run_cli, write_raster

TRANSFORM = ORIGINS["equirectangular"][1]
BAD_IDS = ["ESP 011", 'ESP"011', "ESP\n011", "ESPé011"]


def _one_line_error(result, needle: str, outdir=None) -> None:
    assert result.returncode == 2, result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr  # no warning lines, no traceback
    assert lines[0].startswith("pdsgen: error:") and needle in lines[0], lines[0]
    assert "See previous exception" not in lines[0] and "Error(" not in lines[0]
    if outdir is not None and os.path.isdir(outdir):
        assert os.listdir(outdir) == []


def _dtm_input(tmp_path, lines=64):
    return write_raster(tmp_path / "dtm.tif", elevation_array(lines, 64), CRS_EQUIRECTANGULAR, TRANSFORM)


def _image_input(tmp_path, lines=64):
    data = np.random.default_rng(1).integers(0, 256, (lines, 256), dtype="uint8")  # incompressible
    return write_raster(tmp_path / "image.tif", data, CRS_EQUIRECTANGULAR, TRANSFORM)


@pytest.mark.parametrize("command, make", [("dtm", _dtm_input), ("ortho", _image_input)])
def test_truncated_geotiff(tmp_path, command, make):
    source = make(tmp_path, lines=256)
    data = source.read_bytes()
    source.write_bytes(data[: len(data) // 2])
    result = run_cli(command, source, "-o", tmp_path / "out")
    _one_line_error(result, f"{source.name}: cannot read the raster data", tmp_path / "out")


@pytest.mark.parametrize("bad", BAD_IDS)
def test_bad_source_product_id_refused(tmp_path, bad):
    result = run_cli("dtm", _dtm_input(tmp_path), "-o", tmp_path / "out", "--source-product-id", bad)
    _one_line_error(result, "--source-product-id", tmp_path / "out")


@pytest.mark.parametrize("bad", BAD_IDS[1:3])
def test_bad_source_dtm_id_refused(tmp_path, bad):
    result = run_cli("ortho", _image_input(tmp_path), "-o", tmp_path / "out", "--source-dtm-id", bad)
    _one_line_error(result, "--source-dtm-id", tmp_path / "out")


def test_params_value_of_wrong_type(tmp_path):
    params = tmp_path / "params.toml"
    params.write_text("source_product_id = 5\n")
    result = run_cli("dtm", _dtm_input(tmp_path), "-o", tmp_path / "out", "--params", params)
    _one_line_error(result, "params.toml: SOURCE_PRODUCT_ID must be product identifiers", tmp_path / "out")


def test_long_unbreakable_word_in_free_text(tmp_path):
    params = tmp_path / "params.toml"
    params.write_text(f'rationale_desc = "see https://example.org/{"x" * 120}"\n')
    result = run_cli("dtm", _dtm_input(tmp_path), "-o", tmp_path / "out", "--params", params)
    _one_line_error(result, "RATIONALE_DESC", tmp_path / "out")


@pytest.mark.parametrize("command", ["ortho", "extras"])
def test_no_georeferencing_gives_no_library_warning(tmp_path, command):
    plain = tmp_path / "plain.tif"
    import rasterio

    with rasterio.open(plain, "w", driver="GTiff", width=8, height=8, count=1, dtype="uint8") as dataset:
        dataset.write(np.ones((1, 8, 8), "uint8"))
    result = run_cli(command, plain, "-o", tmp_path / "out")
    _one_line_error(result, "plain.tif:", tmp_path / "out")


@pytest.mark.parametrize("command, make", [("dtm", _dtm_input), ("ortho", _image_input)])
def test_full_disk(tmp_path, command, make):
    """A 64 KiB tmpfs in a private mount namespace (root only): the product does not fit."""
    if os.geteuid() != 0 or shutil.which("unshare") is None:
        pytest.skip("a full file system is made with unshare -m and a small tmpfs, as root")
    source = make(tmp_path, lines=512)
    full = tmp_path / "full"
    full.mkdir()
    run = [sys.executable, "-m", "pdsgen", command, str(source), "-o", str(full / "out")]
    script = (f"mount -t tmpfs -o size=64k tmpfs {shlex.quote(str(full))} && "
              f"{shlex.join(run)}; status=$?; ls -A {shlex.quote(str(full / 'out'))} >&3; exit $status")
    result = subprocess.run(["unshare", "-m", "sh", "-c", f"exec 3>{shlex.quote(str(tmp_path / 'left'))}; "
                             + script], capture_output=True, text=True, timeout=300)
    if "mount:" in result.stderr or "unshare:" in result.stderr:
        pytest.skip(f"cannot mount a small tmpfs here: {result.stderr.strip()}")
    _one_line_error(result, "no space left on device")
    assert (tmp_path / "left").read_text() == ""  # no temporary or partial file left behind
