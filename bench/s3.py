"""Benchmark `pdsgen batch` from and to an S3 bucket against the same on local disk.

--jobs (1000) small DTM jobs (--size 64 posts square) run through `pdsgen batch
--workers 2` twice: inputs and outputs in a bucket of a local S3 server (moto's, on
127.0.0.1, started here; the pdsgen[s3] and moto[server] extras), then inputs and
outputs on local disk. Printed side by side: wall seconds and jobs/s of each, and
their ratio (S3 / disk). Every S3 job makes a HEAD and a few ranged GETs of its input
through GDAL, a LIST of the output prefix, an upload per product file and its
done-marker PUT; on disk the same job opens, renames and stats files. A third run
of the S3 manifest shows resume: all jobs skipped, in jobs/s.

Run: .venv/bin/python bench/s3.py [--jobs 1000] [--size 64] [--workers 2]
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import boto3
import numpy as np
import rasterio
from affine import Affine

CRS = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs"
BIN = Path(sys.executable).parent


def write_inputs(folder: Path, jobs: int, size: int) -> list[Path]:
    folder.mkdir(parents=True)
    rng = np.random.default_rng(0)
    paths = []
    for n in range(jobs):
        path = folder / f"dtm{n:04d}.tif"
        with rasterio.open(path, "w", driver="GTiff", width=size, height=size, count=1, dtype="float32", crs=CRS,
                           transform=Affine(10.0, 0, 10000.0 * n, 0, -10.0, 0.0)) as dataset:
            dataset.write((-4000 + rng.normal(0, 30, (size, size))).astype("float32"), 1)
        paths.append(path)
    return paths


def write_manifest(path: Path, inputs: list[str]) -> Path:
    entries = ['[batch]\nmemory = "256 MB"\n']
    entries += [f'[[dtm]]\ninput = "{name}"\nproduct_id = "DTM_{n:04d}"\n' for n, name in enumerate(inputs)]
    path.write_text("\n".join(entries), encoding="utf-8")
    return path


def run_batch(manifest: Path, outdir: str, workers: int, env: dict[str, str]) -> float:
    start = time.monotonic()
    result = subprocess.run([BIN / "pdsgen", "batch", manifest, "-o", outdir, "--workers", str(workers), "--quiet"],
                            capture_output=True, text=True, env=env)
    seconds = time.monotonic() - start
    if result.returncode != 0:
        sys.exit(f"batch into {outdir} failed:\n{result.stderr[-2000:]}")
    return seconds


def start_server() -> tuple[subprocess.Popen, str]:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    server = subprocess.Popen([BIN / "moto_server", "-H", "127.0.0.1", "-p", str(port)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 30
    while True:
        try:
            socket.create_connection(("127.0.0.1", port), 0.2).close()
            return server, f"http://127.0.0.1:{port}"
        except OSError:
            if time.monotonic() > deadline:
                server.kill()
                sys.exit("moto_server did not start")
            time.sleep(0.05)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--jobs", type=int, default=1000)
    parser.add_argument("--size", type=int, default=64)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="pdsgen-bench-s3-"))
    server, endpoint = start_server()
    try:
        env = {**{k: v for k, v in os.environ.items() if not k.startswith("AWS_")},
               "AWS_ACCESS_KEY_ID": "bench", "AWS_SECRET_ACCESS_KEY": "bench", "AWS_DEFAULT_REGION": "us-east-1",
               "AWS_ENDPOINT_URL": endpoint}
        s3 = boto3.client("s3", endpoint_url=endpoint, aws_access_key_id="bench", aws_secret_access_key="bench",
                          region_name="us-east-1")
        s3.create_bucket(Bucket="bench")
        inputs = write_inputs(work / "input", args.jobs, args.size)
        for path in inputs:
            s3.upload_file(str(path), "bench", f"input/{path.name}")
        remote = write_manifest(work / "s3.toml", [f"s3://bench/input/{p.name}" for p in inputs])
        local = write_manifest(work / "local.toml", [str(p) for p in inputs])
        print(f"{args.jobs} DTM jobs of {args.size} x {args.size} posts, --workers {args.workers}")
        disk = run_batch(local, str(work / "out"), args.workers, env)
        bucket = run_batch(remote, "s3://bench/out", args.workers, env)
        resumed = run_batch(remote, "s3://bench/out", args.workers, env)
        print(f"{'':<24}{'seconds':>10}{'jobs/s':>10}")
        for name, seconds in (("local disk", disk), ("S3 (moto, 127.0.0.1)", bucket),
                              ("S3 resume (all skipped)", resumed)):
            print(f"{name:<24}{seconds:>10.1f}{args.jobs / seconds:>10.1f}")
        print(f"ratio S3 / disk (time): {bucket / disk:.2f}")
    finally:
        server.terminate()
        server.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
