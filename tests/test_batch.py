"""`pdsgen batch` on real Dask clusters: a LocalCluster of 2 worker processes, and a
scheduler with two workers started as separate processes on the loopback address.

Eight small sets (DTM + orthoimage + Extras + validation) go through each; their
outputs must equal those of the same library calls made one after the other, byte
for byte. A broken set, and a job that aborts its own process, cost no other job;
a run killed part way and run again finishes every set without making any twice.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pdsgen.batch import Settings, load_manifest, run
from pdsgen.batch.calls import RUNNERS
from pdsgen.batch.run import make_task
from pdsgen.batch.worker import run_job

from helpers import ORIGINS, elevation_array, write_raster

SETS = 8
SIDE = 64
BIN = Path(sys.executable).parent


def write_inputs(folder: Path, sets: int) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    crs, transform = ORIGINS["equirectangular"]
    for n in range(sets):
        elevation = elevation_array(SIDE, SIDE, seed=100 + n)
        write_raster(folder / f"dtm{n}.tif", elevation, crs, transform)
        write_raster(folder / f"ortho{n}.tif", (elevation + 4100) / 1000, crs, transform)


def set_entries(n: int, dtm_input: str | None = None) -> str:
    """One set: DTM, orthoimage, their Extras, and a validation of the three."""
    return f"""
[[dtm]]
id = "s{n}_dtm"
input = "{dtm_input or f'input/dtm{n}.tif'}"
product_id = "SET{n}_DTM"

[[ortho]]
id = "s{n}_ortho"
input = "input/ortho{n}.tif"
product_id = "SET{n}_ORTHO"

[[extras]]
id = "s{n}_extras"
after = ["s{n}_dtm", "s{n}_ortho"]
outdir = "extras/set{n}"

[[validate]]
id = "s{n}_check"
after = ["s{n}_dtm", "s{n}_ortho", "s{n}_extras"]
format = "json"
output = "reports/set{n}.json"
"""


def write_manifest(folder: Path, sets: int, extra: str = "") -> Path:
    path = folder / "batch.toml"
    text = '[batch]\noutdir = "out"\nmemory = "512 MB"\n' + "".join(set_entries(n) for n in range(sets))
    path.write_text(text + extra, encoding="utf-8")
    return path


def run_sequentially(manifest_path: Path, outdir: Path) -> None:
    """The reference: each job's library call, one after the other, in this process."""
    manifest = load_manifest(manifest_path, outdir)
    products: dict[str, list[str]] = {}
    for job in manifest.jobs:  # the manifest lists dtm, ortho, extras, validate in that order
        task = make_task(job, manifest, Settings(), products)
        products[job.id] = RUNNERS[job.kind](task["params"], False, 1)["products"]


def tree(root: Path) -> dict[str, bytes]:
    """Every delivered file under ROOT (batch state left out), reports with ROOT made neutral."""
    files = {}
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if path.is_file() and ".pdsgen-batch" not in rel.parts:
            files[str(rel)] = path.read_bytes().replace(str(root).encode(), b"ROOT")
    return files


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> tuple[Path, dict[str, bytes]]:
    """The eight sets' inputs, and the files their sequential run makes."""
    folder = tmp_path_factory.mktemp("sets")
    write_inputs(folder / "input", SETS)
    manifest = write_manifest(folder, SETS)
    run_sequentially(manifest, folder / "sequential")
    expected = tree(folder / "sequential")
    assert len([f for f in expected if f.endswith(".jpg")]) == SETS * 12
    return folder, expected


ABORT_HOOK = '''
import os, sys
def _abort_on_open(event, args):
    if event == "open" and "abort-on-open" in str(args[0]):
        os.abort()
sys.addaudithook(_abort_on_open)
'''


def test_local_cluster_equals_sequential_and_isolates_failures(reference, tmp_path, monkeypatch):
    folder, expected = reference
    # A job that aborts its own process: Python's audit hook (loaded through
    # sitecustomize by every process of this test's cluster) calls os.abort() when a
    # file named abort-on-open is opened - here the job's --params file.
    hook_dir = tmp_path / "hook"
    hook_dir.mkdir()
    (hook_dir / "sitecustomize.py").write_text(ABORT_HOOK, encoding="utf-8")
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(hook_dir), os.environ.get("PYTHONPATH", "")]))
    (folder / "abort-on-open.toml").write_text('producer_full_name = "A. Bort"\n', encoding="utf-8")
    extra = """
[[dtm]]
id = "broken"
input = "input/missing.tif"

[[extras]]
id = "broken_extras"
after = ["broken"]
outdir = "extras/broken"

[[dtm]]
id = "aborts"
input = "input/dtm0.tif"
product_id = "ABORTS"
params = "abort-on-open.toml"
retries = 1
"""
    manifest = load_manifest(write_manifest(folder, SETS, extra), tmp_path / "local")
    summary = run(manifest, Settings(workers=2), bar=False)

    status = {j["id"]: j for j in summary.data["jobs"]}
    assert summary.exit_code == 1
    assert status["broken"]["status"] == "failed" and "missing.tif: no such file" in status["broken"]["error"]
    assert status["broken_extras"]["status"] == "blocked"  # the broken DTM costs its own Extras only
    assert status["aborts"]["status"] == "failed" and "SIGABRT" in status["aborts"]["error"]
    assert status["aborts"]["attempts"] == 2  # a crash is retried; a missing file is not
    assert status["broken"]["attempts"] == 1
    good = [j for j in summary.data["jobs"] if not j["id"].startswith(("broken", "aborts"))]
    assert {j["status"] for j in good} == {"done"} and len(good) == SETS * 4
    assert tree(tmp_path / "local") == expected
    assert json.loads(summary.path.read_text())["counts"] == {"done": 32, "skipped": 0, "failed": 2, "blocked": 1}
    assert "Traceback" not in Path(status["broken"]["log"]).read_text()


