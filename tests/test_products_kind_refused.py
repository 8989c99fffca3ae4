"""`pdsgen dtm` of an image and `pdsgen ortho` of heights are refused in one line naming
--any-kind, the Extras' own kind decision telling which (formats/kind.py, one home); the
flag makes the product anyway, and the inputs each command is for still pass."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio
from click.testing import CliRunner

from pdsgen.cli import main

from helpers import ORIGINS, elevation_array, write_raster


@pytest.fixture(scope="module")
def rasters(tmp_path_factory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("kinds")
    crs, transform = ORIGINS["equirectangular"]
    ramp = np.linspace(0, 1, 48 * 40).reshape(48, 40)
    return {
        "image8": write_raster(folder / "image8.tif", (ramp * 200 + 20).astype(np.uint8), crs, transform),
        "reflectance": write_raster(folder / "iof.tif", (ramp * 0.3).astype(np.float32), crs, transform),
        "heights": write_raster(folder / "heights.tif", elevation_array(48, 40), crs, transform),
        "heights16": write_raster(folder / "mola.tif", elevation_array(48, 40, dtype="int16"), crs, transform),
    }


def _run(*args: object):
    return CliRunner().invoke(main, [str(a) for a in args])


@pytest.mark.parametrize(("command", "raster", "looks_like"), [
    ("dtm", "image8", "an orthoimage"), ("dtm", "reflectance", "an orthoimage"), ("ortho", "heights", "a DTM"),
])
def test_the_other_kind_is_refused_in_one_line_naming_the_override(command, raster, looks_like, rasters, tmp_path):
    refused = _run(command, rasters[raster], "-o", tmp_path / "out")
    assert refused.exit_code == 2
    (line,) = refused.stderr.splitlines()
    wanted = "a DTM" if command == "dtm" else "an orthoimage"
    assert line.startswith(f"pdsgen: error: {rasters[raster]}: looks like {looks_like}, not {wanted} (")
    assert line.endswith(f"give --any-kind to make {wanted} of it anyway")
    assert not (tmp_path / "out").exists()  # refused before any output

    made = _run(command, rasters[raster], "-o", tmp_path / "out", "--any-kind", "-q")
    assert made.exit_code == 0, made.output
    written = sorted((tmp_path / "out").iterdir())
    with rasterio.open(written[0]) as product:  # GDAL reads the product made anyway
        assert (product.height, product.width) == (48, 40)


@pytest.mark.parametrize(("command", "raster"), [("dtm", "heights"), ("dtm", "heights16"), ("ortho", "image8"),
                                                ("ortho", "reflectance")])
def test_each_command_takes_its_own_kind(command, raster, rasters, tmp_path):
    made = _run(command, rasters[raster], "-o", tmp_path / "out", "-q")
    assert made.exit_code == 0, made.output


def test_the_decision_has_one_home():
    """The Extras and the writers decide with the same function; extras/ keeps no copy."""
    from pdsgen.extras import product_source
    from pdsgen.formats import kind
    from pdsgen.products import opening

    assert product_source.decide_kind is kind.decide_kind is opening.decide_kind
    source = Path(kind.__file__).parents[1]
    assert not (source / "extras" / "kind.py").exists()
    assert "def decide_kind" not in (source / "extras" / "product_source.py").read_text()
