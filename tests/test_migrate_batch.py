"""`[[migrate]]` jobs in `pdsgen batch` (a real Dask LocalCluster): genuine PDS3 products migrated,
a refused one failing only its own job, and a second run skipping what the first finished."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
from pathlib import Path

from conftest import CORPUS_DIR

PRODUCTS = CORPUS_DIR / "products"
BIN = Path(sys.executable).parent


def test_migrate_jobs_run_validate_and_resume(tmp_path):
    manifest = tmp_path / "volume.toml"
    manifest.write_text(f"""
[batch]
outdir = "out"

[defaults.migrate]
bundle_lid = "urn:nasa:pds:migrated_volume"

[[migrate]]
id = "mola"
inputs = ["{PRODUCTS / 'MOLA_MEGDR_megt90n000cb' / 'megt90n000cb.lbl'}"]
outdir = "data"

[[migrate]]
id = "magellan"
inputs = ["{PRODUCTS / 'MGN_FMIDR_FF01' / 'FF01.LBL'}", "{PRODUCTS / 'MPF_IMP_i985135l' / 'i985135l.img'}"]
outdir = "data"

[[migrate]]
id = "truncated"
inputs = ["{PRODUCTS / 'synthetic_pds3_1band' / 'pds3_1band.IMG'}"]
outdir = "data"

[[validate]]
id = "check"
after = ["mola", "magellan"]
""", encoding="utf-8")
    command = [BIN / "pdsgen", "batch", manifest, "--workers", "1"]
    first = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert first.returncode != 0  # the truncated product's job failed
    summary = json.loads((tmp_path / "out" / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    status = {j["id"]: j["status"] for j in summary["jobs"]}
    assert status == {"mola": "done", "magellan": "done", "truncated": "failed", "check": "done"}, status
    data = tmp_path / "out" / "data"
    assert sorted(p.name for p in data.iterdir()) == sorted([
        "FF01.IMG", "FF01.LBL", "FF01.xml", "i985135l.img", "i985135l.xml",
        "megt90n000cb.img", "megt90n000cb.lbl", "megt90n000cb.xml"])
    original = PRODUCTS / "MOLA_MEGDR_megt90n000cb" / "megt90n000cb.img"
    assert hashlib.md5((data / "megt90n000cb.img").read_bytes()).digest() == \
        hashlib.md5(original.read_bytes()).digest()
    assert "urn:nasa:pds:migrated_volume:data:megt90n000cb.img" in (data / "megt90n000cb.xml").read_text()
    stamp = (data / "FF01.xml").stat().st_mtime_ns

    second = subprocess.run(command, capture_output=True, text=True, timeout=300)
    summary = json.loads((tmp_path / "out" / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    status = {j["id"]: j["status"] for j in summary["jobs"]}
    assert status["mola"] == status["magellan"] == status["check"] == "skipped", status
    assert (data / "FF01.xml").stat().st_mtime_ns == stamp  # not made twice
    assert second.returncode != 0 and status["truncated"] == "failed"
