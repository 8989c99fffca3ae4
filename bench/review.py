"""Benchmark the review page: writing it (`pdsgen review`) and loading it in a browser.

Usage: python bench/review.py [--products 10000] [--repeat 1] [--no-demo]

- demo: the demo delivery (`pdsgen demo`, then `pdsgen deliver --pds3`), its page written by
  `pdsgen review` beside `pdsgen validate --format json` of the same delivery (the same checks
  without the page: the ratio is what the page adds);
- N small products: synthetic PDS3 labels written here from the PDS3 Standards' keywords (not
  by pdsgen's writer), one 8 x 8 float image each, spread over Mars on a grid of latitudes and
  longitudes, each with a thumbnail JPEG; made a volume by `pdsgen deliver`, then the same pair;
- loading: headless Chromium on the page's file URL (to the end of the load, scripts run and
  the first screenful drawn: --screenshot) beside the same on a blank page; for a review in
  pages, the first page (summary, map of every footprint, first products) and a later one.
Each command runs in a fresh process (bench/_measure.py): wall time, CPU time and peak RSS.
"""

from __future__ import annotations

import argparse
import io
import math
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _measure import Run, best_of  # noqa: E402

MARS_R_KM = 3396.19
POSTS = 8
SCALE_M = 1000.0


def _label(product_id: str, lat: float, lon: float) -> str:
    """A detached PDS3 label of an 8 x 8 equirectangular PC_REAL image whose upper-left corner
    is at (lat, lon); offsets by the standard convention (PDS3 Standards Reference, ch. 4)."""
    radius_m = MARS_R_KM * 1000.0
    ulx = math.radians(lon - 180.0) * radius_m
    uly = math.radians(lat) * radius_m
    deg = math.degrees(SCALE_M / radius_m)
    return "\r\n".join([
        "PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", f"RECORD_BYTES = {POSTS * 4}",
        f"FILE_RECORDS = {POSTS}", f'^IMAGE = "{product_id}.IMG"',
        f'PRODUCT_ID = "{product_id}"', 'DATA_SET_ID = "SYNTHETIC-M-DTM-V1.0"', "TARGET_NAME = MARS",
        "PRODUCT_CREATION_TIME = 2026-01-01T00:00:00", 'INSTRUMENT_ID = "SYNTHETIC"',
        "OBJECT = IMAGE", f"  LINES = {POSTS}", f"  LINE_SAMPLES = {POSTS}", "  BANDS = 1",
        "  SAMPLE_TYPE = PC_REAL", "  SAMPLE_BITS = 32", "  UNIT = METER",
        "  VALID_MINIMUM = -4000.0", f"  VALID_MAXIMUM = {-4000.0 + POSTS * POSTS - 1:.1f}",
        "END_OBJECT = IMAGE",
        "OBJECT = IMAGE_MAP_PROJECTION", '  MAP_PROJECTION_TYPE = "EQUIRECTANGULAR"',
        f"  A_AXIS_RADIUS = {MARS_R_KM} <KM>", f"  B_AXIS_RADIUS = {MARS_R_KM} <KM>",
        f"  C_AXIS_RADIUS = {MARS_R_KM} <KM>", "  POSITIVE_LONGITUDE_DIRECTION = EAST",
        "  CENTER_LATITUDE = 0.0 <DEG>", "  CENTER_LONGITUDE = 180.0 <DEG>",
        f"  MAP_SCALE = {SCALE_M} <METERS/PIXEL>",
        f"  MAP_RESOLUTION = {1.0 / deg:.10f} <PIX/DEG>",
        f"  MAXIMUM_LATITUDE = {lat:.10f} <DEG>", f"  MINIMUM_LATITUDE = {lat - POSTS * deg:.10f} <DEG>",
        f"  WESTERNMOST_LONGITUDE = {lon:.10f} <DEG>", f"  EASTERNMOST_LONGITUDE = {lon + POSTS * deg:.10f} <DEG>",
        f"  LINE_PROJECTION_OFFSET = {uly / SCALE_M - 0.5:.4f} <PIXEL>",
        f"  SAMPLE_PROJECTION_OFFSET = {-ulx / SCALE_M - 0.5:.4f} <PIXEL>",
        "END_OBJECT = IMAGE_MAP_PROJECTION", "END", "",
    ])


