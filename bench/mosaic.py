"""Benchmark `pdsgen mosaic` against gdal_merge.py and gdalbuildvrt + gdal_translate.

Usage: python bench/mosaic.py [--strips 33] [--lines 6000] [--samples 1500] [--repeat 2]
                              [--form generic|imars|both]

Makes STRIPS int16 DTM strips (LINES x SAMPLES posts, no-data -32768, ragged edges) on a
south polar stereographic grid, laid out like the iMars south-polar strips: 11 columns of
3 rows, overlapping (33 strips of 6,000 x 1,500 give a 17,800 x 15,300 mosaic). Then,
the commands run in turn, --repeat times (so a change in the machine's load falls on all), each
run after its previous outputs are removed, a sync and a pause (bench/_measure.py); the best
run of each is compared.

--form generic (the PDS3 .IMG form):
- `pdsgen mosaic --profile generic` -> the PDS3 .IMG DTM (float32, label, statistics);
- `gdal_merge.py -n -32768 -a_nodata -32768 -init -32768` -> an int16 GeoTIFF;
- `gdalbuildvrt -srcnodata -32768 -vrtnodata -32768` then `gdal_translate` -> an int16 GeoTIFF.

--form imars (seed 002's own product: tiled, DEFLATE-compressed GeoTIFF, PVL, footprints):
- `pdsgen mosaic --profile imars --kind dtm` -> `<ID>_dtm.tif` (int16, 256 x 256 tiles,
  DEFLATE with the horizontal predictor), its PVL and one footprint polygon per strip;
- `gdal_merge.py ... -co COMPRESS=DEFLATE -co PREDICTOR=2 -co TILED=YES` -> the same file form;
- the same two for the orthoimage (`<ID>_ori.tif`) from byte strips of the same layout
  (no-data 0).

--form both (the default) runs all of them, alternating. Each pdsgen product is checked
against gdal_merge.py's, pixel for pixel (read by blocks); wall time and peak RSS are
printed side by side with the ratios. Targets: time <= 0.8 x
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


def make_strips(folder: Path, strips: int, lines: int, samples: int, dtype: str = "int16") -> list[Path]:
    """Int16 heights (or byte images, no-data 0) written strip by strip, block by block, ragged
    at their left and right edges."""
    rng = np.random.default_rng(30)
    paths = []
    origin_x, origin_y = -450000.0, 400000.0
    nodata = NODATA if dtype == "int16" else 0
    for index, (line, sample) in enumerate(layout(strips, lines, samples)):
        path = folder / f"{'strip' if dtype == 'int16' else 'image'}_{index:02d}.tif"
        transform = Affine(PIXEL, 0, origin_x + sample * PIXEL, 0, -PIXEL, origin_y - line * PIXEL)
        profile = {"driver": "GTiff", "width": samples, "height": lines, "count": 1, "dtype": dtype,
                   "crs": CRS, "transform": transform, "nodata": nodata}
        with rasterio.open(path, "w", **profile) as out:
            for row in range(0, lines, 500):
                rows = min(500, lines - row)
                block: np.ndarray
                if dtype == "int16":
                    block = (rng.integers(-4000, -3000, (rows, 1), dtype=np.int16)
                             + rng.integers(0, 50, (rows, samples), dtype=np.int16))
                else:
                    block = (rng.integers(40, 150, (rows, 1), dtype=np.uint8)
                             + rng.integers(1, 100, (rows, samples), dtype=np.uint8))
                left = rng.integers(0, 60, rows)
                right = rng.integers(0, 60, rows)
                columns = np.arange(samples)
                block[(columns[None, :] < left[:, None]) | (columns[None, :] >= samples - right[:, None])] = nodata
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


def same_samples(product: Path, merged: Path) -> bool:
    """pdsgen's iMars GeoTIFF and gdal_merge.py's hold the same samples (type, no-data, grid)."""
    with rasterio.open(product) as ours, rasterio.open(merged) as theirs:
        if (ours.width, ours.height, ours.dtypes, ours.nodata) != (theirs.width, theirs.height, theirs.dtypes,
                                                                   theirs.nodata) \
                or ours.transform != theirs.transform:
            return False
        for row in range(0, ours.height, 512):
            window = ((row, min(row + 512, ours.height)), (0, ours.width))
            if not np.array_equal(ours.read(1, window=window), theirs.read(1, window=window)):
                return False
    return True


# gdal_merge.py writing the iMars file form: a tiled (256 x 256), DEFLATE-compressed GeoTIFF.
IMARS_CREATION = ["-co", "COMPRESS=DEFLATE", "-co", "PREDICTOR=2", "-co", "TILED=YES",
                  "-co", "NUM_THREADS=ALL_CPUS"]  # compressed on as many threads as pdsgen uses


def merge_command(strips: list[str], out: Path, nodata: int, creation: list[str]) -> list[str]:
    """gdal_merge.py as the mosaic's reference: no-data transparent, the fill and the output's."""
    nd = str(nodata)
    return ["gdal_merge.py", "-q", "-o", str(out), "-n", nd, "-a_nodata", nd, "-init", nd, *creation, *strips]


def pdsgen_command(strips: list[str], out: Path, *options: str) -> list[str]:
    return [sys.executable, "-m", "pdsgen", "mosaic", *strips, "-o", str(out), "--product-id", "BENCH_MOSAIC",
            "-q", *options]


def generic_commands(work: Path, strips: list[str]) -> dict[str, tuple[list[str], list[str]]]:
    """The PDS3 .IMG form against gdal_merge.py and gdalbuildvrt + gdal_translate (plain GeoTIFFs)."""
    out, merged, vrt, translated = work / "out", work / "merged.tif", work / "all.vrt", work / "translated.tif"
    nd = str(NODATA)
    return {
        "ours": (pdsgen_command(strips, out, "--kind", "dtm"), [str(out)]),
        "merge": (merge_command(strips, merged, NODATA, []), [str(merged)]),
        "build": (["gdalbuildvrt", "-q", "-srcnodata", nd, "-vrtnodata", nd, str(vrt), *strips], [str(vrt)]),
        "translate": (["gdal_translate", "-q", str(vrt), str(translated)], [str(translated)]),
    }


def imars_commands(work: Path, strips: list[str], images: list[str]) -> dict[str, tuple[list[str], list[str]]]:
    """The iMars DTM and ORI forms against gdal_merge.py writing the same file form."""
    dtm, ori = work / "imars_dtm", work / "imars_ori"
    commands = {
        "imars dtm": (pdsgen_command(strips, dtm, "--profile", "imars", "--kind", "dtm"), [str(dtm)]),
        "merge dtm": (merge_command(strips, work / "merged_dtm.tif", NODATA, IMARS_CREATION),
                      [str(work / "merged_dtm.tif")]),
    }
    if images:
        commands["imars ori"] = (pdsgen_command(images, ori, "--profile", "imars", "--kind", "ortho"), [str(ori)])
        commands["merge ori"] = (merge_command(images, work / "merged_ori.tif", 0, IMARS_CREATION),
                                 [str(work / "merged_ori.tif")])
    return commands


def report_generic(work: Path, best: dict[str, Run]) -> tuple[bool, bool, bool]:
    """The generic form's tables; (pixels equal, time met, memory met)."""
    ours, merge, build, translate = best["ours"], best["merge"], best["build"], best["translate"]
    both = Run(build.seconds + translate.seconds, max(build.peak_mb, translate.peak_mb),
               build.cpu_seconds + translate.cpu_seconds)
    print_side_by_side("pdsgen mosaic (PDS3 .IMG) vs gdal_merge.py (GeoTIFF)", ours, merge, "gdal_merge.py")
    print_side_by_side("pdsgen mosaic vs gdalbuildvrt + gdal_translate", ours, both, "buildvrt + translate")
    equal = same_heights(work / "out" / "BENCH_MOSAIC.IMG", work / "merged.tif")
    return verdict(equal, ours, merge)


