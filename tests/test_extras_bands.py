"""Band counts: a DTM has exactly one band, an orthoimage one or three."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.errors import PdsgenError
from pdsgen.extras import make_extras
from test_extras_helpers import crater_field, write_geotiff


def stack(n: int, dtype: str) -> np.ndarray:
    return np.stack([crater_field(40, 50, seed=i) for i in range(n)]).astype(dtype)


@pytest.mark.parametrize("bands, dtype, kind", [
    (2, "float32", None), (2, "uint8", None), (4, "uint8", None), (2, "uint8", "ortho"),
    (3, "uint8", "dtm"), (2, "float32", "dtm"),
])
def test_wrong_band_count_is_refused_naming_the_file(tmp_path: Path, bands, dtype, kind):
    (tmp_path / "in").mkdir()
    tif = write_geotiff(tmp_path / "in" / "multi.tif", stack(bands, dtype))
    good = write_geotiff(tmp_path / "in" / "good.tif", crater_field(40, 50))
    with pytest.raises(PdsgenError, match=f"has {bands} bands") as err:
        make_extras([good, tif], tmp_path / "out", kind=kind)
    assert str(err.value.path) == str(tif)
    assert not (tmp_path / "out").exists()
    args = ["extras", str(good), str(tif), "-o", str(tmp_path / "cli")]
    result = CliRunner().invoke(main, args + (["--kind", kind] if kind else []))
    assert result.exit_code == 2 and result.stderr.count("\n") == 1
    assert "multi.tif" in result.stderr and "Traceback" not in result.output
    assert not (tmp_path / "cli").exists() or not any((tmp_path / "cli").iterdir())


def test_one_and_three_band_orthoimages_and_one_band_dtm_are_accepted(tmp_path: Path):
    (tmp_path / "in").mkdir()
    products = [write_geotiff(tmp_path / "in" / "grey.tif", stack(1, "uint8")[0]),
                write_geotiff(tmp_path / "in" / "rgb.tif", stack(3, "uint8")),
                write_geotiff(tmp_path / "in" / "dtm.tif", crater_field(40, 50))]
    written = make_extras(products, tmp_path / "out")
    assert {"grey.browse.jpg", "rgb.browse.jpg", "dtm.cb.jpg"} <= {p.name for p in written}
