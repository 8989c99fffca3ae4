"""`validate -j N` and `validate --scheduler ADDRESS` report what a one-process run reports, byte for
byte: the per-file work in worker processes (a pool, a LocalCluster, a `dask scheduler` with two
`dask worker` processes started here), the checks across files (inventories, membership, PDS4-060, the
SET rules) in the parent over what the workers return. The bundle (tests/scale_bundle.py) has two faults
only a whole run finds: a value out of range in the last product's table, and that product missing from
the inventory."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pdsgen import __version__
from pdsgen.batch.cluster import check_version, open_client
from pdsgen.errors import PdsgenError
from pdsgen.validate.runner import ValidationJob, iter_reports
from scale_bundle import make_bundle

from helpers import run_cli

PRODUCTS = 30
DASK = Path(sys.executable).with_name("dask")


@pytest.fixture(scope="module")
def bundle(tmp_path_factory) -> Path:
    return make_bundle(tmp_path_factory.mktemp("scale") / "bundle", PRODUCTS, fault_last=True, per_directory=12)


@pytest.fixture(scope="module")
def one_process(bundle) -> dict[str, str]:
    """The one-process run's report in text and JSON."""
    return {fmt: _report(bundle, "--format", fmt) for fmt in ("text", "json")}


def _report(bundle: Path, *options: str) -> str:
    done = run_cli("validate", "--offline", *options, str(bundle))
    assert done.returncode == 1, done.stderr  # the two planted faults
    return done.stdout


def test_one_process_run_finds_the_planted_faults(one_process):
    text = one_process["text"]
    last = f"p{PRODUCTS - 1:06d}.xml"
    assert f"{last}:55: error [PDS4-053]" in text and "record 101, field real1: 123.45 outside Field_Statistics" in text
    assert f"{last}: error [DLV-011]" in text
    assert f"{PRODUCTS + 2} file(s) checked: 2 error(s)" in text


def test_two_processes_report_what_one_does(bundle, one_process):
    assert _report(bundle, "-j", "2", "--format", "text") == one_process["text"]
    assert _report(bundle, "-j", "2", "--format", "json") == one_process["json"]


def test_a_local_cluster_reports_what_one_process_does(bundle, monkeypatch):
    """The bundle named relative to the client's directory, which is not the workers' (they started
    before the client moved): the workers read the files where the client names them and name them
    as the client did, without changing their own directory (other tasks share a worker's process)."""
    with open_client(None, 2) as client:
        check_version(client, __version__)  # the workers run this pdsgen; another is refused in one line
        with pytest.raises(PdsgenError, match=r"2 Dask worker\(s\) run pdsgen .* this client runs 0.0.0-other"):
            check_version(client, "0.0.0-other")
        workers_at = client.run(os.getcwd)
        monkeypatch.chdir(bundle.parent)
        assert set(workers_at.values()) != {os.getcwd()}
        clustered = list(iter_reports([bundle.name], ValidationJob(schema_cache=None, cluster=client)))
        assert client.run(os.getcwd) == workers_at
    alone = list(iter_reports([bundle.name], ValidationJob(schema_cache=None)))
    assert clustered == alone
    assert {f.rule for r in alone for f in r.findings} == {"PDS4-053", "DLV-011"}
    assert [r.path for r in alone] == sorted({r.path for r in alone}, key=[r.path for r in alone].index)


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _wait_for_port(port: int, process: subprocess.Popen, seconds: float = 60) -> None:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        assert process.poll() is None, "the dask scheduler exited"
        with socket.socket() as probe:
            if probe.connect_ex(("127.0.0.1", port)) == 0:
                return
        time.sleep(0.2)
    raise AssertionError(f"no dask scheduler on port {port} within {seconds} s")


