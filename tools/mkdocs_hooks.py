"""MkDocs hooks of the documentation site (mkdocs.yml `hooks:`).

Two pages are made at build time from their one source, so neither can drift:

- the home page is README.md (the walk-through a new user follows), its links into
  docs/ made relative to the site;
- the command reference is the help of the click commands themselves, as `pdsgen
  COMMAND --help` prints it (hidden options stay hidden), one section per command.

A hook of a dozen lines instead of a plugin: the reference needs nothing but click,
which pdsgen depends on already, and prints exactly what the terminal prints.
"""

from __future__ import annotations

import re
from pathlib import Path

import click

ROOT = Path(__file__).resolve().parents[1]
README_MARK = "<!-- the home page is README.md -->"
REFERENCE_MARK = "<!-- the reference is the commands' own help -->"


def on_page_markdown(markdown: str, page, config, files) -> str:
    if README_MARK in markdown:
        return readme_for_site((ROOT / "README.md").read_text(encoding="utf-8"))
    if REFERENCE_MARK in markdown:
        return markdown.replace(REFERENCE_MARK, command_reference())
    return markdown


def readme_for_site(readme: str) -> str:
    """README.md's links into docs/ (pages, images) as the site's own relative links."""
    return re.sub(r"\]\(docs/", "](", readme)


def command_reference() -> str:
    """One section per command: its `--help`, as click formats it for `pdsgen COMMAND`."""
    from pdsgen.cli import main

    top = click.Context(main, info_name="pdsgen")
    parts = [_help_block("pdsgen", main.get_help(top))]
    for name in main.list_commands(top):
        command = main.get_command(top, name)
        context = click.Context(command, info_name=name, parent=top)
        parts.append(_help_block(f"pdsgen {name}", command.get_help(context)))
    return "\n".join(parts)


def _help_block(title: str, text: str) -> str:
    return f"## {title}\n\n```text\n{text}\n```\n"
