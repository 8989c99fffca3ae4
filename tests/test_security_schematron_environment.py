"""The Saxon child that runs Schematron rules (a delivery's own, given with --schemas, too)
starts with only what Python needs of the environment: a secret of the validating process (a
CI job's token) is not in the child's environment at all, whatever the rules' static check."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from pdsgen.validate.pds4 import schematron

pytestmark = pytest.mark.skipif(not schematron.available() or not Path("/proc/self/environ").exists(),
                                reason="needs saxonche and /proc")


def test_the_schematron_child_gets_no_secret_of_the_validating_process(monkeypatch):
    monkeypatch.setenv("PDSGEN_TEST_TOKEN", "SECRET-7f3c9a")
    running = schematron._WORKERS.pop(os.getpid(), None)
    if running is not None:
        running.stop()
    worker = schematron._worker()
    try:
        environment = b""
        deadline = time.monotonic() + 10
        while not environment and worker.process.poll() is None and time.monotonic() < deadline:
            environment = Path(f"/proc/{worker.process.pid}/environ").read_bytes()  # empty while it starts
            time.sleep(0.05)
        assert b"SECRET-7f3c9a" not in environment and b"PDSGEN_TEST_TOKEN" not in environment
        assert b"PATH=" in environment  # what starting Python needs is passed on
        assert worker.process.poll() is None  # and the child runs with it
    finally:
        schematron._WORKERS.pop(os.getpid(), None)
        worker.stop()
