"""`pdsgen batch` with inputs in a bucket and -o s3://...: the Dask workers read and write
the bucket themselves (real S3 server on 127.0.0.1, tests/s3_server.py), a run killed part
way resumes from the done-markers kept in the bucket without remaking a finished product,
and the delivered objects equal the files of the same manifest run on local disk."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from test_batch import set_entries, tree, write_inputs
from test_storage_s3 import _without_times

BIN = Path(sys.executable).parent
SETS = 2  # 8 jobs: enough to kill the run part way


def _manifest(folder: Path, inputs: str, name: str) -> Path:
    text = '[batch]\nmemory = "512 MB"\n' + "".join(
        set_entries(n).replace("input/", inputs) for n in range(SETS))
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def _done_markers(s3_server, bucket: str) -> dict[str, dict]:
    found = {}
    for key in s3_server.keys(bucket, "out/.pdsgen-batch/jobs/"):
        data = json.loads(s3_server.get(bucket, key))
        if data.get("state") == "done":
            found[Path(key).stem] = data
    return found


def _versions(s3_server, bucket: str) -> dict[str, tuple[str, object]]:
    """Each delivered object's ETag and time: a product made again would change its time."""
    found = {}
    for key in s3_server.keys(bucket, "out/"):
        head = s3_server.client.head_object(Bucket=bucket, Key=key)
        found[key] = (head["ETag"], head["LastModified"])
    return found


def test_batch_from_and_into_a_bucket_resumes_and_equals_local(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    write_inputs(tmp_path / "input", SETS)
    for path in sorted((tmp_path / "input").iterdir()):
        s3_server.put(bucket, f"input/{path.name}", path.read_bytes())
    remote_manifest = _manifest(tmp_path, f"s3://{bucket}/input/", "remote.toml")
    command = [BIN / "pdsgen", "batch", remote_manifest, "-o", f"s3://{bucket}/out", "--workers", "2"]
    first = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while len(_done_markers(s3_server, bucket)) < 2 and first.poll() is None and time.monotonic() < deadline:
            time.sleep(0.1)
    finally:
        os.killpg(first.pid, signal.SIGKILL)
        first.wait(timeout=30)
    done_before = _done_markers(s3_server, bucket)
    assert 2 <= len(done_before) < SETS * 4, "the run must be killed part way"
    made = {key: version for key, version in _versions(s3_server, bucket).items()
            if any(f"/vsis3/{bucket}/{key}" in marker["outputs"] for marker in done_before.values())}
    assert made

    second = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert second.returncode == 0, second.stderr
    summary = json.loads(s3_server.get(bucket, "out/.pdsgen-batch/logs/summary.json"))
    assert {j["id"] for j in summary["jobs"] if j["status"] == "skipped"} >= set(done_before)
    after = _versions(s3_server, bucket)
    assert all(after[key] == version for key, version in made.items())  # none made twice
    assert any(key.startswith("out/.pdsgen-batch/logs/") and key.endswith(".log") for key in after)

    local_manifest = _manifest(tmp_path, "input/", "local.toml")
    local = subprocess.run([BIN / "pdsgen", "batch", local_manifest, "-o", tmp_path / "local", "--workers", "2"],
                           capture_output=True, text=True, timeout=300)
    assert local.returncode == 0, local.stderr
    expected = {name: _without_times(data).replace(str(tmp_path / "local").encode(), b"ROOT")
                for name, data in tree(tmp_path / "local").items()}
    remote = {name: _without_times(data).replace(f"s3://{bucket}/out".encode(), b"ROOT")
              for name, data in s3_server.tree(bucket, "out/").items() if not name.startswith(".pdsgen-batch/")}
    assert sorted(remote) == sorted(expected)
    for name in expected:
        assert remote[name] == expected[name], name
    plan = subprocess.run([*command, "--dry-run"], capture_output=True, text=True, timeout=60)
    assert f"{SETS * 4} jobs: 0 to do, {SETS * 4} done, 0 blocked" in plan.stdout
