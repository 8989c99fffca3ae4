"""Shared test fixtures.

The real-archive corpus lives in `../shared/corpus` beside the repository; tests
that use it skip cleanly when it is absent (a fresh clone elsewhere still passes).
"""

from __future__ import annotations

from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[1]
SHARED_DIR = REPO_ROOT.parent / "shared"
CORPUS_DIR = SHARED_DIR / "corpus"


@pytest.fixture(scope="session")
def corpus_dir() -> Path:
    """The shared real-archive corpus, or skip the test when it is not available."""
    if not CORPUS_DIR.is_dir():
        pytest.skip("../shared/corpus is not present")
    return CORPUS_DIR