def report_imars(work: Path, best: dict[str, Run], kind: str) -> tuple[bool, bool, bool]:
    """One iMars form's table (`kind` dtm or ori); (pixels equal, time met, memory met)."""
    ours, merge = best[f"imars {kind}"], best[f"merge {kind}"]
    print_side_by_side(f"pdsgen mosaic (iMars {kind.upper()}) vs gdal_merge.py (tiled DEFLATE GeoTIFF)",
                       ours, merge, "gdal_merge.py")
    product = work / f"imars_{kind}" / f"BENCH_MOSAIC_{kind}.tif"
    return verdict(same_samples(product, work / f"merged_{kind}.tif"), ours, merge)


def verdict(equal: bool, ours: Run, merge: Run) -> tuple[bool, bool, bool]:
    """Print and return whether the pixels are equal and the time and memory targets met."""
    time_ok, memory_ok = ours.seconds <= 0.8 * merge.seconds, ours.peak_mb <= 0.25 * merge.peak_mb
    print(f"  CPU time (all threads): pdsgen {ours.cpu_seconds:.1f} s, gdal_merge.py {merge.cpu_seconds:.1f} s")
    print(f"  pixels equal to gdal_merge.py's: {'yes' if equal else 'NO'}; "
          f"targets: time <= 0.8 x gdal_merge.py {'met' if time_ok else 'NOT met'}, "
          f"peak memory <= 0.25 x {'met' if memory_ok else 'NOT met'}")
    return equal, time_ok, memory_ok


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strips", type=int, default=33)
    parser.add_argument("--lines", type=int, default=6000)
    parser.add_argument("--samples", type=int, default=1500)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--form", choices=("generic", "imars", "both"), default="both",
                        help="generic: the PDS3 .IMG form; imars: the iMars DTM and ORI forms [default: both]")
    parser.add_argument("--no-ori", action="store_true", help="imars: the DTM form only")
    args = parser.parse_args()
    for tool in ("gdal_merge.py", "gdalbuildvrt", "gdal_translate"):
        if shutil.which(tool) is None:
            raise SystemExit(f"{tool} not found: install GDAL's tools (Debian: gdal-bin, python3-gdal)")
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-mosaic-") as tmp:
        work = Path(tmp)
        strips = [str(p) for p in make_strips(work, args.strips, args.lines, args.samples)]
        commands: dict[str, tuple[list[str], list[str]]] = {}
        if args.form in ("generic", "both"):
            commands.update(generic_commands(work, strips))
        if args.form in ("imars", "both"):
            images = [] if args.no_ori else \
                [str(p) for p in make_strips(work, args.strips, args.lines, args.samples, "uint8")]
            commands.update(imars_commands(work, strips, images))
        runs: dict[str, list[Run]] = {name: [] for name in commands}
        for _ in range(args.repeat):  # alternating, so a change in the machine's load falls on all
            for name, (command, outputs) in commands.items():
                runs[name].append(best_of(command, 1, outputs))
                run = runs[name][-1]
                print(f"  run {name}: {run.seconds:.2f} s, {run.cpu_seconds:.1f} s CPU, {run.peak_mb:.0f} MB "
                      f"(load {os.getloadavg()[0]:.1f})", flush=True)
        best = {name: min(runs[name], key=lambda r: r.seconds) for name in commands}
        with rasterio.open(work / ("merged.tif" if "merge" in best else "merged_dtm.tif")) as dataset:
            size = f"{dataset.width} x {dataset.height}"
        print(f"{args.strips} int16 strips of {args.lines} x {args.samples} -> mosaic {size}, best of "
              f"{args.repeat}, load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
        verdicts = []
        if "ours" in best:
            verdicts.append(report_generic(work, best))
        for kind in ("dtm", "ori"):
            if f"imars {kind}" in best:
                verdicts.append(report_imars(work, best, kind))
        if not all(equal for equal, _, _ in verdicts):
            raise SystemExit("pixels differ from gdal_merge.py's")


if __name__ == "__main__":
    main()
