"""Benchmark: `write_ortho` against gdal_translate's lossless JP2OpenJPEG on one 8-bit image.

Generates an N x N uint8 GeoTIFF (default 8,000 x 8,000) in a temporary
directory, then runs each writer in a fresh subprocess and reports wall time and
peak resident memory (bench/_measure.py: measured from a small launcher process) side by side.
Targets (issue 3): time ratio <= 1.0, peak memory lower than GDAL's.

    PYTHONPATH=src python bench/ortho_write.py [--size 8000] [--repeat 1]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

import numpy as np
import rasterio
from affine import Affine
from rasterio.crs import CRS

from _measure import measure

MARS_EQC = "+proj=eqc +lat_ts=-5 +lat_0=0 +lon_0=180 +R=3396190 +units=m +no_defs"


def make_input(path: Path, size: int) -> None:
    """A textured byte image (smooth relief plus noise), written strip by strip."""
    rng = np.random.default_rng(2026)
    profile = {
        "driver": "GTiff", "width": size, "height": size, "count": 1, "dtype": "uint8",
        "crs": CRS.from_proj4(MARS_EQC), "transform": Affine(0.5, 0, 6099776.0, 0, -0.5, -563110.0),
        "tiled": True, "blockxsize": 256, "blockysize": 256,
    }
    xx = np.arange(size, dtype=np.float32)[None, :]
    with rasterio.open(path, "w", **profile) as dataset:
        for top in range(0, size, 1024):
            rows = min(1024, size - top)
            yy = np.arange(top, top + rows, dtype=np.float32)[:, None]
            relief = 60 * np.sin(yy / 97.0) * np.cos(xx / 131.0) + 30 * np.sin((xx + yy) / 23.0)
            noise = rng.normal(scale=12.0, size=(rows, size)).astype(np.float32)
            block = np.clip(128 + relief + noise, 1, 254).astype(np.uint8)
            dataset.write(block, 1, window=rasterio.windows.Window(0, top, size, rows))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=8000)
    parser.add_argument("--repeat", type=int, default=1, help="runs of each writer; the best time is kept")
    args = parser.parse_args()
    cores = os.cpu_count() or 1
    src = str(Path(__file__).resolve().parents[1] / "src")
    env = {**os.environ, "PYTHONPATH": src + os.pathsep + os.environ.get("PYTHONPATH", "")}
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
        tmp_path = Path(tmp)
        source = tmp_path / "input.tif"
        make_input(source, args.size)
        ours = [
            sys.executable, "-c",
            "import sys; from pdsgen.ortho import write_ortho; "
            "write_ortho(sys.argv[1], sys.argv[2], product_id='BENCH', overwrite=True)",
            str(source), str(tmp_path / "pdsgen"),
        ]
        gdal = [
            "gdal_translate", "-q", "-of", "JP2OpenJPEG", "-co", "REVERSIBLE=YES", "-co", "QUALITY=100",
            "-co", f"NUM_THREADS={cores}", str(source), str(tmp_path / "gdal.jp2"),
        ]
        results = {"pdsgen": [], "gdal": []}
        for _ in range(args.repeat):
            results["gdal"].append(measure(gdal, env))
            results["pdsgen"].append(measure(ours, env))
        t_ours = min(run.seconds for run in results["pdsgen"])
        t_gdal = min(run.seconds for run in results["gdal"])
        m_ours = min(run.peak_mb for run in results["pdsgen"])
        m_gdal = min(run.peak_mb for run in results["gdal"])
        size_ours = (tmp_path / "pdsgen" / "BENCH.JP2").stat().st_size
        size_gdal = (tmp_path / "gdal.jp2").stat().st_size
    print(f"input: {args.size} x {args.size} uint8, {cores} cores, best of {args.repeat}")
    print(f"{'':24}{'pdsgen':>12}{'gdal_translate':>16}{'ratio':>8}")
    print(f"{'wall time (s)':24}{t_ours:12.2f}{t_gdal:16.2f}{t_ours / t_gdal:8.2f}")
    print(f"{'peak RSS (MiB)':24}{m_ours:12.1f}{m_gdal:16.1f}{m_ours / m_gdal:8.2f}")
    print(f"{'output (MB)':24}{size_ours / 1e6:12.1f}{size_gdal / 1e6:16.1f}{size_ours / size_gdal:8.2f}")
    ok = t_ours / t_gdal <= 1.0 and m_ours < m_gdal
    print("targets (time ratio <= 1.0, lower peak memory):", "met" if ok else "NOT met")


if __name__ == "__main__":
    main()
