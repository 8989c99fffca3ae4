"""Benchmark `pdsgen deliver` and `pdsgen validate` on a delivery of many products.

Usage: python bench/deliver.py [--products 10000] [--dialect pds3|both] [--repeat 1] [--no-baselines]

Products are made at run time: one small DTM (.IMG with its attached PDS3 label, and with
--dialect both its PDS4 label) written by pdsgen, copied --products times under distinct
PRODUCT_IDs (same label, same data; the PDS4 label's file name and MD5 follow). Then:
- deliver: `pdsgen deliver SRC -o OUT --pds3|--both` (index, volume files; bundle,
  collections and inventories; MD5 manifest) beside a
  baseline a hand-made script would at least do: hard-link the tree and md5sum every file;
- validate: `pdsgen validate OUT` (every label, the index against every label, the manifest)
  beside `md5sum -c` of the manifest, and `pdsgen validate OUT --labels-only` (the checks
  deliver's review page runs);
- deliver / validate: deliver's time (with its review page) over validate's alone on the same
  delivery, the issue 42 target being at most 1.5 (each label is parsed once per deliver run).
  --no-baselines leaves out the cp/md5sum baselines (a shorter run at 10,000 products).
Each command runs in a fresh process (bench/_measure.py): wall time, CPU time and peak RSS.
On a shared machine the wall figures follow the neighbours; the CPU ratio is the steadier one.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _measure import Run, best_of  # noqa: E402

TEMPLATE_ID = "DTEEC_008669_1705_009025_1705_U01"


def make_products(directory: Path, count: int, label: str = "pds3") -> None:
    """`count` copies of one small pdsgen DTM, each under its own PRODUCT_ID and file name."""
    import numpy as np

    from pdsgen.products.dtm import write_dtm
    from pdsgen.synthetic import make_scene, write_geotiff

    scene = make_scene(width=64, height=64)
    work = directory.parent / "template"
    work.mkdir()
    heights = (-4000.0 + np.arange(16 * 16, dtype="float32").reshape(16, 16)).astype("float32")
    source = write_geotiff(work / "dtm.tif", heights, scene.transform, scene.crs, None)
    product = write_dtm(source, work, profile="hirise", source_product_ids=("PSP_008669_1705", "PSP_009025_1705"),
                        institution="U", label=label)
    data = product.path.read_bytes()
    xml = product.pds4_label_path.read_text() if label == "both" else ""
    directory.mkdir()
    for number in range(count):
        product_id = f"DTEEC_{number:06d}_1705_009025_1705_U01"  # same length: the label's layout holds
        copy = data.replace(TEMPLATE_ID.encode(), product_id.encode())
        (directory / f"{product_id}.IMG").write_bytes(copy)
        if xml:
            text = xml.replace(TEMPLATE_ID, product_id).replace(TEMPLATE_ID.lower(), product_id.lower())
            text = text.replace(hashlib.md5(data).hexdigest(), hashlib.md5(copy).hexdigest())
            (directory / f"{product_id}.xml").write_text(text)


def report(title: str, count: int, ours: Run, baseline: Run, baseline_name: str) -> None:
    print(title)
    print(f"  {'':34s} {'wall s':>8s} {'CPU s':>8s} {'peak MB':>8s} {'products/s':>11s}")
    for name, run in (("pdsgen", ours), (baseline_name, baseline)):
        print(f"  {name:34s} {run.seconds:8.2f} {run.cpu_seconds:8.2f} {run.peak_mb:8.1f} {count / run.seconds:11.0f}")
    print(f"  ratio pdsgen/baseline: wall {ours.seconds / baseline.seconds:.2f}, "
          f"CPU {ours.cpu_seconds / max(baseline.cpu_seconds, 1e-9):.2f}, memory {ours.peak_mb / baseline.peak_mb:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--products", type=int, default=10000)
    parser.add_argument("--dialect", choices=("pds3", "both"), default="pds3")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--no-baselines", action="store_true", help="leave out the cp/md5sum baselines")
    args = parser.parse_args()
    pdsgen = shutil.which("pdsgen", path=str(Path(sys.executable).parent)) or "pdsgen"
    with tempfile.TemporaryDirectory(prefix="pdsgen-bench-deliver-") as tmp:
        root = Path(tmp)
        source = root / "products"
        make_products(source, args.products, args.dialect)
        out, copy = root / "delivery", root / "baseline"
        print(f"{args.products} products, --{args.dialect}; "
              f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
        ours = best_of([pdsgen, "deliver", str(source), "-o", str(out), f"--{args.dialect}", "--volume-id",
                        "BENCH_0001", "--bundle-lid", "urn:nasa:pds:bench"], args.repeat, [str(out)])
        deliver = ours
        if not args.no_baselines:
            baseline = best_of(["sh", "-c", f"cp -al '{source}' '{copy}' && cd '{copy}' && "
                                            "find . -type f -exec md5sum {} + > MD5SUMS.TXT"], args.repeat, [str(copy)])
            report("deliver", args.products, ours, baseline, "cp -al + md5sum of every file")
        validate = best_of([pdsgen, "validate", str(out), "--quiet"], args.repeat, [])
        if not args.no_baselines:
            baseline = best_of(["sh", "-c", f"cd '{out}' && md5sum -c --quiet MD5SUMS.TXT"], args.repeat, [])
            report("validate", args.products, validate, baseline, "md5sum -c MD5SUMS.TXT")
        labels_only = best_of([pdsgen, "validate", str(out), "--quiet", "--labels-only"], args.repeat, [])
        compare(args.products, deliver, validate, labels_only)


def compare(count: int, deliver: Run, validate: Run, labels_only: Run) -> None:
    """Deliver (with its review page) beside validate alone on the same delivery."""
    print(f"deliver (with review page) / validate alone, {count} products (target <= 1.5)")
    print(f"  {'':34s} {'wall s':>8s} {'CPU s':>8s} {'peak MB':>8s}")
    for name, run in (("pdsgen deliver", deliver), ("pdsgen validate", validate),
                      ("pdsgen validate --labels-only", labels_only)):
        print(f"  {name:34s} {run.seconds:8.2f} {run.cpu_seconds:8.2f} {run.peak_mb:8.1f}")
    for name, alone in (("validate", validate), ("validate --labels-only", labels_only)):
        print(f"  ratio deliver/{name}: wall {deliver.seconds / alone.seconds:.2f}, "
              f"CPU {deliver.cpu_seconds / max(alone.cpu_seconds, 1e-9):.2f}")


if __name__ == "__main__":
    main()
