"""The installed command ends without interpreter teardown (cli.run), losing nothing on the way.

What a user can notice of an exit must be unchanged: the status, every byte written to a
pipe, exit handlers (temporary directories, Dask, logging), and threads that are still
working. Each test runs the command in a real process, as a shell or a batch script does.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np

from helpers import ORIGINS, write_raster

# Streams buffered as they are for users (an environment may set PYTHONUNBUFFERED, which would
# hide output lost at exit).
_BUFFERED = {name: value for name, value in os.environ.items() if name != "PYTHONUNBUFFERED"}


def _run(command: list[str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(command, capture_output=True, text=True, env=_BUFFERED)


def _run_script(code: str) -> subprocess.CompletedProcess[str]:
    return _run([sys.executable, "-c", textwrap.dedent(code)])


def test_status_and_piped_output_are_kept(tmp_path):
    crs, transform = ORIGINS["equirectangular"]
    source = write_raster(tmp_path / "in.tif", np.arange(64 * 64, dtype=np.float32).reshape(64, 64), crs, transform)
    done = _run([sys.executable, "-m", "pdsgen", "dtm", str(source), "-o", str(tmp_path / "out"), "--json"])
    assert done.returncode == 0, done.stderr
    summary = json.loads(done.stdout)  # the whole JSON document reached the pipe
    written = Path(summary["files"][0]["path"])
    assert written.is_file() and written.stat().st_size == summary["files"][0]["bytes"]

    refused = _run([sys.executable, "-m", "pdsgen", "dtm", str(tmp_path / "missing.tif"), "-o", str(tmp_path / "out2")])
    assert refused.returncode == 2
    assert refused.stderr.strip().splitlines() == [f"pdsgen: error: {tmp_path / 'missing.tif'}: no such file"]

    usage = _run([sys.executable, "-m", "pdsgen", "dtm", "--no-such-flag"])
    assert usage.returncode == 2 and "No such option" in usage.stderr


def test_a_long_listing_reaches_the_pipe_in_full():
    """Tens of kilobytes on stdout, more than any pipe buffer holds unread: all of it arrives."""
    from click.testing import CliRunner

    from pdsgen.cli import main

    expected = CliRunner().invoke(main, ["validate", "--list-rules"]).output
    assert len(expected) > 8192
    done = _run([sys.executable, "-m", "pdsgen", "validate", "--list-rules"])
    assert done.returncode == 0 and done.stdout == expected


def test_exit_handlers_run_and_their_output_is_kept(tmp_path):
    marker = tmp_path / "handler-ran"
    done = _run_script(f"""
        import atexit, sys
        from pathlib import Path
        atexit.register(lambda: (Path({str(marker)!r}).write_text("ran"), print("bye from a handler")))
        from pdsgen.cli import run
        run(["--version"])
    """)
    assert done.returncode == 0
    assert marker.read_text() == "ran"
    assert done.stdout.startswith("pdsgen, version") and done.stdout.endswith("bye from a handler\n")


def test_a_working_thread_is_waited_for(tmp_path):
    """A non-daemon thread still at work takes Python's ordinary exit, which waits for it."""
    marker = tmp_path / "thread-finished"
    done = _run_script(f"""
        import threading, time
        from pathlib import Path
        def work():
            time.sleep(1.5)  # long past the command's end, even on a slow machine
            Path({str(marker)!r}).write_text("done")
        threading.Thread(target=work).start()
        from pdsgen.cli import run
        run(["--version"])
    """)
    assert done.returncode == 0, done.stderr
    assert marker.read_text() == "done"


def test_exit_codes_other_than_numbers_are_reported_as_python_does():
    done = _run_script("""
        from pdsgen.cli import _end
        _end("stopped: a reason")
    """)
    assert done.returncode == 1 and done.stderr == "stopped: a reason\n"
    assert _run_script("from pdsgen.cli import _end; _end(None)").returncode == 0
    assert _run_script("from pdsgen.cli import _end; _end(3)").returncode == 3


def test_the_collector_pauses_for_imports_only():
    """Paused while the command's modules are imported, running again for the command's work
    (a validation of thousands of files must not run without it); a pause the caller made
    is left as it is."""
    done = _run_script("""
        import gc, click
        from pdsgen import cli
        cli._start_up_begins()
        assert not gc.isenabled()
        cli.main.get_command(click.Context(cli.main), "dtm")
        assert gc.isenabled() and gc.get_freeze_count() > 10000, gc.get_freeze_count()
        gc.disable()
        cli._start_up_begins()
        cli.main.get_command(click.Context(cli.main), "validate")
        assert not gc.isenabled()
        print("ok")
    """)
    assert done.stdout == "ok\n", done.stderr


def test_a_validation_report_written_to_a_pipe_arrives_whole(tmp_path):
    """The report goes to stdout in pieces without a flush of its own: the end of the run flushes it."""
    crs, transform = ORIGINS["equirectangular"]
    source = write_raster(tmp_path / "in.tif", np.arange(64 * 64, dtype=np.float32).reshape(64, 64), crs, transform)
    made = _run([sys.executable, "-m", "pdsgen", "dtm", str(source), "-o", str(tmp_path / "out"), "-q"])
    assert made.returncode == 0, made.stderr
    done = _run([sys.executable, "-m", "pdsgen", "validate", str(tmp_path / "out"), "--format", "json"])
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert [Path(f["path"]).name for f in report["files"]] == ["IN.IMG"]


def test_a_closed_stdout_or_stderr_is_no_error():
    """Started with a descriptor closed (some cron jobs and daemons), the command ends as before."""
    for redirect in (">&-", "2>&-"):
        done = subprocess.run(["sh", "-c", f"{sys.executable} -m pdsgen --version {redirect}"],
                              capture_output=True, text=True, env=_BUFFERED)
        assert done.returncode == 0 and "Traceback" not in done.stderr, (redirect, done.stderr)
