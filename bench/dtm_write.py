"""Benchmark `pdsgen dtm` against `gdal_translate -of PDS4` (raw float32) on one input.

Usage: python bench/dtm_write.py [--size 8000] [--repeat 2] [--memory-size 16000]

Both tools read the same GeoTIFF and write raw float32 image data plus a label;
pdsgen also computes VALID_MINIMUM/MAXIMUM and maps nodata in the same pass.
Target: time ratio <= 1.0 with lower peak memory. With --memory-size it also
converts a larger raster and checks that pdsgen's peak RSS stays under 300 MB.
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

CRS = "+proj=eqc +lat_ts=-5 +lon_0=180 +R=3396190 +units=m +no_defs"


def make_input(path: Path, size: int) -> Path:
    """A float32 DTM written strip by strip, so the bench itself stays small in memory."""
    profile = {"driver": "GTiff", "width": size, "height": size, "count": 1, "dtype": "float32",
               "crs": CRS, "transform": Affine(1.0, 0, 6100000.0, 0, -1.0, -560000.0),
               "nodata": -9999.0, "tiled": True, "blockxsize": 512, "blockysize": 512}
    rng = np.random.default_rng(0)
    with rasterio.open(path, "w", **profile) as dataset:
        for row in range(0, size, 512):
            rows = min(512, size - row)
            block = (-4000 + rng.normal(0, 30, (rows, size))).astype(np.float32)
            block[:, :7] = -9999.0
            dataset.write(block, 1, window=((row, row + rows), (0, size)))
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=8000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--memory-size", type=int, default=0, help="also check peak RSS on SIZE x SIZE")
    args = parser.parse_args()
    if shutil.which("gdal_translate") is None:
        raise SystemExit("gdal_translate not found: install GDAL's command-line tools (Debian: gdal-bin)")
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
        work = Path(tmp)
        source = make_input(work / "dtm.tif", args.size)
        ours = best_of([sys.executable, "-m", "pdsgen", "dtm", str(source), "-o", str(work / "ours"),
                        "--product-id", "BENCH"], args.repeat, [str(work / "ours")])
        baseline = best_of(["gdal_translate", "-q", "-of", "PDS4", "-co", "IMAGE_FORMAT=RAW",
                            str(source), str(work / "gdal.xml")], args.repeat,
                           [str(work / "gdal.xml"), str(work / "gdal.img")])
        print_side_by_side(f"DTM write, {args.size} x {args.size} float32 "
                           f"({args.size * args.size * 4 / 2**20:.0f} MiB)", ours, baseline,
                           "gdal_translate -of PDS4")
        if args.memory_size:
            (work / "dtm.tif").unlink()
            shutil.rmtree(work / "ours", ignore_errors=True)
            big = make_input(work / "big.tif", args.memory_size)
            big_ours = best_of([sys.executable, "-m", "pdsgen", "dtm", str(big), "-o", str(work / "big"),
                                "--product-id", "BIG"], 1, [str(work / "big")])
            big_gdal = best_of(["gdal_translate", "-q", "-of", "PDS4", "-co", "IMAGE_FORMAT=RAW", str(big),
                                str(work / "big.xml")], 1, [str(work / "big.xml"), str(work / "big.img")])
            print_side_by_side(f"DTM write, {args.memory_size} x {args.memory_size} float32 "
                               f"({args.memory_size ** 2 * 4 / 2**20:.0f} MiB)", big_ours, big_gdal,
                               "gdal_translate -of PDS4")
            verdict = "OK" if big_ours.peak_mb < 300 else "OVER the 300 MB target"
            print(f"  pdsgen peak RSS {big_ours.peak_mb:.0f} MB at {args.memory_size} x {args.memory_size} "
                  f"({verdict}; {ours.peak_mb:.0f} MB at {args.size} x {args.size})")


if __name__ == "__main__":
    main()