def _free_port() -> int:
    import socket

    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def _stop(procs: list[subprocess.Popen]) -> None:
    """Workers first, then the scheduler (a worker whose scheduler is gone takes 8 s to close)."""
    for proc in reversed(procs):
        proc.terminate()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=5)


def _cluster(tmp_path: Path, worker_options: list[str]):
    """`dask scheduler` and two `dask worker` processes (WORKER_OPTIONS) on 127.0.0.1, stopped afterwards."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = tmp_path / "dask-logs.txt"
    procs: list[subprocess.Popen] = []
    with open(logs, "w") as log:
        procs.append(subprocess.Popen([BIN / "dask", "scheduler", "--host", "127.0.0.1", "--port", str(port),
                                       "--no-dashboard"], stdout=log, stderr=log))
        for _ in range(2):
            procs.append(subprocess.Popen([BIN / "dask", "worker", address, "--host", "127.0.0.1", "--no-dashboard",
                                           *worker_options], stdout=log, stderr=log))
        from distributed import Client

        try:
            with Client(address, timeout="30s") as client:
                client.wait_for_workers(2, timeout=60)
            yield address
        finally:
            _stop(procs)


@pytest.fixture()
def scheduler(tmp_path):
    """Two workers declaring MEMORY=2e9 for jobs, one thread each."""
    yield from _cluster(tmp_path, ["--nthreads", "1", "--resources", "MEMORY=2e9", "--memory-limit", "0"])


@pytest.fixture()
def plain_scheduler(tmp_path):
    """Two workers started as most clusters are: no resources; two threads and a memory_limit
    that holds one 512 MB job at a time."""
    yield from _cluster(tmp_path, ["--nthreads", "2", "--memory-limit", "0.9GB"])


def test_remote_scheduler_equals_sequential(reference, tmp_path, scheduler):
    folder, expected = reference
    manifest = load_manifest(write_manifest(folder, SETS), tmp_path / "remote")
    summary = run(manifest, Settings(scheduler=scheduler), bar=False)
    assert summary.exit_code == 0, summary.failed
    assert tree(tmp_path / "remote") == expected
    # The workers outlive the batch; the job processes they kept for it do not.
    record = json.loads((tmp_path / "remote" / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    children = {job["child_pid"] for job in record["jobs"] if job.get("child_pid")}
    assert children and not [pid for pid in children if Path(f"/proc/{pid}").exists()]

    # Workers that cannot take a job are refused up front, in one line, never waited for.
    big = folder / "big.toml"
    big.write_text(write_manifest(folder, 1).read_text().replace("512 MB", "100 GB"), encoding="utf-8")
    proc = subprocess.run([BIN / "pdsgen", "batch", big, "-o", tmp_path / "big", "--scheduler", scheduler],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "offers MEMORY=2.00 GB" in proc.stderr


def test_plain_workers_are_sized_by_memory_limit_and_threads(reference, tmp_path, plain_scheduler):
    """Workers without a MEMORY resource take jobs; each worker runs only as many at once as
    its memory_limit holds (here one, although it has two threads)."""
    folder, expected = reference
    manifest = write_manifest(folder, SETS)
    proc = subprocess.run([BIN / "pdsgen", "batch", manifest, "-o", tmp_path / "plain", "--scheduler",
                           plain_scheduler, "--verbose"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "workers declare no MEMORY resource: jobs placed by each worker's threads and memory_limit" in proc.stderr
    assert tree(tmp_path / "plain") == expected
    summary = json.loads((tmp_path / "plain" / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    by_worker: dict[str, list[tuple[float, float]]] = {}
    for job in summary["jobs"]:
        by_worker.setdefault(job["worker"], []).append((job["started"], job["started"] + job["seconds"]))
    assert len(by_worker) == 2  # both workers used
    for spans in by_worker.values():
        spans.sort()
        assert all(end <= next_start + 0.01 for (_, end), (next_start, _) in zip(spans, spans[1:], strict=False))

    big = folder / "big.toml"
    big.write_text(write_manifest(folder, 1).read_text().replace("512 MB", "2 GB"), encoding="utf-8")
    refused = subprocess.run([BIN / "pdsgen", "batch", big, "-o", tmp_path / "big", "--scheduler", plain_scheduler],
                             capture_output=True, text=True, timeout=120)
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1
    assert "needs memory 2.00 GB but the largest Dask worker offers memory_limit=0.90 GB" in refused.stderr


def test_killed_run_resumes_without_remaking(tmp_path):
    sets = 5  # 20 jobs: room to kill the run part way even when a loaded machine delays the poll
    write_inputs(tmp_path / "input", sets)
    manifest = write_manifest(tmp_path, sets)
    markers = tmp_path / "out" / ".pdsgen-batch" / "jobs"
    command = [BIN / "pdsgen", "batch", manifest, "--workers", "2"]
    first = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 90
        while len(_done(markers)) < 2 and first.poll() is None and time.monotonic() < deadline:
            time.sleep(0.1)
    finally:
        os.killpg(first.pid, signal.SIGKILL)
        first.wait(timeout=30)
    done_before = _done(markers)
    assert 2 <= len(done_before) < sets * 4, "the run must be killed part way"
    made = {out: _identity(out) for m in done_before.values() for out in m["outputs"]}

    second = subprocess.run(command, capture_output=True, text=True, timeout=180)
    assert second.returncode == 0, second.stderr
    summary = json.loads((tmp_path / "out" / ".pdsgen-batch" / "logs" / "summary.json").read_text())
    assert {j["id"] for j in summary["jobs"] if j["status"] == "skipped"} >= set(done_before)
    assert all(_identity(out) == before for out, before in made.items())  # none made twice
    assert not list((tmp_path / "out").rglob("*.part"))  # temporary files of killed jobs are gone
    for n in range(sets):
        report = json.loads((tmp_path / "out" / "reports" / f"set{n}.json").read_text())
        assert report["summary"]["errors"] == 0
    plan = subprocess.run([*command, "--dry-run"], capture_output=True, text=True, timeout=60)
    assert f"{sets * 4} jobs: 0 to do, {sets * 4} done, 0 blocked" in plan.stdout


def _done(markers: Path) -> dict[str, dict]:
    found = {}
    for path in markers.glob("*.json"):
        try:
            data = json.loads(path.read_text())
        except ValueError:
            continue
        if data.get("state") == "done":
            found[path.stem] = data
    return found


def _identity(path: str) -> tuple[int, int]:
    st = os.stat(path)
    return st.st_ino, st.st_mtime_ns


def test_job_past_its_timeout_is_stopped(tmp_path):
    """A job's child is ended at its timeout; the job fails with that reason and may be retried.
    The child starts cold (its imports alone outlast 0.01 s): a warm one left by an earlier test
    could finish a small DTM first."""
    from pdsgen.batch.resident import POOL

    write_inputs(tmp_path / "input", 1)
    manifest = load_manifest(write_manifest(tmp_path, 1), tmp_path / "out")
    task = make_task(manifest.jobs[0], manifest, Settings(), {})
    POOL.close()
    outcome = run_job({**task, "timeout": 0.01})
    assert outcome["status"] == "failed" and outcome["error"] == "timed out after 0.01 s" and outcome["retry"]
    assert not Path(task["marker"]).exists() and not list((tmp_path / "out").glob("*.IMG"))


def test_jobs_sharing_a_readme_stay_done(tmp_path):
    """Two Extras jobs in one directory (ordered by `after`) both stay done: the second
    rewriting README.TXT does not make the first look changed."""
    write_inputs(tmp_path / "input", 2)
    (tmp_path / "batch.toml").write_text("""