def make_products(directory: Path, count: int) -> None:
    """`count` small products over Mars (a grid of positions), each with a thumbnail."""
    import numpy as np
    from PIL import Image

    directory.mkdir()
    (directory / "extras").mkdir()
    data = (-4000.0 + np.arange(POSTS * POSTS, dtype="<f4")).tobytes()
    thumb = io.BytesIO()
    Image.fromarray(np.arange(64 * 64, dtype=np.uint8).reshape(64, 64)).save(thumb, "JPEG", quality=80)
    side = math.ceil(math.sqrt(count))
    for number in range(count):
        lat = -60.0 + 120.0 * (number // side) / side
        lon = 360.0 * (number % side + 0.5) / side  # clear of the 0/360 seam
        product_id = f"SYN_{number:06d}"
        (directory / f"{product_id}.LBL").write_bytes(_label(product_id, lat, lon).encode("ascii"))
        (directory / f"{product_id}.IMG").write_bytes(data)
        (directory / "extras" / f"{product_id}.th.jpg").write_bytes(thumb.getvalue())


def report(title: str, rows: list[tuple[str, Run]], count: int) -> None:
    print(title)
    print(f"  {'':40s} {'wall s':>8s} {'CPU s':>8s} {'peak MB':>8s}")
    for name, run in rows:
        print(f"  {name:40s} {run.seconds:8.2f} {run.cpu_seconds:8.2f} {run.peak_mb:8.1f}")
    ours, baseline = rows[0][1], rows[1][1]
    print(f"  ratio: wall {ours.seconds / baseline.seconds:.2f}, CPU {ours.cpu_seconds / baseline.cpu_seconds:.2f}"
          f" ({count} product(s))")


def _chromium(page: Path, profile: Path, shot: Path) -> list[str]:
    binary = shutil.which("chromium") or "chromium"
    return [binary, "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={profile}", "--no-first-run",
            "--disable-background-networking", "--disable-component-update",
            "--host-resolver-rules=MAP * ~NOTFOUND", "--window-size=1280,1600", f"--screenshot={shot}",
            page.resolve().as_uri()]


def review_pair(pdsgen: str, delivery: Path, repeat: int, count: int, title: str, baseline: bool) -> list[Path]:
    """Time `pdsgen review` (beside `validate --format json` unless baseline is False); the pages."""
    page = delivery.parent / f"{delivery.name}-review.html"
    ours = best_of([pdsgen, "review", str(delivery), "-o", str(page), "--quiet"], repeat, [str(page)])
    if baseline:
        other = best_of(["sh", "-c", f"'{pdsgen}' validate '{delivery}' --format json > /dev/null; "
                                     "test $? -le 1"], repeat, [])
        report(title, [("pdsgen review (checks + page)", ours), ("pdsgen validate --format json", other)], count)
    else:
        print(f"{title}\n  pdsgen review (checks + page): wall {ours.seconds:.2f} s, CPU {ours.cpu_seconds:.2f} s, "
              f"peak {ours.peak_mb:.1f} MB")
    pages = [page] + sorted(page.parent.glob(f"{page.stem}-*.html"), key=lambda p: int(p.stem.rsplit("-", 1)[1]))
    sizes = [p.stat().st_size / 1e6 for p in pages]
    print(f"  {len(pages)} page(s): the first {sizes[0]:.2f} MB, the others up to {max(sizes[1:] or [0]):.2f} MB, "
          f"{sum(sizes):.1f} MB in all")
    return pages


def load_pair(pages: list[Path], repeat: int, count: int, work: Path) -> None:
    blank = work / "blank.html"
    blank.write_text("<!DOCTYPE html><title>blank</title>")
    profile, shot = work / "chromium-profile", work / "shot.png"
    rows = [("the review page" if len(pages) == 1 else f"the first page ({pages[0].name})",
             best_of(_chromium(pages[0], profile, shot), repeat, [str(profile), str(shot)]))]
    baseline = best_of(_chromium(blank, profile, shot), repeat, [str(profile), str(shot)])
    rows.append(("a blank page", baseline))
    if len(pages) > 1:
        later = pages[len(pages) // 2]
        rows.append((f"a later page ({later.name})", best_of(_chromium(later, profile, shot), repeat,
                                                               [str(profile), str(shot)])))
    report(f"Chromium loads the page ({count} products; headless, to the first screenful)", rows, count)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--products", type=int, default=10000)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--no-demo", action="store_true", help="only the synthetic products")
    parser.add_argument("--no-baseline", action="store_true",
                        help="time review alone (not validate --format json beside it)")
    args = parser.parse_args()
    pdsgen = str(Path(sys.executable).with_name("pdsgen"))
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-review-") as tmp:
        work = Path(tmp)
        if not args.no_demo:
            subprocess.run([pdsgen, "demo", str(work / "demo"), "--quiet"], check=True)
            subprocess.run([pdsgen, "deliver", str(work / "demo"), "-o", str(work / "demo-volume"), "--pds3",
                            "--volume-id", "DEMO_0001", "--quiet"], check=True)
            pages = review_pair(pdsgen, work / "demo-volume", args.repeat, 2, "Demo delivery: the review page",
                                not args.no_baseline)
            load_pair(pages, args.repeat, 2, work)
        make_products(work / "synthetic", args.products)
        subprocess.run([pdsgen, "deliver", str(work / "synthetic"), "-o", str(work / "volume"), "--pds3",
                        "--volume-id", "SYN_0001", "--quiet"], check=True)
        pages = review_pair(pdsgen, work / "volume", args.repeat, args.products,
                            f"{args.products} small products: the review page", not args.no_baseline)
        load_pair(pages, args.repeat, args.products, work)
        os.sync()


if __name__ == "__main__":
    main()
