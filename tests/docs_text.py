"""The documentation's text as tests read it: README.md and the pages of the site (docs/).

A section is found by its heading wherever it lives (README or a page), so a test that runs
or checks what a section shows follows the text when it moves between pages.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"


def documents() -> list[Path]:
    """README.md, then every Markdown page of the site."""
    return [README, *sorted(DOCS.rglob("*.md"))]


def all_text() -> str:
    return "\n".join(path.read_text(encoding="utf-8") for path in documents())


def headings(text: str) -> list[tuple[int, str, int]]:
    """(start, title, level) of each `#` or `##` heading outside fenced code blocks."""
    found, fenced, offset = [], False, 0
    for line in text.splitlines(keepends=True):
        if line.startswith("```"):
            fenced = not fenced
        match = None if fenced else re.match(r"(#{1,2}) (.+)\n?$", line)
        if match:
            found.append((offset, match.group(2).strip(), len(match.group(1))))
        offset += len(line)
    return found


def section(title: str) -> str:
    """The body of the one section headed `# title` or `## title`, up to the next heading of
    level 1 or 2 (its `###` subsections included)."""
    found = []
    for path in documents():
        text = path.read_text(encoding="utf-8")
        marks = headings(text)
        for index, (start, name, _) in enumerate(marks):
            if name == title:
                body_start = text.index("\n", start) + 1
                end = marks[index + 1][0] if index + 1 < len(marks) else len(text)
                found.append((path, text[body_start:end]))
    assert len(found) == 1, f"section {title!r} is in {[str(p) for p, _ in found] or 'no document'}"
    return found[0][1]


def section_starting(prefix: str) -> str:
    """The body of the one section whose heading begins with `prefix`."""
    titles = [name for path in documents() for _, name, _ in headings(path.read_text(encoding="utf-8"))
              if name.startswith(prefix)]
    assert len(titles) == 1, f"headings starting {prefix!r}: {titles}"
    return section(titles[0])


WALK = "Walk-through: your own DTM and orthoimage to a delivery"


def walkthrough_params(where: Path) -> Path:
    """where/params.toml: the walk-through's params file (its identification keywords, step 1), as a
    user following the README writes it - what every later example that makes products reads."""
    (block,) = [b for b in re.findall(r"```toml\n(.*?)```", section(WALK), re.S) if b.startswith("# params.toml")]
    (where / "params.toml").write_text(block)
    return where / "params.toml"
