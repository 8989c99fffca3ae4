"""Golden outputs: labels, README.TXT, the rule list and a JSON report, compared byte for byte.

Small synthetic inputs (fixed seeds) go through every writer; the text each one
produces is compared with the copy stored in tests/golden/. A change of any byte
fails here first, so refactoring cannot alter products unnoticed. After an
intended change of output, regenerate with `PDSGEN_UPDATE_GOLDEN=1 make test`
and review the diff of tests/golden/ like any other change.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from affine import Affine

from pdsgen import write_dtm, write_ortho
from pdsgen.extras import make_extras

from helpers import CRS_EQUIRECTANGULAR, elevation_array, write_raster

GOLDEN_DIR = Path(__file__).parent / "golden"
UPDATE = os.environ.get("PDSGEN_UPDATE_GOLDEN") == "1"
SINUSOIDAL_HRSC = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"
SOUTH_POLAR_HRSC = "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs"


def attached_label(path: Path) -> bytes:
    """The attached label of a PDS3 file: every byte up to and including the END line."""
    data = path.read_bytes()
    end = data.index(b"\r\nEND\r\n") + len(b"\r\nEND\r\n")
    return data[:end]


def check_golden(name: str, produced: bytes) -> None:
    golden = GOLDEN_DIR / name
    if UPDATE:
        golden.write_bytes(produced)
    assert golden.is_file(), f"{golden} is missing; run with PDSGEN_UPDATE_GOLDEN=1 to create it"
    assert produced == golden.read_bytes(), f"{name} differs from tests/golden/{name}"


@pytest.fixture(scope="module")
def delivery(tmp_path_factory) -> Path:
    """A HiRISE DTM, its orthoimage and their Extras, written from small fixed inputs."""
    root = tmp_path_factory.mktemp("golden")
    heights = elevation_array(40, 30, seed=5)
    heights[3:5, 4:9] = np.nan
    transform = Affine(1.0, 0, 6123456.0, 0, -1.0, -563210.0)
    dtm_in = write_raster(root / "dtm.tif", heights, CRS_EQUIRECTANGULAR, transform)
    image = np.linspace(0.05, 0.25, 40 * 30, dtype=np.float32).reshape(40, 30)
    ortho_in = write_raster(root / "ortho.tif", image, CRS_EQUIRECTANGULAR, transform)
    out = root / "delivery"
    dtm = write_dtm(dtm_in, out, profile="hirise", source_product_ids=["PSP_008669_1705", "PSP_009025_1705"],
                    institution="U")
    ortho = write_ortho(ortho_in, out, profile="hirise", observation_id="PSP_008669_1705",
                        source_dtm_id=dtm.product_id)
    make_extras([dtm.path, ortho.label_path], out / "extras")
    return out


def test_hirise_dtm_label(delivery):
    check_golden("hirise_dtm.lbl", attached_label(delivery / "DTEEC_008669_1705_009025_1705_U01.IMG"))


def test_hirise_ortho_label(delivery):
    check_golden("hirise_ortho.lbl", (delivery / "PSP_008669_1705_RED_C_01_ORTHO.LBL").read_bytes())


def test_extras_readme(delivery):
    check_golden("extras_README.TXT", (delivery / "extras" / "README.TXT").read_bytes())


def _cli(*args: str, cwd: Path) -> bytes:
    result = subprocess.run([sys.executable, "-m", "pdsgen", *args], capture_output=True, cwd=cwd, timeout=300)
    return result.stdout


def test_validate_json_report(delivery):
    check_golden("validate_report.json", _cli("validate", "--format", "json", "delivery", cwd=delivery.parent))


def test_list_rules(tmp_path):
    check_golden("list_rules.txt", _cli("validate", "--list-rules", cwd=tmp_path))


def test_hrsc_dt4_and_nd4_labels(tmp_path):
    heights = elevation_array(30, 24, seed=7)
    heights[2:4, 5:9] = np.nan
    transform = Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0)
    source = write_raster(tmp_path / "heights.tif", heights, SINUSOIDAL_HRSC, transform)
    dt4 = write_dtm(source, tmp_path / "out", profile="hrsc", precision=0.5, source_product_ids=["H1234_0000_ND3"])
    check_golden("hrsc_dt4.lbl", attached_label(dt4.path))
    image = np.linspace(3, 250, 30 * 24).reshape(30, 24).astype(np.uint8)
    nadir = write_raster(tmp_path / "nadir.tif", image, SINUSOIDAL_HRSC, transform)
    nd4 = write_ortho(nadir, tmp_path / "out", profile="hrsc", source_product_ids=["H1234_0000_ND3"])
    check_golden("hrsc_nd4.lbl", attached_label(nd4.path))


def test_imars_pvl(tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")  # ProcessingDate 2023-11-14, reproducibly
    heights = elevation_array(30, 20, seed=11)
    heights[:3, :] = np.nan
    transform = Affine(100.0, 0, -20000.0, 0, -100.0, 150000.0)
    source = write_raster(tmp_path / "heights.tif", heights, SOUTH_POLAR_HRSC, transform)
    product = write_dtm(source, tmp_path / "out", profile="imars", product_id="h0022_0000", precision=0.1)
    check_golden("imars_da4_ucl.pvl", product.pvl_path.read_bytes())
