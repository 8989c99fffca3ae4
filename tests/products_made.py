"""Every kind of product pdsgen makes, written through the command line from fixed inputs,
and the SHA-256 of every file written.

Run as a script it prints the table as JSON:

    python tests/products_made.py OUTDIR > tests/golden/products_made.json

The table in tests/golden/ was written by the version named in its "made_by" field; the
test beside this file (test_products_unchanged.py) runs the same commands with the code
under test and compares every file. The commands go through `python -m pdsgen` only, so
the same script runs against an old and a new version whatever their import paths.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from affine import Affine

sys.path.insert(0, str(Path(__file__).resolve().parent))

from helpers import CRS_EQUIRECTANGULAR, elevation_array, write_raster  # noqa: E402
from hrsc_ax_tiles import dtm_group, map_group, tile_name, write_vicar  # noqa: E402

SINUSOIDAL_HRSC = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"
EQC = Affine(1.0, 0, 6123456.0, 0, -1.0, -563210.0)
SINU = Affine(50.0, 0, 4150000.0, 0, -50.0, -1000000.0)
# The day of making of every product and delivery (iMars ProcessingDate, publication dates,
# index creation times, the review page's time): 2023-11-14T22:13:20Z, the same on any day.
EPOCH = "1700000000"


def _inputs(root: Path) -> dict[str, Path]:
    """Small rasters with fixed seeds: a HiRISE-like DTM and orthoimage, HRSC-like ones, HRSC-AX tiles."""
    heights = elevation_array(40, 30, seed=5)
    heights[3:5, 4:9] = np.nan
    image = np.linspace(0.05, 0.25, 40 * 30, dtype=np.float32).reshape(40, 30)
    nadir = np.random.default_rng(7).integers(1, 256, (40, 30)).astype(np.uint8)
    left = elevation_array(20, 30, seed=8)
    right = elevation_array(20, 30, seed=9)
    made = {
        "dtm": write_raster(root / "dtm.tif", heights, CRS_EQUIRECTANGULAR, EQC),
        "ortho": write_raster(root / "ortho.tif", image, CRS_EQUIRECTANGULAR, EQC),
        "hrsc_dtm": write_raster(root / "h_dtm.tif", heights, SINUSOIDAL_HRSC, SINU),
        "hrsc_nadir": write_raster(root / "h_nd.tif", nadir, SINUSOIDAL_HRSC, SINU, nodata=0),
        "strip_a": write_raster(root / "strip_a.tif", left, CRS_EQUIRECTANGULAR, EQC, nodata=-9999.0),
        "strip_b": write_raster(root / "strip_b.tif", right, CRS_EQUIRECTANGULAR,
                                Affine(1.0, 0, 6123466.0, 0, -1.0, -563222.0), nodata=-9999.0),
    }
    rows, cols = np.mgrid[0:48, 0:64]
    stored = (rows * 7.0 - cols * 3.5 + 0.25 * rows * cols).astype(np.float32)
    stored[5, 9] = -32768.0
    name = tile_name(430, 8765, 48, 0.5)
    tiles = root / "ax"
    tiles.mkdir()
    made["ax_dem"] = write_vicar(tiles / f"{name}.dsm", stored, {
        "MAP": map_group(430000.0, 8765000.0, 0.5), "DIGITAL_TERRAIN_MODEL": dtm_group(100.0, 0.25, -500.0, 2000.0)})
    pan = np.random.default_rng(3).integers(1, 256, (48, 64)).astype(np.uint8)
    made["ax_pan"] = write_vicar(tiles / f"{name}.pan", pan, {"MAP": map_group(430000.0, 8765000.0, 0.5)})
    return made


def _commands(i: dict[str, Path]) -> list[list[str]]:
    """One command per kind of product; outputs under out/<name>/."""
    hirise = ["--profile", "hirise"]
    return [
        ["demo", "out/demo", "-q"],
        ["dtm", str(i["dtm"]), "-o", "out/hirise", *hirise, "--source-product-id", "PSP_008669_1705",
         "--source-product-id", "PSP_009025_1705", "--institution", "U", "--label", "both"],
        ["ortho", str(i["ortho"]), "-o", "out/hirise", *hirise, "--observation-id", "PSP_008669_1705",
         "--label", "both"],
        ["extras", "out/hirise/DTEEC_008669_1705_009025_1705_U01.IMG",
         "out/hirise/PSP_008669_1705_RED_C_01_ORTHO.LBL", "-o", "out/hirise/extras"],
        ["dtm", str(i["dtm"]), "-o", "out/generic_pds4", "--label", "pds4", "--byte-order", "msb"],
        ["dtm", str(i["hrsc_dtm"]), "-o", "out/hrsc", "--profile", "hrsc", "--product-id", "h1234_0000",
         "--precision", "0.5", "--label", "both"],
        ["ortho", str(i["hrsc_nadir"]), "-o", "out/hrsc", "--profile", "hrsc", "--product-id", "h1234_0000"],
        ["dtm", str(i["hrsc_dtm"]), "-o", "out/imars", "--profile", "imars", "--product-id", "h1234_0000"],
        ["ortho", str(i["hrsc_nadir"]), "-o", "out/imars", "--profile", "imars", "--product-id", "h1234_0000"],
        ["dtm", str(i["ax_dem"]), "-o", "out/hrsc_ax", "--profile", "hrsc-ax", "--label", "both"],
        ["ortho", str(i["ax_pan"]), "-o", "out/hrsc_ax", "--profile", "hrsc-ax"],
        ["mosaic", str(i["strip_a"]), str(i["strip_b"]), "-o", "out/mosaic", "--product-id", "MOSAIC_A"],
        ["migrate", "out/hirise/DTEEC_008669_1705_009025_1705_U01.IMG", "-o", "out/migrated"],
        ["deliver", "out/hirise", "-o", "out/delivery", "--both", "--volume-id", "PDSGEN_0001",
         "--bundle-lid", "urn:nasa:pds:pdsgen_test"],
    ]


def make(root: Path) -> dict[str, str]:
    """Write every product under root/out and return {path relative to out: sha256}."""
    root.mkdir(parents=True, exist_ok=True)
    inputs = _inputs(root)
    environment = {**os.environ, "SOURCE_DATE_EPOCH": EPOCH}
    for command in _commands(inputs):
        done = subprocess.run([sys.executable, "-m", "pdsgen", *command], cwd=root, env=environment,
                              capture_output=True, text=True, timeout=600)
        if done.returncode != 0:
            raise RuntimeError(f"pdsgen {' '.join(command)} failed:\n{done.stderr}")
    out = root / "out"
    return {path.relative_to(out).as_posix(): hashlib.sha256(path.read_bytes()).hexdigest()
            for path in sorted(out.rglob("*")) if path.is_file()}


if __name__ == "__main__":
    table = make(Path(sys.argv[1]))
    made_by = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                             cwd=Path(__file__).parent).stdout.strip()
    print(json.dumps({"made_by": made_by, "files": table}, indent=1, sort_keys=True))
