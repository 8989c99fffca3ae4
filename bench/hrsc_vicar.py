"""Convert a large HRSC-AX-like VICAR DEM (Earth ellipsoid, float32) with flat memory.

Usage: python bench/hrsc_vicar.py [--size 25000]

Writes a SIZE x SIZE float32 VICAR file (HRSC-AX tiles reach 25,000 x 25,000),
converts it with `pdsgen dtm` and with `gdal_translate -of PDS4` for comparison,
and prints wall time and peak RSS side by side. Target: pdsgen under 400 MB RSS.
Needs about 3 x SIZE^2 x 4 bytes of free disk.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import rasterio
from affine import Affine

from _measure import best_of, print_side_by_side

EARTH = "+proj=eqc +lat_ts=0 +lon_0=0 +a=6378140 +b=6356750 +units=m +no_defs"


def make_vicar(path: Path, size: int) -> Path:
    profile = {"driver": "VICAR", "width": size, "height": size, "count": 1, "dtype": "float32",
               "crs": EARTH, "transform": Affine(0.5, 0, 1200000.0, 0, -0.5, 5800000.0)}
    rng = np.random.default_rng(5)
    with rasterio.open(path, "w", **profile) as dataset:
        for row in range(0, size, 1024):
            rows = min(1024, size - row)
            strip = (36.5 + np.cumsum(rng.normal(0, 0.05, (rows, size)), axis=1)).astype(np.float32)
            dataset.write(strip, 1, window=((row, row + rows), (0, size)))
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=25000)
    args = parser.parse_args()
    if shutil.which("gdal_translate") is None:
        raise SystemExit("gdal_translate not found: install GDAL's command-line tools (Debian: gdal-bin)")
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-", dir=".") as tmp:
        work = Path(tmp)
        source = make_vicar(work / "ax.vic", args.size)
        ours = best_of([sys.executable, "-m", "pdsgen", "dtm", str(source), "-o", str(work / "ours"),
                        "--product-id", "HRSC_AX_TILE"], 1, [str(work / "ours")])
        baseline = best_of(["gdal_translate", "-q", "-of", "PDS4", "-co", "IMAGE_FORMAT=RAW", str(source),
                            str(work / "gdal.xml")], 1, [str(work / "gdal.xml"), str(work / "gdal.img")])
        print_side_by_side(f"VICAR {args.size} x {args.size} float32 (Earth ellipsoid) -> PDS3 DTM",
                           ours, baseline, "gdal_translate -of PDS4")
        verdict = "OK" if ours.peak_mb < 400 else "OVER the 400 MB target"
        print(f"pdsgen peak RSS {ours.peak_mb:.0f} MB: {verdict}")


if __name__ == "__main__":
    main()
