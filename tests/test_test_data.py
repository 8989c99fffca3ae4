"""The suite carries its own data: a clone with nothing beside it runs every test.

Every file of the real-archive corpus in tests/data/corpus has a row in its SOURCES.md giving
the public repository, commit and path it was copied from, and no test reads a directory
outside the repository.
"""

from __future__ import annotations

import re
from fnmatch import fnmatch

from conftest import CORPUS_DIR, REPO_ROOT

# Notes the corpus's curators wrote beside the copies, not copies themselves.
CURATORS_NOTES = {"SOURCES.md", "pds3_product_tools/EXPECTED.md"}


def _source_rows() -> list[list[str]]:
    """Table rows, each cell stripped; the first cell is the file (or a glob) in backquotes."""
    rows = []
    for line in (CORPUS_DIR / "SOURCES.md").read_text(encoding="utf-8").splitlines():
        if line.startswith("| `"):
            cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
            cells[0] = cells[0].split("`")[1]
            rows.append([cells[0]] + [cell.strip("`") for cell in cells[1:]])
    return rows


def test_every_corpus_file_names_its_repository_commit_and_path():
    rows = _source_rows()
    files = sorted(p.relative_to(CORPUS_DIR).as_posix() for p in CORPUS_DIR.rglob("*") if p.is_file())
    copies = [f for f in files if f not in CURATORS_NOTES]
    assert len(copies) >= 90
    unlisted = [f for f in copies if not any(fnmatch(f, row[0]) for row in rows)]
    assert not unlisted, f"corpus files without a SOURCES.md row: {unlisted}"
    for row in rows:
        file, _what, repository, commit, path, copy = row[:6]
        assert re.fullmatch(r"[\w.-]+/[\w.-]+", repository), row
        assert re.fullmatch(r"[0-9a-f]{40}", commit), row
        assert path and copy, row


def test_sources_rows_name_files_that_are_here():
    patterns = [row[0] for row in _source_rows()]
    files = [p.relative_to(CORPUS_DIR).as_posix() for p in CORPUS_DIR.rglob("*") if p.is_file()]
    assert [p for p in patterns if not any(fnmatch(f, p) for f in files)] == []


# The hostile-input tests write `../` names into labels, manifests and schemas they make under a
# temporary directory, on purpose: they check that pdsgen refuses to follow them. The cluster
# run's path mapping (test_validate_partitions.py) maps `../` names as strings, never reading them.
HOSTILE_INPUT_TESTS = {"test_security_bounds.py", "test_security_containment.py", "test_security_schemas.py",
                       "test_security_inbound.py", "test_boundaries_properties.py", "test_hostile_doors.py",
                       "test_validate_partitions.py"}


def test_no_test_reads_outside_the_repository():
    """A path to a sibling of the clone (such as a shared corpus) would skip or fail in a user's clone."""
    outside = re.compile(r"""\.\./|parents\[[2-9]\]|REPO_ROOT\.parent|\.parent\s*/\s*["']shared""")
    offenders = []
    sources = sorted((REPO_ROOT / "tests").glob("*.py")) + sorted((REPO_ROOT / "bench").glob("*.py"))
    for source in [path for path in sources if path.name not in HOSTILE_INPUT_TESTS]:
        for number, line in enumerate(source.read_text(encoding="utf-8").splitlines(), 1):
            code = line.split("#", 1)[0]
            if outside.search(code) and not code.lstrip().startswith(('"', "'")):
                offenders.append(f"{source.name}:{number}: {line.strip()}")
    assert offenders == []