def test_a_scheduler_and_two_workers_report_what_one_process_does(bundle, one_process, tmp_path):
    """`dask scheduler` and two `dask worker` processes on 127.0.0.1, started and torn down here."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    quiet = {**os.environ, "DASK_LOGGING__DISTRIBUTED": "error"}
    logs = open(tmp_path / "dask.log", "wb")
    processes = [subprocess.Popen([str(DASK), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                                   "--no-dashboard"], stdout=logs, stderr=logs, env=quiet)]
    try:
        _wait_for_port(port, processes[0])
        for _ in range(2):
            processes.append(subprocess.Popen([str(DASK), "worker", address, "--nthreads", "1", "--no-dashboard",
                                               "--memory-limit", "0", "--host", "127.0.0.1"],
                                              stdout=logs, stderr=logs, env=quiet))
        assert _report(bundle, "--scheduler", address, "--format", "text") == one_process["text"]
        assert _report(bundle, "--scheduler", address, "--format", "json") == one_process["json"]
    finally:
        for process in reversed(processes):
            process.terminate()
        for process in processes:
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        logs.close()


def test_jobs_with_a_scheduler_is_a_usage_error(bundle):
    done = run_cli("validate", "-j", "2", "--scheduler", "tcp://127.0.0.1:1", str(bundle))
    assert done.returncode == 2 and "--jobs" in done.stderr


def test_a_delivery_run_on_two_processes_streams(bundle):
    """The delivery is checked before the first file is validated (over what the workers read of every
    file, in a process of its own), so the first report goes out while files are still being checked -
    the run holds no report until the last file - and the delivery's findings are in the reports.
    The count of files moves in both passes: first a count, then out of the files the first found."""
    done: list[int] = []
    totals: list[int] = []
    reports = iter_reports([bundle], ValidationJob(schema_cache=None, jobs=2),
                           lambda count, total: (done.append(count), totals.append(total)))
    first = next(reports)
    assert first.path.endswith("bundle_scale.xml") and done[-1] < PRODUCTS
    rest = list(reports)
    assert len(rest) == PRODUCTS + 1 and done[-1] == PRODUCTS + 2
    files = PRODUCTS + 2
    assert done == [*range(1, files + 1), *range(1, files + 1)] and totals == [0] * files + [files] * files
    last = rest[-1]
    assert last.path.endswith(f"p{PRODUCTS - 1:06d}.xml") and {f.rule for f in last.findings} == {"PDS4-053", "DLV-011"}


def test_a_run_sharing_its_label_cache_checks_the_delivery_itself(bundle):
    """review -j N hands the run its label cache: the delivery is checked in the run's own process
    (what the check reads stays in the caller's cache), with the findings of a one-process run."""
    from pdsgen.label.read import LabelCache

    shared = list(iter_reports([bundle], ValidationJob(schema_cache=None, jobs=2, labels=LabelCache())))
    assert shared == list(iter_reports([bundle], ValidationJob(schema_cache=None)))
    assert {f.rule for r in shared for f in r.findings} == {"PDS4-053", "DLV-011"}


def test_without_a_delivery_two_processes_still_stream(bundle, tmp_path):
    """A directory of labels that is no delivery gets its first report while files are still being
    checked (one pass: the workers read the facts PDS4-060 joins beside each file's own checks)."""
    import shutil

    data = shutil.copytree(bundle / "data", tmp_path / "data")
    (data / "collection_data.xml").unlink()
    (data / "collection_data_inventory.csv").unlink()
    done: list[int] = []
    reports = iter_reports([data], ValidationJob(schema_cache=None, jobs=2), lambda count, _: done.append(count))
    first = next(reports)
    assert first.path.endswith("p000000.xml") and done[-1] < PRODUCTS
    assert len([first, *reports]) == PRODUCTS and done[-1] == PRODUCTS


def test_a_checking_process_that_dies_leaves_no_file_unchecked(bundle, monkeypatch):
    """The process forked to check the delivery may die (killed for its memory, say): the run then
    checks the delivery itself, and every file is still validated - the names the workers had not
    yet taken are spooled too - with the findings of a one-process run."""
    from pdsgen.validate import runner

    monkeypatch.setattr(runner, "_check_learnt", lambda *args: os._exit(1))
    died = list(iter_reports([bundle], ValidationJob(schema_cache=None, jobs=2)))
    assert died == list(iter_reports([bundle], ValidationJob(schema_cache=None)))
    assert len(died) == PRODUCTS + 2
