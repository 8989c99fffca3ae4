"""Benchmark: all DTM Extras of an 8,000 x 8,000 float32 DTM, pdsgen vs GDAL tools.

The GDAL baseline makes the comparable images with the command-line tools:
`gdaldem hillshade` and `gdaldem color-relief` over the full raster, then
`gdal_translate -of JPEG -outsize ... -r average` for the greyscale, shaded and
colour browse (1024 px) and thumbnail (128 px) - six JPEGs, no annotation, no
shading blended into the colour. pdsgen makes its nine JPEGs (three of them
annotated) and README.TXT. Each side runs in a fresh runner process that reports
the wall time and the peak RSS of its children (getrusage RUSAGE_CHILDREN), so
the two measurements never mix.

With --memory-size N it also makes the Extras of an N x N DTM (pdsgen only) to show
that peak memory follows the preview size, not the raster size.

With --ortho-size N it makes the Extras of an N x N 16-bit orthoimage GeoTIFF - the
browse JPEGs and the full-scale QLOOK.JP2 - and of one of half that side, beside
`gdal_translate -of JP2OpenJPEG` making a lossy 8-bit JPEG 2000 of the same image
(-scale, REVERSIBLE=NO, QUALITY=5); peak RSS at both sizes shows whether the
quick look's memory grows with the raster (measured through bench/_measure.py).

With --nomap WIDTHxLINES it makes the six HiRISE NOMAP Extras (`--kind nomap`: RED,
IRB and RGB JP2s and browses, README.TXT) of a RED and an IRB NOMAP mosaic (10-bit
DNs in uint16 GeoTIFFs without georeferencing) at that size and at half the lines,
beside GDAL making what it can of the same: gdal_translate to lossy 8-bit JPEG 2000
(fixed -scale, REVERSIBLE=NO, QUALITY=5) and a 2048-wide JPEG browse of each mosaic
(no per-band percentile stretch, no synthetic-blue RGB: GDAL's tools have neither).
Peak RSS at both sizes shows whether memory grows with the mosaic.

Run: PYTHONPATH=src python bench/extras.py [--size 8000] [--memory-size 16000]
                                           [--ortho-size 12000] [--skip-dtm]
                                           [--nomap 2000x8000]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import numpy as np
import rasterio
from rasterio.transform import from_origin
from rasterio.windows import Window

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _measure import measure  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
NODATA = -3.4028226550889045e38
MARS_EQC = (
    'PROJCS["Mars equirectangular",GEOGCS["Mars",DATUM["D_Mars",SPHEROID["Mars",3396190,0]],'
    'PRIMEM["Reference_Meridian",0],UNIT["degree",0.0174532925199433]],'
    'PROJECTION["Equirectangular"],PARAMETER["standard_parallel_1",0],'
    'PARAMETER["central_meridian",0],PARAMETER["false_easting",0],'
    'PARAMETER["false_northing",0],UNIT["metre",1]]'
)

# The runner: time the given commands and report the peak RSS of its children.
RUNNER = textwrap.dedent("""
    import json, resource, subprocess, sys, time
    commands = json.loads(sys.argv[1])
    start = time.perf_counter()
    for command in commands:
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    print(json.dumps({"wall": wall, "peak_mib": peak_kib / 1024.0}))
""")


def make_dtm(path: Path, size: int) -> None:
    """A crater field with a no-data gap, written in strips (never all in memory)."""
    rng = np.random.default_rng(42)
    craters = [(rng.uniform(0, size), rng.uniform(0, size), rng.uniform(20, size / 8))
               for _ in range(150)]
    profile = {"driver": "GTiff", "width": size, "height": size, "count": 1,
               "dtype": "float32", "crs": MARS_EQC, "nodata": NODATA,
               "transform": from_origin(100000.0, 50000.0, 1.0, 1.0), "tiled": True,
               "blockxsize": 256, "blockysize": 256}
    strip = 512
    cols = np.arange(size, dtype=np.float32)
    with rasterio.open(path, "w", **profile) as ds:
        for top in range(0, size, strip):
            rows = np.arange(top, min(top + strip, size), dtype=np.float32)[:, None]
            z = (-4000.0 + 0.01 * cols + 0.005 * rows
                 + 15.0 * np.sin(cols / 97.0) * np.cos(rows / 131.0)).astype(np.float32)
            for cr, cc, radius in craters:
                if abs(cr - rows[0, 0]) > radius + strip:
                    continue
                d = np.hypot(rows - cr, cols - cc) / radius
                z -= np.where(d < 1.0, 0.2 * radius * (1.0 - d**2), 0.0).astype(np.float32)
            z[(rows[:, 0] > size * 0.4) & (rows[:, 0] < size * 0.45), : size // 10] = NODATA
            ds.write(z, 1, window=Window(0, top, size, z.shape[0]))


def make_ortho(path: Path, size: int) -> None:
    """A textured 16-bit orthoimage (DN 0 = no data along the left edge), written in strips."""
    profile = {"driver": "GTiff", "width": size, "height": size, "count": 1,
               "dtype": "uint16", "crs": MARS_EQC, "nodata": 0,
               "transform": from_origin(100000.0, 50000.0, 0.25, 0.25), "tiled": True,
               "blockxsize": 512, "blockysize": 512}
    strip = 512
    cols = np.arange(size, dtype=np.float32)
    rng = np.random.default_rng(5)
    with rasterio.open(path, "w", **profile) as ds:
        for top in range(0, size, strip):
            rows = np.arange(top, min(top + strip, size), dtype=np.float32)[:, None]
            dn = (400.0 + 250.0 * np.sin(cols / 83.0) * np.cos(rows / 61.0)
                  + rng.normal(0.0, 20.0, (rows.shape[0], size)))
            dn[:, : size // 20] = 0
            ds.write(np.clip(dn, 0, 1023).astype(np.uint16), 1,
                     window=Window(0, top, size, dn.shape[0]))


def ortho_bench(size: int) -> None:
    """pdsgen Extras of an orthoimage (with QLOOK.JP2) vs gdal_translate to lossy JP2."""
    env = {**os.environ, "PYTHONPATH": f"{REPO / 'src'}{os.pathsep}" + os.environ.get(
        "PYTHONPATH", "")}
    code = ("from pdsgen.extras import make_extras; import sys; "
            "make_extras([sys.argv[1]], sys.argv[2], overwrite=True)")
    rows = []
    for side in (size // 2, size):
        with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
            work = Path(tmp)
            tif = work / "ortho.tif"
            make_ortho(tif, side)
            ours = measure([sys.executable, "-c", code, str(tif), str(work / "extras")], env)
            qlook = work / "extras" / "ortho.QLOOK.JP2"
            gdal = measure(["gdal_translate", "-q", "-of", "JP2OpenJPEG", "-ot", "Byte",
                            "-scale", "1", "1023", "1", "255", "-co", "REVERSIBLE=NO",
                            "-co", "QUALITY=5", "-co", "BLOCKXSIZE=512", "-co",
                            "BLOCKYSIZE=512", str(tif), str(work / "gdal.jp2")], env)
            rows.append((side, ours, gdal, qlook.stat().st_size, tif.stat().st_size,
                         (work / "gdal.jp2").stat().st_size))
    print("Orthoimage Extras (browse, abrowse, thumb, QLOOK.JP2) vs gdal_translate lossy JP2")
    print(f"{'':30}{'wall s':>9}{'peak MB':>9}{'JP2 MB':>8}")
    for side, ours, gdal, ql_bytes, tif_bytes, gdal_bytes in rows:
        print(f"{side} x {side} uint16 ({tif_bytes / 2**20:.0f} MB GeoTIFF)")
        print(f"  {'pdsgen extras':28}{ours.seconds:>9.2f}{ours.peak_mb:>9.1f}"
              f"{ql_bytes / 2**20:>8.1f}")
        print(f"  {'gdal_translate JP2OpenJPEG':28}{gdal.seconds:>9.2f}{gdal.peak_mb:>9.1f}"
              f"{gdal_bytes / 2**20:>8.1f}")
        print(f"  ratio pdsgen/GDAL: time {ours.seconds / gdal.seconds:.2f}, "
              f"memory {ours.peak_mb / gdal.peak_mb:.2f}")
    small, large = rows[0][1], rows[1][1]
    print(f"pdsgen peak RSS at 4x the pixels: {large.peak_mb / small.peak_mb:.2f}x "
          f"({small.peak_mb:.0f} -> {large.peak_mb:.0f} MB; flat means ~1)")


def make_nomap(folder: Path, width: int, lines: int) -> tuple[Path, Path]:
    """RED and IRB NOMAP mosaics (uint16, 10-bit DNs, DN 0 at the edges), written in strips."""
    rng = np.random.default_rng(9)
    cols = np.arange(width, dtype=np.float32)
    paths = (folder / "PSP_005000_1000_RED.NOMAP.tif", folder / "PSP_005000_1000_IRB.NOMAP.tif")
    profiles = [{"driver": "GTiff", "width": width, "height": lines, "count": count,
                 "dtype": "uint16", "tiled": True, "blockxsize": 512, "blockysize": 512}
                for count in (1, 3)]
    with rasterio.Env(), rasterio.open(paths[0], "w", **profiles[0]) as red_ds, \
            rasterio.open(paths[1], "w", **profiles[1]) as irb_ds:
        for top in range(0, lines, 512):
            rows = np.arange(top, min(top + 512, lines), dtype=np.float32)[:, None]
            red = (500.0 + 250.0 * np.sin(cols / 37.0) * np.cos(rows / 53.0)
                   + rng.normal(0.0, 15.0, (rows.shape[0], width)))
            bg = 300.0 + 45.0 * np.cos(rows / 29.0 + cols / 61.0) + 0.1 * red
            ir = 0.6 * red + 150.0 + 30.0 * np.sin(rows / 41.0)
            irb = np.clip(np.stack([ir, red, bg]), 3, 1021).astype(np.uint16)
            irb[:, :, : width // 25] = 0
            window = Window(0, top, width, rows.shape[0])
            red_ds.write(irb[1], 1, window=window)
            irb_ds.write(irb, window=window)
    return paths


def nomap_bench(width: int, lines: int) -> None:
    """pdsgen's six NOMAP Extras vs GDAL's lossy JP2s and browses of the two mosaics."""
    env = {**os.environ, "PYTHONPATH": f"{REPO / 'src'}{os.pathsep}" + os.environ.get(
        "PYTHONPATH", "")}
    rows = []
    for height in (lines // 2, lines):
        with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
            work = Path(tmp)
            red, irb = make_nomap(work, width, height)
            ours = measure([sys.executable, "-m", "pdsgen", "extras", "--kind", "nomap",
                            str(red), str(irb), "-o", str(work / "extras"), "--overwrite"], env)
            gdal = measure(["sh", "-c", " && ".join(
                f"gdal_translate -q -of JP2OpenJPEG -ot Byte -scale 1 1023 1 255 "
                f"-co REVERSIBLE=NO -co QUALITY=5 -co BLOCKXSIZE=1024 -co BLOCKYSIZE=1024 "
                f"{src} {work / src.name}.jp2 && gdal_translate -q -of JPEG -ot Byte "
                f"-scale 1 1023 1 255 -r average -outsize 2048 0 {src} {work / src.name}.jpg"
                for src in (red, irb))], env)
            rows.append((height, ours, gdal))
    print(f"HiRISE NOMAP Extras (6 files + README) of a RED + IRB mosaic, {width} wide")
    print(f"{'':30}{'wall s':>9}{'CPU s':>9}{'peak MB':>9}")
    for height, ours, gdal in rows:
        print(f"{width} x {height} (RED {width * height * 2 / 2**20:.0f} MB + IRB "
              f"{width * height * 6 / 2**20:.0f} MB uint16)")
        print(f"  {'pdsgen extras --kind nomap':28}{ours.seconds:>9.2f}{ours.cpu_seconds:>9.2f}"
              f"{ours.peak_mb:>9.1f}")
        print(f"  {'gdal_translate (2 JP2, 2 JPEG)':28}{gdal.seconds:>9.2f}"
              f"{gdal.cpu_seconds:>9.2f}{gdal.peak_mb:>9.1f}")
        print(f"  ratio pdsgen/GDAL: time {ours.seconds / gdal.seconds:.2f}, CPU time "
              f"{ours.cpu_seconds / gdal.cpu_seconds:.2f}, memory {ours.peak_mb / gdal.peak_mb:.2f}")
    small, large = rows[0][1], rows[1][1]
    print(f"pdsgen peak RSS at 2x the lines: {large.peak_mb / small.peak_mb:.2f}x "
          f"({small.peak_mb:.0f} -> {large.peak_mb:.0f} MB; flat means ~1)")


def colour_file(path: Path) -> None:
    """Viridis control points over the DTM's range, for gdaldem color-relief."""
    stops = ["440154", "3b528b", "21918c", "5ec962", "fde725"]
    low, high = -5600.0, -3900.0
    lines = [f"{low + (high - low) * i / 4:.1f} {int(h[0:2], 16)} {int(h[2:4], 16)} "
             f"{int(h[4:6], 16)}" for i, h in enumerate(stops)]
    path.write_text("\n".join(lines + ["nv 0 0 0"]) + "\n")


