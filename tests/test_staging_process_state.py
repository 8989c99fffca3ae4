"""Importing or calling the library changes nothing process-wide.

A program that uses pdsgen keeps its environment (GDAL's S3 options are set only while a
raster is open, as rasterio.Env does) and its modules (boto3 is kept from rasterio only by
pdsgen's own processes, and only while a command runs). The `pdsgen` command still sets
OPENBLAS_NUM_THREADS for itself, in its entry point.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from helpers import ORIGINS, elevation_array, write_raster

# GDAL's own words for the S3 settings pdsgen derives from the AWS variables.
GDAL_S3_OPTIONS = ("AWS_S3_ENDPOINT", "AWS_HTTPS", "AWS_VIRTUAL_HOSTING", "AWS_REGION")


def _python(code: str, env: dict[str, str] | None = None) -> str:
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                            env=env if env is not None else dict(os.environ))
    return result.stdout.strip().splitlines()[-1]


def _dtm_source(tmp_path: Path) -> Path:
    crs, transform = ORIGINS["equirectangular"]
    return write_raster(tmp_path / "dtm.tif", elevation_array(24, 20, seed=5), crs, transform)


def test_importing_the_command_line_and_the_library_changes_no_environment_or_module():
    env = {name: value for name, value in os.environ.items() if name != "OPENBLAS_NUM_THREADS"}
    code = ("import os, sys; before = dict(os.environ); "
            "import pdsgen, pdsgen.cli, pdsgen.storage, pdsgen.formats.raster; "
            "print(dict(os.environ) == before, 'boto3' in sys.modules and sys.modules['boto3'] is None)")
    assert _python(code, env) == "True False"


def test_the_command_keeps_blas_to_one_thread_and_boto3_from_rasterio_for_itself(tmp_path):
    """What the entry point `run` does for its own process: OPENBLAS_NUM_THREADS=1 before numpy
    loads, rasterio without boto3; and after the command, no marker left in sys.modules."""
    pytest.importorskip("boto3", reason="without the s3 extra there is no boto3 to keep away")
    source = _dtm_source(tmp_path)
    env = {name: value for name, value in os.environ.items() if name != "OPENBLAS_NUM_THREADS"}
    code = ("import atexit, os, sys, pdsgen.cli as cli\n"
            "def report():\n"
            "    print(os.environ.get('OPENBLAS_NUM_THREADS'), sys.modules['rasterio.session'].boto3 is None, "
            "'boto3' in sys.modules)\n"
            "atexit.register(report)\n"
            f"cli.run(['dtm', {str(source)!r}, '-o', {str(tmp_path / 'out')!r}, '-q'])\n")
    assert _python(code, env) == "1 True False"
    assert (tmp_path / "out" / "DTM.IMG").is_file()


def test_boto3_is_kept_from_rasterio_inside_the_block_only():
    pytest.importorskip("boto3", reason="without the s3 extra there is no boto3 to keep away")
    code = ("import sys\n"
            "from pdsgen.storage.objects import _import_boto3, boto3_kept_from_rasterio\n"
            "assert 'rasterio' not in sys.modules\n"
            "with boto3_kept_from_rasterio():\n"
            "    import rasterio.session\n"
            "    hidden = 'boto3' in sys.modules and sys.modules['boto3'] is None\n"
            "after = 'boto3' in sys.modules\n"
            "with boto3_kept_from_rasterio():\n"
            "    client_module = _import_boto3().__name__\n"
            "print(hidden, rasterio.session.boto3 is None, after, client_module, sys.modules['boto3'] is not None)\n")
    assert _python(code) == "True True False boto3 True"


def test_the_library_leaves_os_environ_and_gdal_as_they_were(s3_server, tmp_path, monkeypatch):
    """Reading a raster from a bucket configures GDAL for that reading only: os.environ and
    GDAL's configuration are the same before and after write_dtm, open_raster and validation."""
    from rasterio.env import get_gdal_config

    import pdsgen
    from pdsgen.formats.raster import open_raster
    from pdsgen.storage import internal
    from pdsgen.validate import validate_file

    for name in GDAL_S3_OPTIONS:  # as in a fresh process, whatever earlier tests did
        monkeypatch.delenv(name, raising=False)
    bucket = s3_server.new_bucket()
    url = s3_server.put(bucket, "in/dtm.tif", _dtm_source(tmp_path).read_bytes())
    before = dict(os.environ)

    with open_raster(url) as dataset:
        assert get_gdal_config("AWS_S3_ENDPOINT") == s3_server.endpoint.removeprefix("http://")
        assert dataset.read(1).shape == (24, 20)
    assert dict(os.environ) == before and get_gdal_config("AWS_S3_ENDPOINT") is None

    pdsgen.write_dtm(internal(url), tmp_path / "out")  # as the command passes it
    assert dict(os.environ) == before and get_gdal_config("AWS_S3_ENDPOINT") is None
    report, _ = validate_file(tmp_path / "out" / "DTM.IMG")
    assert dict(os.environ) == before and not [f for f in report.findings if f.severity == "error"]


def test_a_local_raster_enters_no_gdal_environment(tmp_path, monkeypatch):
    """Without AWS variables nothing is configured: a local product is read as it always was."""
    from rasterio.env import getenv, hasenv

    from pdsgen.formats.raster import open_raster

    for name in [n for n in os.environ if n.startswith("AWS_")]:
        monkeypatch.delenv(name)
    before = dict(os.environ)
    source = _dtm_source(tmp_path)
    with open_raster(source) as dataset:
        options = getenv() if hasenv() else {}
        assert not any(name.startswith("AWS_") for name in options)
        assert np.isfinite(dataset.read(1)).all()
    assert dict(os.environ) == before
