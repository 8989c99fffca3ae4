"""Benchmark `pdsgen migrate`: 1,000 PDS3 products described in PDS4 labels, labels per second
and peak memory, side by side with GDAL's label-only PDS4 writer on the same products.

Usage: python bench/migrate.py [--products 1000] [--repeat 1] [--mixed]

With --mixed the products also include the genuine ones of tests/data/migrate_objects
(CRISM CDR4 combined label, Galileo NIMS FITS header + SPECTRAL_QUBE, MARIE ASCII table
with its TABLE_HEADER and ^STRUCTURE in the volume's LABEL/), one in every six products
of each; the GDAL baseline is then left out (it takes rasters only).

The products are the genuine small ones of tests/data/corpus/products (Mars Pathfinder IMP
with its attached label, CRISM MRDR and Magellan F-MIDR with detached labels), one per
directory: labels copied, the detached products' data files hard links to the one copy
(nothing large on disk; every run still reads every data file whole for its MD5).

- pdsgen: one `pdsgen migrate --in-place` process over all the labels (the command line
  users run, start-up included): each product's label read, objects described, data file
  digested, cart: computed (CRISM, Magellan), PDS4 label rendered and written.
- baseline: GDAL 3.6's PDS4 driver with CREATE_LABEL_ONLY=YES (`gdal.Translate` in one
  Python process over the same products): a label-only PDS4 label of each raster, without
  Header, special constants, tables or identification (GDAL writes no MD5 either).
- memory: the pdsgen run over a tenth of the products, to show peak RSS does not grow with
  the number of inputs.

Both are measured by bench/_measure.py (wall time, peak RSS of the process).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

from _measure import measure

REPO = Path(__file__).resolve().parents[1]
PRODUCTS = REPO / "tests" / "data" / "corpus" / "products"
# (directory, label, data file or None for an attached label)
KINDS = (
    ("MPF_IMP_i985135l", "i985135l.img", None),
    ("CRISM_MRDR_t1865_cropped", "t1865_mrrde_70n185_0256_1_cropped.lbl", "t1865_mrrde_70n185_0256_1_cropped.img"),
    ("MGN_FMIDR_FF01", "FF01.LBL", "FF01.IMG"),
)
OBJECTS = REPO / "tests" / "data" / "migrate_objects"
# (directory under tests/data/migrate_objects, label, data files)
MIXED_KINDS = (
    ("", "CDR410000000000_AT0300020L_2.LBL", ("CDR410000000000_AT0300020L_2.IMG",)),
    ("", "gaspra_nims_hires_radiance_cropped.lbl", ("gaspra_nims_hires_radiance_cropped.fit",)),
    ("marie", "DATA/PWR02176_01.LBL", ("DATA/PWR02176_01.TAB", "LABEL/PWR.FMT")),
)
BASELINE = """
import sys
from osgeo import gdal
gdal.UseExceptions()
gdal.PushErrorHandler("CPLQuietErrorHandler")
for label in open(sys.argv[1]).read().split("\\n"):
    gdal.Translate(label + ".gdal.xml", label, format="PDS4", creationOptions=["CREATE_LABEL_ONLY=YES"])
"""


def lay_out(root: Path, count: int, mixed: bool = False) -> list[Path]:
    """`count` product directories, each a copy of one genuine product (data linked)."""
    labels = []
    for n in range(count):
        if mixed and n % 2:
            labels.append(_lay_out_object_product(root / f"p{n:05d}", MIXED_KINDS[(n // 2) % len(MIXED_KINDS)]))
            continue
        folder, label, data = KINDS[n % len(KINDS)]
        target = root / f"p{n:05d}"
        target.mkdir(parents=True)
        shutil.copyfile(PRODUCTS / folder / label, target / label)
        if data is not None:
            _link(PRODUCTS / folder / data, target / data)
        labels.append(target / label)
    return labels


def _lay_out_object_product(target: Path, kind: tuple[str, str, tuple[str, ...]]) -> Path:
    folder, label, data = kind
    for name in (label, *data):
        (target / name).parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(OBJECTS / folder / label, target / label)
    for name in data:
        _link(OBJECTS / folder / name, target / name)
    return target / label


def _link(source: Path, target: Path) -> None:
    """A hard link (the containment rule refuses a symbolic link leading out of the product's
    tree), a copy where the temporary directory is on another file system."""
    try:
        os.link(source, target)
    except OSError:
        shutil.copyfile(source, target)


def clean(labels: list[Path]) -> None:
    for label in labels:
        for made in label.parent.glob("*.xml"):
            made.unlink()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--products", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--mixed", action="store_true", help="half the products of the new object classes")
    args = parser.parse_args()
    pdsgen = str(Path(sys.executable).parent / "pdsgen")
    with tempfile.TemporaryDirectory(prefix="bench-migrate-") as tmp:
        root = Path(tmp)
        labels = lay_out(root / "products", args.products, args.mixed)
        widen = ["--root", str(root / "products")] if args.mixed else []
        listing = root / "labels.txt"
        listing.write_text("\n".join(map(str, labels)))
        runs, small, gdal = [], [], []
        for _ in range(args.repeat):
            clean(labels)
            runs.append(measure([pdsgen, "migrate", "-q", "--in-place", *widen, *map(str, labels)]))
            made = sum(1 for label in labels if label.with_suffix(".xml").is_file())
            clean(labels)
            small.append(measure([pdsgen, "migrate", "-q", "--in-place", *widen,
                                  *map(str, labels[: args.products // 10])]))
            clean(labels)
            if not args.mixed:
                gdal.append(measure(["/usr/bin/python3", "-c", BASELINE, str(listing)]))
        ours, tenth = (min(r, key=lambda run: run.seconds) for r in (runs, small))
    n = args.products
    kinds = "IMP, CRISM MRDR, Magellan F-MIDR" + (", CRISM CDR4, NIMS qube, MARIE table" if args.mixed else "")
    print(f"pdsgen migrate: {n} genuine PDS3 products ({kinds}), load {os.getloadavg()[0]:.1f}")
    print(f"  {'':34s} {'wall s':>8s} {'labels/s':>9s} {'peak MB':>8s}")
    print(f"  {'pdsgen migrate --in-place':34s} {ours.seconds:8.2f} {n / ours.seconds:9.1f} {ours.peak_mb:8.1f}")
    print(f"  {f'pdsgen, {n // 10} products':34s} {tenth.seconds:8.2f} {n // 10 / tenth.seconds:9.1f} "
          f"{tenth.peak_mb:8.1f}")
    if gdal:
        baseline = min(gdal, key=lambda run: run.seconds)
        print(f"  {'GDAL PDS4 CREATE_LABEL_ONLY':34s} {baseline.seconds:8.2f} {n / baseline.seconds:9.1f} "
              f"{baseline.peak_mb:8.1f}")
        print(f"  ratio pdsgen/GDAL: time {ours.seconds / baseline.seconds:.2f}, memory "
              f"{ours.peak_mb / baseline.peak_mb:.2f}")
    print(f"  peak RSS {n} vs {n // 10} products: {ours.peak_mb / tenth.peak_mb:.2f}")
    if made != n:
        raise SystemExit(f"only {made} of {n} labels were written")


if __name__ == "__main__":
    main()