[[dtm]]
input = "input/dtm0.tif"
[[dtm]]
input = "input/dtm1.tif"
[[extras]]
id = "first"
after = ["dtm0"]
outdir = "extras"
[[extras]]
id = "second"
after = ["dtm1", "first"]
outdir = "extras"
""", encoding="utf-8")
    manifest = load_manifest(tmp_path / "batch.toml", tmp_path / "out")

    def run_all() -> list[str]:
        products: dict[str, list[str]] = {}
        statuses = []
        for job in manifest.jobs:
            outcome = run_job(make_task(job, manifest, Settings(), products))
            products[job.id] = outcome["products"]
            statuses.append(outcome["status"])
        return statuses

    assert run_all() == ["done"] * 4
    readme = (tmp_path / "out" / "extras" / "README.TXT").read_text()
    assert "DTM0" in readme and "DTM1" in readme
    assert run_all() == ["skipped"] * 4


def test_a_busy_dashboard_port_prints_nothing(tmp_path):
    """Another Dask cluster on the machine holding port 8787 costs no warning on stderr."""
    import socket

    write_inputs(tmp_path / "input", 1)
    (tmp_path / "batch.toml").write_text('[[dtm]]\ninput = "input/dtm0.tif"\n', encoding="utf-8")
    holder = socket.socket()
    try:
        holder.bind(("", 8787))
        holder.listen()
    except OSError:
        pass  # already held by another cluster: the case itself
    try:
        proc = subprocess.run([BIN / "pdsgen", "batch", tmp_path / "batch.toml", "-o", tmp_path / "out",
                               "--workers", "1", "--quiet"], capture_output=True, text=True, timeout=180)
    finally:
        holder.close()
    assert (proc.returncode, proc.stderr) == (0, "")
    assert (tmp_path / "out" / "DTM0.IMG").is_file()
