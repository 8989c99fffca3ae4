"""Benchmark `pdsgen migrate VOLUME_DIR`: a synthetic PDS3 volume of small products becomes a
PDS4 bundle; products per second and peak memory of the process.

Usage: python bench/migrate_volume.py [--products 10000] [--per-directory 500]

The volume: VOLDESC.CAT, CATALOG/DATASET.CAT, LABEL/SPECTRUM.FMT (the column description
every product's ^STRUCTURE names), INDEX/INDEX.LBL + INDEX.TAB (one row per product) and
DATA/Dnnn/Pnnnnnn.LBL + .TAB: a detached label and a 20-row ASCII table each. Measured by
bench/_measure.py (wall time, peak RSS of the `pdsgen migrate` process, start-up included):

- the full volume;
- a tenth of it, to show peak RSS does not grow with the number of products (the run keeps a
  few strings per product, never the parsed labels);
- with --batch: the same number of products as two volumes of half the size, migrated by two
  `[[migrate]]` jobs of one `pdsgen batch --workers 2` (Dask LocalCluster); the peak is the
  largest process's.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

from _measure import measure

DATA_SET = "BENCH-X-SYNTH-2-TABLE-V1.0"
ROW = "{:8.4f} {:8.4f}\r\n"  # 19 bytes + CR LF
ROWS = 20


def _label(product_id: str, table: str) -> str:
    lines = ["PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", "RECORD_BYTES = 19",
             f"FILE_RECORDS = {ROWS}", f'^TABLE = "{table}"', f'DATA_SET_ID = "{DATA_SET}"',
             f'PRODUCT_ID = "{product_id}"', 'TARGET_NAME = "MARS"', "OBJECT = TABLE", "  ROWS = 20",
             "  ROW_BYTES = 19", "  INTERCHANGE_FORMAT = ASCII", "  COLUMNS = 2",
             '  ^STRUCTURE = "SPECTRUM.FMT"', "END_OBJECT = TABLE", "END", ""]
    return "\r\n".join(lines)


FORMAT = "\r\n".join([
    "OBJECT = COLUMN", '  NAME = "WAVELENGTH"', "  DATA_TYPE = ASCII_REAL", "  START_BYTE = 1", "  BYTES = 8",
    '  UNIT = "MICRON"', '  DESCRIPTION = "Wavelength."', "END_OBJECT = COLUMN",
    "OBJECT = COLUMN", '  NAME = "REFLECTANCE"', "  DATA_TYPE = ASCII_REAL", "  START_BYTE = 10", "  BYTES = 8",
    '  DESCRIPTION = "Reflectance."', "END_OBJECT = COLUMN", ""])


def lay_out(root: Path, count: int, per_directory: int) -> None:
    """The volume of `count` products under `root`."""
    (root / "CATALOG").mkdir(parents=True)
    (root / "LABEL").mkdir()
    (root / "INDEX").mkdir()
    (root / "LABEL" / "SPECTRUM.FMT").write_text(FORMAT, newline="")
    (root / "VOLDESC.CAT").write_text("\r\n".join([
        "PDS_VERSION_ID = PDS3", "OBJECT = VOLUME", '  VOLUME_ID = "BENCH_0001"', '  VOLUME_NAME = "BENCH VOLUME"',
        f'  DATA_SET_ID = "{DATA_SET}"', "  PUBLICATION_DATE = 2026-01-01", '  DESCRIPTION = "A benchmark volume."',
        "  OBJECT = CATALOG", '    ^DATA_SET_CATALOG = "DATASET.CAT"', "  END_OBJECT = CATALOG",
        "END_OBJECT = VOLUME", "END", ""]), newline="")
    (root / "CATALOG" / "DATASET.CAT").write_text("\r\n".join([
        "PDS_VERSION_ID = PDS3", "OBJECT = DATA_SET", f'  DATA_SET_ID = "{DATA_SET}"',
        "  OBJECT = DATA_SET_INFORMATION", '    DATA_SET_NAME = "BENCHMARK SPECTRA"',
        "    DATA_SET_RELEASE_DATE = 2026-01-01", '    CITATION_DESC = "Bench, A., Benchmark spectra, 2026."',
        '    ABSTRACT_DESC = "Synthetic spectra for a benchmark."', "  END_OBJECT = DATA_SET_INFORMATION",
        "END_OBJECT = DATA_SET", "END", ""]), newline="")
    table = "".join(ROW.format(0.5 + i * 0.01, 0.2 + i * 0.001) for i in range(ROWS))
    width = len("DATA/D000/P000000.LBL")
    with open(root / "INDEX" / "INDEX.TAB", "w", newline="") as index:
        for n in range(count):
            directory = root / "DATA" / f"D{n // per_directory:03d}"
            if n % per_directory == 0:
                directory.mkdir(parents=True)
            name = f"P{n:06d}"
            (directory / f"{name}.TAB").write_text(table, newline="")
            (directory / f"{name}.LBL").write_text(_label(name, f"{name}.TAB").replace(
                '"SPECTRUM.FMT"', '"../../LABEL/SPECTRUM.FMT"'), newline="")
            path = (directory.relative_to(root) / f"{name}.LBL").as_posix()
            index.write(f'"{path:<{width}}","{name}"\r\n')
    row_bytes = width + 2 + 1 + 9 + 2
    (root / "INDEX" / "INDEX.LBL").write_text("\r\n".join([
        "PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", f"RECORD_BYTES = {row_bytes}",
        f"FILE_RECORDS = {count}", '^INDEX_TABLE = "INDEX.TAB"', f'DATA_SET_ID = "{DATA_SET}"', "OBJECT = INDEX_TABLE",
        "  INTERCHANGE_FORMAT = ASCII", f"  ROWS = {count}", f"  ROW_BYTES = {row_bytes}", "  COLUMNS = 2",
        "  OBJECT = COLUMN", '    NAME = "FILE_SPECIFICATION_NAME"', "    DATA_TYPE = CHARACTER",
        "    START_BYTE = 2", f"    BYTES = {width}", "  END_OBJECT = COLUMN",
        "  OBJECT = COLUMN", '    NAME = "PRODUCT_ID"', "    DATA_TYPE = CHARACTER",
        f"    START_BYTE = {width + 5}", "    BYTES = 7", "  END_OBJECT = COLUMN",
        "END_OBJECT = INDEX_TABLE", "END", ""]), newline="")


def run(products: int, per_directory: int) -> None:
    pdsgen = str(Path(sys.executable).with_name("pdsgen"))
    for count in (products // 10, products):
        with tempfile.TemporaryDirectory(prefix="bench-volume-") as scratch:
            volume = Path(scratch) / "BENCH_0001"
            lay_out(volume, count, per_directory)
            out = Path(scratch) / "bundle"
            measured = measure([pdsgen, "migrate", str(volume), "-o", str(out), "--bundle-lid",
                                "urn:nasa:pds:bench_volume"])
            labels = sum(1 for _ in out.rglob("*.xml"))
            print(f"{count:6d} products: {measured.seconds:7.1f} s, {count / measured.seconds:6.1f} products/s, "
                  f"peak RSS {measured.peak_mb:6.1f} MB ({labels} PDS4 labels written)")
            shutil.rmtree(out, ignore_errors=True)


def run_batch(products: int, per_directory: int) -> None:
    pdsgen = str(Path(sys.executable).with_name("pdsgen"))
    with tempfile.TemporaryDirectory(prefix="bench-volume-batch-") as scratch:
        jobs = []
        for part in ("A", "B"):
            volume = Path(scratch) / f"BENCH_000{part}"
            lay_out(volume, products // 2, per_directory)
            jobs.append(f'[[migrate]]\nid = "{part}"\ninputs = ["{volume}"]\noutdir = "bundle_{part}"\n'
                        f'bundle_lid = "urn:nasa:pds:bench_{part.lower()}"\n')
        manifest = Path(scratch) / "volumes.toml"
        manifest.write_text(f'[batch]\noutdir = "{Path(scratch) / "out"}"\n\n' + "\n".join(jobs), encoding="utf-8")
        measured = measure([pdsgen, "batch", str(manifest), "--workers", "2"])
        labels = sum(1 for _ in (Path(scratch) / "out").rglob("*.xml"))
        print(f"{products:6d} products as 2 volumes, 2 workers: {measured.seconds:7.1f} s, "
              f"{products / measured.seconds:6.1f} products/s, peak RSS {measured.peak_mb:6.1f} MB "
              f"({labels} PDS4 labels written)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--products", type=int, default=10000)
    parser.add_argument("--per-directory", type=int, default=500)
    parser.add_argument("--batch", action="store_true", help="also two volumes as two batch jobs on two workers")
    args = parser.parse_args()
    run(args.products, args.per_directory)
    if args.batch:
        run_batch(args.products, args.per_directory)


if __name__ == "__main__":
    main()
