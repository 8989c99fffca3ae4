"""docs/migrate-volume.md shows the volume-part -> bundle-part table the code implements
(volume_files.VOLUME_PARTS), row for row, and the CLI help names the volume form."""

from __future__ import annotations

from pathlib import Path

from pdsgen.migrate.volume_files import VOLUME_PARTS

from helpers import run_cli

PAGE = Path(__file__).resolve().parents[1] / "docs" / "migrate-volume.md"


def _table_rows(text: str, heading: str) -> list[tuple[str, ...]]:
    section = text.split(heading, 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("|")]
    return [tuple(cell.strip() for cell in row.strip("|").split(" | ")) for row in rows[2:]]


def test_the_page_table_is_the_code_table():
    rows = _table_rows(PAGE.read_text(encoding="utf-8"), "## What becomes of each part of the volume")
    assert rows == [tuple(part) for part in VOLUME_PARTS]


def test_the_help_tells_a_directory_is_a_volume():
    shown = run_cli("migrate", "--help")
    assert shown.returncode == 0
    assert "PDS3 volume" in shown.stdout and "--bundle-lid" in shown.stdout
