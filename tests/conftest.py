"""Shared test fixtures.

The real-archive corpus the tests read (mission labels, small products, known-bad labels,
PDS4 map labels) is carried in `tests/data/corpus`, with the repository, commit and path of
every file in its SOURCES.md, so a plain clone runs the whole suite.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from s3_server import s3_server  # noqa: F401  (the real S3 server fixture)

REPO_ROOT = Path(__file__).resolve().parents[1]
DATA_DIR = REPO_ROOT / "tests" / "data"
CORPUS_DIR = DATA_DIR / "corpus"
PDS4_EXAMPLES_DIR = CORPUS_DIR / "pds4_examples"


@pytest.fixture(scope="session")
def corpus_dir() -> Path:
    """The real-archive corpus copied into the repository."""
    return CORPUS_DIR



def _say_count(config: pytest.Config, count: int) -> None:
    reporter = config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None and count:
        reporter.write_line(f"pdsgen: {count} tests to run")


def pytest_collection_finish(session: pytest.Session) -> None:
    """Say up front how many tests will run, so a long run is not a silent one (pytest -q prints
    only dots): the whole suite or the subset `make check` names."""
    if not hasattr(session.config, "workerinput"):  # a one-process run (with -n, the workers collect)
        _say_count(session.config, len(session.items))


_COUNTED: set[int] = set()


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_node_collection_finished(node, ids) -> None:  # noqa: ANN001 - pytest-xdist's hook
    """The same, once, when the first worker of `make test` (pytest -n 2) has collected."""
    if id(node.config) not in _COUNTED:
        _COUNTED.add(id(node.config))
        _say_count(node.config, len(ids))
