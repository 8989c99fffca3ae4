"""Benchmark `pdsgen mosaic` against gdal_merge.py and gdalbuildvrt + gdal_translate.

Usage: python bench/mosaic.py [--strips 33] [--lines 6000] [--samples 1500] [--repeat 2]

Makes STRIPS int16 DTM strips (LINES x SAMPLES posts, no-data -32768, ragged edges) on a
south polar stereographic grid, laid out like the iMars south-polar strips: 11 columns of
3 rows, overlapping (33 strips of 6,000 x 1,500 give a 17,800 x 15,300 mosaic). Then,
the commands run in turn, --repeat times (so a change in the machine's load falls on all), each
run after its previous outputs are removed, a sync and a pause (bench/_measure.py); the best
run of each is compared:

- `pdsgen mosaic --profile generic` -> the PDS3 .IMG DTM (float32, label, statistics);
- `gdal_merge.py -n -32768 -a_nodata -32768 -init -32768` -> an int16 GeoTIFF;
- `gdalbuildvrt -srcnodata -32768 -vrtnodata -32768` then `gdal_translate` -> an int16 GeoTIFF.

It checks pdsgen's heights equal gdal_merge.py's, pixel for pixel (read by blocks), and
prints wall time and peak RSS side by side with the ratios. Targets: time <= 0.8 x
gdal_merge.py, peak memory <= 0.25 x. The machine's load average is printed with them.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import rasterio
from affine import Affine

from _measure import Run, best_of, print_side_by_side

CRS = "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +x_0=0 +y_0=0 +R=3396190 +units=m +no_defs"
NODATA = -32768
PIXEL = 50.0
COLUMNS = 11


def layout(strips: int, lines: int, samples: int) -> list[tuple[int, int]]:
    """(line, sample) of each strip's upper-left corner on the mosaic grid: COLUMNS columns
    side by side, rows overlapping by 22 %."""
    column_step = samples + samples // 11 - 6
    row_step = int(lines * 0.775)
    return [((index // COLUMNS) * row_step, (index % COLUMNS) * column_step) for index in range(strips)]


def make_strips(folder: Path, strips: int, lines: int, samples: int) -> list[Path]:
    """Int16 heights written strip by strip, block by block, ragged at their left and right edges."""
    rng = np.random.default_rng(30)
    paths = []
    origin_x, origin_y = -450000.0, 400000.0
    for index, (line, sample) in enumerate(layout(strips, lines, samples)):
        path = folder / f"strip_{index:02d}.tif"
        transform = Affine(PIXEL, 0, origin_x + sample * PIXEL, 0, -PIXEL, origin_y - line * PIXEL)
        profile = {"driver": "GTiff", "width": samples, "height": lines, "count": 1, "dtype": "int16",
                   "crs": CRS, "transform": transform, "nodata": NODATA}
        with rasterio.open(path, "w", **profile) as out:
            for row in range(0, lines, 500):
                rows = min(500, lines - row)
                block = (rng.integers(-4000, -3000, (rows, 1), dtype=np.int16)
                         + rng.integers(0, 50, (rows, samples), dtype=np.int16))
                left = rng.integers(0, 60, rows)
                right = rng.integers(0, 60, rows)
                columns = np.arange(samples)
                block[(columns[None, :] < left[:, None]) | (columns[None, :] >= samples - right[:, None])] = NODATA
                out.write(block, 1, window=((row, row + rows), (0, samples)))
        paths.append(path)
    return paths


def same_heights(product: Path, merged: Path) -> bool:
    """pdsgen's float32 .IMG and gdal_merge.py's int16 GeoTIFF hold the same heights and no-data."""
    with rasterio.open(product) as ours, rasterio.open(merged) as theirs:
        if (ours.width, ours.height) != (theirs.width, theirs.height) or ours.transform != theirs.transform:
            return False
        for row in range(0, ours.height, 512):
            window = ((row, min(row + 512, ours.height)), (0, ours.width))
            a, b = ours.read(1, window=window), theirs.read(1, window=window)
            if not np.array_equal(np.where(a == ours.nodata, NODATA, a), b.astype(np.float32)):
                return False
    return True


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strips", type=int, default=33)
    parser.add_argument("--lines", type=int, default=6000)
    parser.add_argument("--samples", type=int, default=1500)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    for tool in ("gdal_merge.py", "gdalbuildvrt", "gdal_translate"):
        if shutil.which(tool) is None:
            raise SystemExit(f"{tool} not found: install GDAL's tools (Debian: gdal-bin, python3-gdal)")
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-mosaic-") as tmp:
        work = Path(tmp)
        strips = [str(p) for p in make_strips(work, args.strips, args.lines, args.samples)]
        out, merged, vrt, translated = work / "out", work / "merged.tif", work / "all.vrt", work / "translated.tif"
        nd = str(NODATA)
        commands = {
            "ours": ([sys.executable, "-m", "pdsgen", "mosaic", *strips, "-o", str(out), "--kind", "dtm",
                      "--product-id", "BENCH_MOSAIC", "-q"], [str(out)]),
            "merge": (["gdal_merge.py", "-q", "-o", str(merged), "-n", nd, "-a_nodata", nd, "-init", nd, *strips],
                      [str(merged)]),
            "build": (["gdalbuildvrt", "-q", "-srcnodata", nd, "-vrtnodata", nd, str(vrt), *strips], [str(vrt)]),
            "translate": (["gdal_translate", "-q", str(vrt), str(translated)], [str(translated)]),
        }
        runs: dict[str, list[Run]] = {name: [] for name in commands}
        for _ in range(args.repeat):  # alternating, so a change in the machine's load falls on all
            for name, (command, outputs) in commands.items():
                runs[name].append(best_of(command, 1, outputs))
                print(f"  run {name}: {runs[name][-1].seconds:.2f} s, {runs[name][-1].peak_mb:.0f} MB "
                      f"(load {os.getloadavg()[0]:.1f})", flush=True)
        ours, merge, build, translate = (min(runs[n], key=lambda r: r.seconds) for n in commands)
        both = Run(build.seconds + translate.seconds, max(build.peak_mb, translate.peak_mb),
                   build.cpu_seconds + translate.cpu_seconds)
        with rasterio.open(merged) as dataset:
            size = f"{dataset.width} x {dataset.height}"
        print(f"{args.strips} int16 strips of {args.lines} x {args.samples} -> mosaic {size}, "
              f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
        print_side_by_side("pdsgen mosaic (PDS3 .IMG) vs gdal_merge.py (GeoTIFF)", ours, merge, "gdal_merge.py")
        print_side_by_side("pdsgen mosaic vs gdalbuildvrt + gdal_translate", ours, both, "buildvrt + translate")
        equal = same_heights(out / "BENCH_MOSAIC.IMG", merged)
        print(f"  heights equal to gdal_merge.py's, pixel for pixel: {'yes' if equal else 'NO'}")
        time_ok, memory_ok = ours.seconds <= 0.8 * merge.seconds, ours.peak_mb <= 0.25 * merge.peak_mb
        print(f"  targets: time <= 0.8 x gdal_merge.py {'met' if time_ok else 'NOT met'}, "
              f"peak memory <= 0.25 x {'met' if memory_ok else 'NOT met'}")


if __name__ == "__main__":
    main()