def gdal_commands(dtm: Path, work: Path) -> list[list[str]]:
    hs, cr = work / "hs.tif", work / "cr.tif"
    colours = work / "colours.txt"
    colour_file(colours)
    commands = [
        ["gdaldem", "hillshade", "-q", "-az", "315", "-alt", "45", str(dtm), str(hs)],
        ["gdaldem", "color-relief", "-q", str(dtm), str(colours), str(cr)],
    ]
    for name, source, extra in (("br", dtm, ["-ot", "Byte", "-scale"]), ("sb", hs, []),
                                ("cb", cr, [])):
        for suffix, width in ((name, "1024"), (name[0] + "t", "128")):
            commands.append(["gdal_translate", "-q", "-of", "JPEG", "-co", "QUALITY=90",
                             "-r", "average", "-outsize", width, "0", *extra, str(source),
                             str(work / f"dtm.{suffix}.jpg")])
    return commands


def pdsgen_commands(dtm: Path, work: Path) -> list[list[str]]:
    code = ("from pdsgen.extras import make_extras; import sys; "
            "make_extras([sys.argv[1]], sys.argv[2], overwrite=True)")
    return [[sys.executable, "-c", code, str(dtm), str(work / "extras")]]


def run(commands: list[list[str]]) -> dict[str, float]:
    env = {**os.environ, "PYTHONPATH": f"{REPO / 'src'}{os.pathsep}" + os.environ.get(
        "PYTHONPATH", "")}
    out = subprocess.run([sys.executable, "-c", RUNNER, json.dumps(commands)], check=True,
                         capture_output=True, text=True, env=env)
    return json.loads(out.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=8000, help="DTM width and height")
    parser.add_argument("--memory-size", type=int, default=0,
                        help="also run pdsgen alone on an N x N DTM (e.g. 16000)")
    parser.add_argument("--ortho-size", type=int, default=12000,
                        help="orthoimage side for the QLOOK.JP2 run (0 to skip)")
    parser.add_argument("--skip-dtm", action="store_true", help="only the orthoimage run")
    parser.add_argument("--nomap", metavar="WIDTHxLINES", default="",
                        help="also the HiRISE NOMAP Extras of mosaics this size (e.g. 2000x8000)")
    args = parser.parse_args()
    for tool in ("gdaldem", "gdal_translate"):
        if shutil.which(tool) is None:
            sys.exit(f"bench/extras.py: {tool} not found (install gdal-bin)")
    if not args.skip_dtm:
        dtm_bench(args)
    if args.ortho_size:
        ortho_bench(args.ortho_size)
    if args.nomap:
        width, lines = (int(v) for v in args.nomap.lower().split("x"))
        nomap_bench(width, lines)


