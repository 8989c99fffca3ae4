"""Resident job processes: a worker slot's child is reused job after job, and replaced
when it crashes, times out, has run its share of jobs or has grown too much.

The jobs are real DTM jobs run through `run_job` (what a Dask worker calls), so each
test exercises the real child process, its pipes and its memory accounting. Faults
are injected into the child through Python's audit hook, loaded by sitecustomize in
every process these tests start: opening a file whose name holds `abort-on-open`
aborts the process; `kill-on-open` has it killed by SIGKILL, as the kernel's OOM killer
does; `grow-on-open` makes it keep 300 MB; `warn-on-open` issues a UserWarning;
`sleep-on-open` holds it for 5 s.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import rasterio

from pdsgen.batch import Settings, load_manifest
from pdsgen.batch.resident import POOL
from pdsgen.batch.run import make_task
from pdsgen.batch.worker import run_job

from helpers import ORIGINS, elevation_array, write_raster

HOOK = '''
import os, sys
_kept = []
def _faults(event, args):
    if event == "open" and isinstance(args[0], str):
        if "abort-on-open" in args[0]:
            os.abort()
        if "kill-on-open" in args[0]:
            os.kill(os.getpid(), 9)
        if "warn-on-open" in args[0]:
            import warnings
            warnings.warn("injected warning", UserWarning)
        if "sleep-on-open" in args[0]:
            import time
            time.sleep(5)
        if "grow-on-open" in args[0]:
            _kept.append(bytearray(os.urandom(1)) * (300 * 1000 * 1000))
sys.addaudithook(_faults)
'''


@pytest.fixture()
def jobs(tmp_path, monkeypatch):
    """A manifest of nine DTM jobs (job 2 with the abort params, 4 the grow params, 5 the
    kill params, 6 and 7 the warn params, 8 the sleep params) and a function making the task
    of job N; fresh children for this test."""
    hook_dir = tmp_path / "hook"
    hook_dir.mkdir()
    (hook_dir / "sitecustomize.py").write_text(HOOK, encoding="utf-8")
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(hook_dir), os.environ.get("PYTHONPATH", "")]))
    crs, transform = ORIGINS["equirectangular"]
    (tmp_path / "input").mkdir()
    write_raster(tmp_path / "input" / "dtm.tif", elevation_array(64, 64, seed=7), crs, transform)
    for name in ("abort-on-open.toml", "grow-on-open.toml", "kill-on-open.toml", "warn-on-open.toml",
                 "sleep-on-open.toml"):
        (tmp_path / name).write_text('producer_full_name = "A. Tester"\n', encoding="utf-8")
    entries = []
    for n in range(9):
        params = {2: 'params = "abort-on-open.toml"\n', 4: 'params = "grow-on-open.toml"\n',
                  5: 'params = "kill-on-open.toml"\n', 6: 'params = "warn-on-open.toml"\n',
                  7: 'params = "warn-on-open.toml"\n', 8: 'params = "sleep-on-open.toml"\n'}.get(n, "")
        entries.append(f'[[dtm]]\nid = "j{n}"\ninput = "input/dtm.tif"\nproduct_id = "J{n}"\n{params}')
    (tmp_path / "batch.toml").write_text("\n".join(entries), encoding="utf-8")
    manifest = load_manifest(tmp_path / "batch.toml", tmp_path / "out")
    POOL.close()  # children of earlier tests run without this test's hook

    def task(n: int, **settings) -> dict:
        return make_task(manifest.jobs[n], manifest, Settings(**settings), {})

    yield task
    POOL.close()


def test_one_child_runs_job_after_job_and_a_crash_costs_only_its_job(jobs, tmp_path):
    first, second = run_job(jobs(0)), run_job(jobs(1))
    assert first["status"] == second["status"] == "done"
    assert first["child_pid"] == second["child_pid"]  # the same resident process
    crashed = run_job(jobs(2))
    assert crashed["status"] == "failed" and crashed["retry"]
    assert crashed["error"].startswith("crashed (killed by SIGABRT)") and crashed["child_pid"] == first["child_pid"]
    after = run_job(jobs(3))
    assert after["status"] == "done" and after["child_pid"] not in (first["child_pid"], None)
    for n in (0, 1, 3):  # each product whole, read back by GDAL
        with rasterio.open(tmp_path / "out" / f"J{n}.IMG") as dataset:
            assert (dataset.width, dataset.height) == (64, 64)
    assert not (tmp_path / "out" / "J2.IMG").exists()
    assert "J0" not in Path(second["log"]).read_text()  # each job's output in its own log


def test_a_job_killed_like_the_oom_killer_does_fails_alone(jobs, tmp_path):
    warm = run_job(jobs(0))
    killed = run_job(jobs(5))
    assert killed["status"] == "failed" and killed["retry"] and killed["child_pid"] == warm["child_pid"]
    assert killed["error"].startswith("crashed (killed by SIGKILL)")
    assert not (tmp_path / "out" / "J5.IMG").exists() and not list((tmp_path / "out").glob(".*.part"))
    after = run_job(jobs(1))
    assert after["status"] == "done" and after["child_pid"] != warm["child_pid"]


def test_a_child_that_grew_is_replaced_and_peaks_are_per_job(jobs):
    small = run_job(jobs(0, child_growth_mb=100))
    grown = run_job(jobs(4, child_growth_mb=100))
    assert grown["status"] == "done" and grown["child_pid"] == small["child_pid"]
    assert grown["peak_mb"] > small["peak_mb"] + 250  # the job's own peak holds the 300 MB it kept
    fresh = run_job(jobs(1, child_growth_mb=100))
    assert fresh["child_pid"] != grown["child_pid"]  # grown by 300 MB > 100 MB: replaced
    assert fresh["peak_mb"] < grown["peak_mb"] - 250  # a new child's peak is not the old one's


def test_each_job_log_has_its_own_warnings(jobs):
    """Python shows a warning once per place in a process; a resident child still writes it
    into the log of every job that raises it, as a process per job did."""
    first, second = run_job(jobs(6)), run_job(jobs(7))
    assert first["child_pid"] == second["child_pid"] and first["status"] == second["status"] == "done"
    for outcome in (first, second):
        assert "UserWarning: injected warning" in Path(outcome["log"]).read_text()


def test_a_fresh_process_per_job_when_asked(jobs):
    pids = {run_job(jobs(n, child_jobs=1))["child_pid"] for n in (0, 1, 3)}
    assert len(pids) == 3 and None not in pids


def test_a_timed_out_job_loses_its_child_and_the_next_job_runs(jobs, tmp_path):
    """Job 8's child sleeps 5 s reading its params (a job stuck on a hung file system): the
    timeout kills it whatever the machine's speed, before the product is written."""
    warm = run_job(jobs(0))
    late = run_job({**jobs(8), "timeout": 0.5})
    assert late["status"] == "failed" and late["error"] == "timed out after 0.5 s" and late["retry"]
    assert late["child_pid"] == warm["child_pid"]
    with pytest.raises(ProcessLookupError):
        os.kill(warm["child_pid"], 0)  # killed and reaped
    assert not (tmp_path / "out" / "J8.IMG").exists() and not list((tmp_path / "out").glob(".*.part"))
    assert run_job(jobs(1))["status"] == "done"


def test_a_child_growth_that_is_no_size_is_one_line(tmp_path):
    import subprocess
    import sys

    (tmp_path / "batch.toml").write_text('[[dtm]]\ninput = "dtm.tif"\n', encoding="utf-8")
    proc = subprocess.run([Path(sys.executable).parent / "pdsgen", "batch", tmp_path / "batch.toml", "-o",
                           tmp_path / "out", "--child-growth", "lots"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
    assert "'--child-growth': 'lots' is not a size" in proc.stderr and not (tmp_path / "out").exists()
