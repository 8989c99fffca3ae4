"""A killed batch's temporaries are cleaned up even while its killed processes wait to be reaped."""

from __future__ import annotations

import subprocess
import sys
import time

import pytest

from pdsgen.batch.resume import _writer_alive


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="process states are read from /proc")
def test_a_killed_process_not_yet_reaped_writes_nothing_more():
    """A zombie (exited, not reaped: a killed batch's worker) holds its PID but is no writer."""
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    try:
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:  # exited: /proc says Z until it is reaped
            with open(f"/proc/{child.pid}/stat") as stat:
                if stat.read().rsplit(")", 1)[1].split()[0] == "Z":
                    break
            time.sleep(0.02)
        assert not _writer_alive(child.pid, time.time())
    finally:
        child.wait()
    running = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        assert _writer_alive(running.pid, time.time())
    finally:
        running.kill()
        running.wait()
