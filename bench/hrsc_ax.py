"""Benchmark: HRSC-AX tiles to lossless JP2, `pdsgen ortho --profile hrsc-ax` against GDAL.

Builds HRSC-AX-like VICAR channel files (BYTE, TM on the HRSC-AX ellipsoid; the tests'
tile writer) of SIZE x SIZE pixels in a temporary directory: one panchromatic `.pan`
and the three colour channels `.re .gr .bl`. Then, in fresh processes, alternating:

  pan: pdsgen ortho TILE.pan --profile hrsc-ax    vs  GDAL JP2OpenJPEG of TILE.pan
  RGB: pdsgen ortho TILE.re TILE.gr TILE.bl ...   vs  GDAL JP2OpenJPEG of a VRT of the three

GDAL runs with REVERSIBLE=YES QUALITY=100 (lossless) on every core, through
`gdal_translate` when it is on PATH, else `rio convert` (the same GDAL CreateCopy, from
the GDAL rasterio is built with). Reports the best wall time, peak resident memory
(bench/_measure.py) and CPU time of each, with the ratios pdsgen / GDAL.
Targets (issue 20): time <= 1.0 x GDAL, memory <= 0.5 x GDAL. The issue's size is
25,000^2; on a small shared machine use --size to run smaller, and say so.

    python bench/hrsc_ax.py [--size 25000] [--repeat 1]
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

from _measure import Run, best_of

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from hrsc_ax_tiles import map_group, tile_name  # noqa: E402  (the tests' independent VICAR writer)

TARGET_TIME, TARGET_MEMORY = 1.0, 0.5


def write_channel(path: Path, size: int, seed: int) -> None:
    """A textured BYTE VICAR channel written row block by row block (memory stays small)."""
    import hrsc_ax_tiles

    # The label comes from the tests' writer on a one-line stand-in; the rows follow it.
    probe = path.with_suffix(path.suffix + ".probe")
    hrsc_ax_tiles.write_vicar(probe, np.zeros((1, size), np.uint8), {"MAP": map_group(430000.0, 8765000.0, 0.2)})
    head = probe.read_bytes()[:-size]
    probe.unlink()
    text = head.decode("ascii").replace("NL=1 ", f"NL={size} ").replace("N2=1 ", f"N2={size} ")
    rng = np.random.default_rng(seed)
    xx = np.arange(size, dtype=np.float32)[None, :]
    with open(path, "wb") as handle:
        handle.write(text.encode("ascii"))
        for top in range(0, size, 512):
            rows = min(512, size - top)
            yy = np.arange(top, top + rows, dtype=np.float32)[:, None]
            relief = 60 * np.sin(yy / 97.0) * np.cos(xx / 131.0) + 30 * np.sin((xx + yy) / 23.0)
            noise = rng.normal(scale=12.0, size=(rows, size)).astype(np.float32)
            handle.write(np.clip(128 + relief + noise, 1, 254).astype(np.uint8).tobytes())


def gdal_command(source: Path, target: Path) -> list[str]:
    options = ["REVERSIBLE=YES", "QUALITY=100"]
    if shutil.which("gdal_translate"):
        return ["gdal_translate", "-q", "-of", "JP2OpenJPEG", *sum((["-co", o] for o in options), []),
                str(source), str(target)]
    rio = Path(sys.executable).with_name("rio")
    options += ["BLOCKXSIZE=1024", "BLOCKYSIZE=1024"]  # gdal_translate's default tiles (rio copies the input's)
    return [str(rio), "convert", "--driver", "JP2OpenJPEG", *sum((["--co", o] for o in options), []),
            str(source), str(target)]


def rgb_vrt(paths: list[Path], size: int, target: Path) -> Path:
    bands = "".join(
        f'<VRTRasterBand dataType="Byte" band="{i}"><SimpleSource><SourceFilename relativeToVRT="0">{p}'
        f"</SourceFilename><SourceBand>1</SourceBand></SimpleSource></VRTRasterBand>"
        for i, p in enumerate(paths, start=1))
    target.write_text(f'<VRTDataset rasterXSize="{size}" rasterYSize="{size}">{bands}</VRTDataset>')
    return target


def compare(name: str, ours: list[str], ours_out: Path, gdal: list[str], gdal_out: Path, repeat: int,
            env: dict[str, str]) -> tuple[Run, Run]:
    ours_runs, gdal_runs = [], []
    for _ in range(repeat):
        gdal_runs.append(best_of(gdal, 1, [str(gdal_out), str(gdal_out) + ".aux.xml"], env))
        ours_runs.append(best_of(ours, 1, [str(ours_out)], env))
    return min(ours_runs, key=lambda r: r.seconds), min(gdal_runs, key=lambda r: r.seconds)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=25000)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    src = str(Path(__file__).resolve().parent.parent / "src")
    env = {**os.environ, "PYTHONPATH": src + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "GDAL_NUM_THREADS": "ALL_CPUS"}
    print(f"HRSC-AX {args.size}^2 channels to lossless JP2: pdsgen ortho --profile hrsc-ax vs "
          f"{gdal_command(Path('in'), Path('out'))[0].split('/')[-1]} JP2OpenJPEG REVERSIBLE=YES QUALITY=100; "
          f"{os.cpu_count()} cores")
    print(f"{'product':8}{'wall s: pdsgen':>15}{'gdal':>8}{'ratio':>7}{'cpu ratio':>10}"
          f"{'peak MB: pdsgen':>17}{'gdal':>8}{'ratio':>7}")
    with tempfile.TemporaryDirectory(prefix="bench-hrsc-ax-") as tmp:
        work = Path(tmp)
        stem = tile_name(430, 8765, args.size, 0.2)
        channels = {ext: work / f"{stem}.{ext}" for ext in ("pan", "re", "gr", "bl")}
        for seed, path in enumerate(channels.values()):
            write_channel(path, args.size, seed)
        cases = {
            "pan": ([str(channels["pan"])], channels["pan"]),
            "RGB": ([str(channels[c]) for c in ("re", "gr", "bl")],
                    rgb_vrt([channels[c] for c in ("re", "gr", "bl")], args.size, work / "rgb.vrt")),
        }
        for name, (inputs, gdal_source) in cases.items():
            ours_out, gdal_out = work / f"pdsgen_{name}", work / f"gdal_{name}.jp2"
            ours = [sys.executable, "-m", "pdsgen", "ortho", *inputs, "--profile", "hrsc-ax", "-o", str(ours_out)]
            mine, theirs = compare(name, ours, ours_out, gdal_command(gdal_source, gdal_out), gdal_out,
                                   args.repeat, env)
            print(f"{name:8}{mine.seconds:15.2f}{theirs.seconds:8.2f}{mine.seconds / theirs.seconds:7.2f}"
                  f"{mine.cpu_seconds / max(theirs.cpu_seconds, 1e-9):10.2f}{mine.peak_mb:17.1f}"
                  f"{theirs.peak_mb:8.1f}{mine.peak_mb / theirs.peak_mb:7.2f}")
    print(f"targets: time <= {TARGET_TIME} x, memory <= {TARGET_MEMORY} x GDAL")


if __name__ == "__main__":
    main()
