"""`[[migrate]]` jobs of whole volumes in `pdsgen batch` (a real Dask LocalCluster, two workers):
each volume becomes its bundle, a validate job after them finds the bundles clean, and a second
run skips the finished jobs without remaking them."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

VOLUME = Path(__file__).parent / "data" / "volume_fbirtfspec"
BIN = Path(sys.executable).parent


def test_volume_jobs_run_on_two_workers_validate_and_resume(tmp_path):
    for name in ("SBN_0233_A", "SBN_0233_B"):
        shutil.copytree(VOLUME, tmp_path / name)
    manifest = tmp_path / "volumes.toml"
    manifest.write_text(f"""
[batch]
outdir = "out"

[[migrate]]
id = "a"
inputs = ["{tmp_path / 'SBN_0233_A'}"]
outdir = "bundle_a"
bundle_lid = "urn:nasa:pds:fbirtfspec_a"

[[migrate]]
id = "b"
inputs = ["{tmp_path / 'SBN_0233_B'}"]
outdir = "bundle_b"
bundle_lid = "urn:nasa:pds:fbirtfspec_b"

[[validate]]
id = "check"
inputs = ["out/bundle_a", "out/bundle_b"]
after = ["a", "b"]
""", encoding="utf-8")
    command = [BIN / "pdsgen", "batch", manifest, "--workers", "2"]
    first = subprocess.run(command, capture_output=True, text=True, timeout=300)
    summary = json.loads((tmp_path / "out" / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    status = {j["id"]: j["status"] for j in summary["jobs"]}
    assert status == {"a": "done", "b": "done", "check": "done"}, (status, first.stderr)
    assert first.returncode == 0, first.stderr
    bundle = tmp_path / "out" / "bundle_a" / "bundle_fbirtfspec_a.xml"
    assert "urn:nasa:pds:fbirtfspec_a" in bundle.read_text()
    assert (tmp_path / "out" / "bundle_b" / "data" / "fieberbeyer2010" / "1358.xml").is_file()
    stamp = bundle.stat().st_mtime_ns

    second = subprocess.run(command, capture_output=True, text=True, timeout=300)
    summary = json.loads((tmp_path / "out" / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    status = {j["id"]: j["status"] for j in summary["jobs"]}
    assert status == {"a": "skipped", "b": "skipped", "check": "skipped"}, status
    assert second.returncode == 0
    assert bundle.stat().st_mtime_ns == stamp  # not made twice