def dtm_bench(args: argparse.Namespace) -> None:
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
        work = Path(tmp)
        dtm = work / "dtm.tif"
        make_dtm(dtm, args.size)
        gdal_work = work / "gdal"
        gdal_work.mkdir()
        gdal = run(gdal_commands(dtm, gdal_work))
        ours = run(pdsgen_commands(dtm, work))
        made = sorted(p.name for p in (work / "extras").iterdir())
    size_mib = args.size * args.size * 4 / 2**20
    print(f"DTM {args.size} x {args.size} float32 ({size_mib:.0f} MiB), all DTM Extras")
    print(f"{'':28}{'wall s':>10}{'peak RSS MiB':>15}")
    print(f"{'GDAL tools (6 JPEGs)':28}{gdal['wall']:>10.2f}{gdal['peak_mib']:>15.1f}")
    print(f"{'pdsgen extras (9 + README)':28}{ours['wall']:>10.2f}{ours['peak_mib']:>15.1f}")
    print(f"{'ratio pdsgen / GDAL':28}{ours['wall'] / gdal['wall']:>10.2f}"
          f"{ours['peak_mib'] / gdal['peak_mib']:>15.2f}")
    print("pdsgen wrote: " + ", ".join(made))
    ok = ours["wall"] / gdal["wall"] <= 0.5 and ours["peak_mib"] < gdal["peak_mib"]
    print("target (wall ratio <= 0.5, lower peak memory):", "met" if ok else "NOT met")
    if args.memory_size:
        with tempfile.TemporaryDirectory(prefix="pdsgen-bench-") as tmp:
            dtm = Path(tmp) / "dtm.tif"
            make_dtm(dtm, args.memory_size)
            big = run(pdsgen_commands(dtm, Path(tmp)))
        big_mib = args.memory_size**2 * 4 / 2**20
        print(f"pdsgen on {args.memory_size} x {args.memory_size} ({big_mib:.0f} MiB): "
              f"{big['wall']:.2f} s, peak RSS {big['peak_mib']:.1f} MiB "
              f"(vs {ours['peak_mib']:.1f} MiB at {args.size} x {args.size})")


if __name__ == "__main__":
    main()
