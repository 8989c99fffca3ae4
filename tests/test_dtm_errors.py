"""User mistakes: one line on stderr naming the file, exit code 2, nothing written."""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys

import numpy as np
import pytest
from affine import Affine

from helpers import CRS_EQUIRECTANGULAR, ORIGINS, elevation_array, run_cli, write_raster

MERCATOR = "+proj=merc +lon_0=0 +k=1 +R=3396190 +units=m +no_defs"


def _assert_user_error(result, needle: str, outdir) -> None:
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("pdsgen: error:")
    assert needle in lines[0]
    assert "Traceback" not in result.stderr
    if os.path.isdir(outdir):
        assert [name for name in os.listdir(outdir) if not name.startswith("keep")] == []


def test_missing_file(tmp_path):
    result = run_cli("dtm", tmp_path / "nope.tif", "-o", tmp_path / "out")
    _assert_user_error(result, "nope.tif: no such file", tmp_path / "out")


def test_not_a_raster(tmp_path):
    bogus = tmp_path / "notes.tif"
    bogus.write_text("hello")
    result = run_cli("dtm", bogus, "-o", tmp_path / "out")
    _assert_user_error(result, "notes.tif: not a raster GDAL can read", tmp_path / "out")


def test_no_crs(tmp_path):
    source = write_raster(tmp_path / "nocrs.tif", elevation_array(10, 10), None, Affine(1, 0, 0, 0, -1, 0))
    result = run_cli("dtm", source, "-o", tmp_path / "out")
    _assert_user_error(result, "no coordinate reference system", tmp_path / "out")


def test_unsupported_projection(tmp_path):
    source = write_raster(tmp_path / "merc.tif", elevation_array(10, 10), MERCATOR, Affine(1, 0, 0, 0, -1, 0))
    result = run_cli("dtm", source, "-o", tmp_path / "out")
    _assert_user_error(result, "unsupported map projection", tmp_path / "out")


def test_multiband(tmp_path):
    data = np.stack([elevation_array(10, 10), elevation_array(10, 10)])
    source = write_raster(tmp_path / "two.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1])
    result = run_cli("dtm", source, "-o", tmp_path / "out")
    _assert_user_error(result, "has 2 bands", tmp_path / "out")


def test_all_nodata(tmp_path):
    data = np.full((10, 10), -9999.0, dtype=np.float32)
    source = write_raster(tmp_path / "empty.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1],
                          nodata=-9999.0)
    result = run_cli("dtm", source, "-o", tmp_path / "out")
    _assert_user_error(result, "no valid pixels", tmp_path / "out")


def test_existing_output_needs_overwrite(tmp_path):
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), CRS_EQUIRECTANGULAR,
                          ORIGINS["equirectangular"][1])
    outdir = tmp_path / "out"
    outdir.mkdir()
    existing = outdir / "keep.IMG"
    existing.write_bytes(b"previous delivery")
    result = run_cli("dtm", source, "-o", outdir, "--product-id", "keep")
    _assert_user_error(result, "output exists; use --overwrite", outdir)
    assert existing.read_bytes() == b"previous delivery"
    again = run_cli("dtm", source, "-o", outdir, "--product-id", "keep", "--overwrite")
    assert again.returncode == 0, again.stderr
    assert existing.read_bytes().startswith(b"PDS_VERSION_ID = PDS3\r\n")


def test_unwritable_outdir(tmp_path):
    """As a user: a mode-0500 directory. As root (CI): a read-only mount in a private namespace."""
    outdir = tmp_path / "locked"
    outdir.mkdir()
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), CRS_EQUIRECTANGULAR,
                          ORIGINS["equirectangular"][1])
    command = [sys.executable, "-m", "pdsgen", "dtm", str(source), "-o", str(outdir)]
    if os.geteuid() != 0:
        outdir.chmod(0o500)
    else:
        if shutil.which("unshare") is None:
            pytest.skip("unshare is not available to make a read-only directory as root")
        mount = f"mount -t tmpfs -o ro,size=1m tmpfs {shlex.quote(str(outdir))}"
        command = ["unshare", "-m", "sh", "-c", f"{mount} && exec {shlex.join(command)}"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    if "mount:" in result.stderr or "unshare:" in result.stderr:
        pytest.skip(f"cannot make a read-only directory here: {result.stderr.strip()}")
    _assert_user_error(result, "not writable", outdir)


def test_outdir_is_a_file(tmp_path):
    blocker = tmp_path / "blocker"
    blocker.write_text("")
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), CRS_EQUIRECTANGULAR,
                          ORIGINS["equirectangular"][1])
    result = run_cli("dtm", source, "-o", blocker / "out")
    _assert_user_error(result, "cannot create output directory", blocker / "out")


def test_hirise_profile_refuses_unencodable_version(tmp_path):
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), CRS_EQUIRECTANGULAR,
                          ORIGINS["equirectangular"][1])
    result = run_cli("dtm", source, "-o", tmp_path / "out", "--profile", "hirise", "--institution", "U",
                     "--source-product-id", "PSP_008669_1705", "--source-product-id", "PSP_009025_1705",
                     "--version", "10.5")
    _assert_user_error(result, "cannot be encoded", tmp_path / "out")


def test_bad_params_file(tmp_path):
    params = tmp_path / "params.pvl"
    params.write_text('PRODUCER_FULL_NAM = "Typo"\nEND\n')
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), CRS_EQUIRECTANGULAR,
                          ORIGINS["equirectangular"][1])
    result = run_cli("dtm", source, "-o", tmp_path / "out", "--params", params)
    _assert_user_error(result, "unknown keyword PRODUCER_FULL_NAM", tmp_path / "out")


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--profile", "generic", "--precision", "2"], "--precision does not apply to --profile generic"),
        (["--profile", "hirise", "--reproject"], "--reproject does not apply to --profile hirise"),
        (["--profile", "hrsc", "--product-id", "h0001_0000", "--institution", "U"],
         "--institution does not apply to --profile hrsc"),
        (["--profile", "imars", "--product-id", "h0001_0000", "--byte-order", "msb"],
         "--byte-order does not apply to --profile imars"),
        (["--version", ""], "product version must look like 1.0"),
    ],
)
def test_options_a_profile_does_not_use_are_refused(tmp_path, args, needle):
    source = write_raster(tmp_path / "in.tif", elevation_array(10, 10), CRS_EQUIRECTANGULAR,
                          ORIGINS["equirectangular"][1])
    result = run_cli("dtm", source, "-o", tmp_path / "out", *args)
    _assert_user_error(result, needle, tmp_path / "out")


def test_raster_beyond_the_body_is_refused(tmp_path):
    source = write_raster(tmp_path / "far.tif", elevation_array(10, 10), CRS_EQUIRECTANGULAR,
                          Affine(1.0, 0, 0.0, 0, -1.0, 1e9))
    result = run_cli("dtm", source, "-o", tmp_path / "out")
    _assert_user_error(result, "extends beyond the body", tmp_path / "out")


def test_float64_values_beyond_float32_are_refused(tmp_path):
    data = elevation_array(10, 10, dtype="float64")
    data[4, 4] = 1e39
    source = write_raster(tmp_path / "wide.tif", data, CRS_EQUIRECTANGULAR, ORIGINS["equirectangular"][1])
    result = run_cli("dtm", source, "-o", tmp_path / "out")
    _assert_user_error(result, "beyond the 32-bit float range", tmp_path / "out")
