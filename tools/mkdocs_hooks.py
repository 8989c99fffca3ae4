"""MkDocs hooks of the documentation site (mkdocs.yml `hooks:`).

Two pages are made at build time from their one source, so neither can drift (and every page's
links to a directory, the theme's home link, point at its index.html: the site opens from disk):

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


# A link to a directory ("." the theme's link to the home page, "../"): a directory listing when
# the site is opened from disk, so it is written as that directory's index.html.
_DIRECTORY_LINK = re.compile(r'href="(\.\.?(?:/\.\.)*)/?"')


def on_post_page(output: str, page, config) -> str:
    """Every page as it opens from disk: no link left to a directory."""
    return _DIRECTORY_LINK.sub(lambda m: f'href="{"" if m.group(1) == "." else m.group(1) + "/"}index.html"', output)


def readme_for_site(readme: str) -> str:
    """README.md's links into docs/ (pages, images) as the site's own relative links."""
    return re.sub(r"\]\(docs/", "](", readme)


def command_reference() -> str:
    """One section per command: its `--help`, as click formats it for `pdsgen COMMAND`."""
    from pdsgen.cli import main

    # the group's own settings (-h as well as --help), which every command's context inherits
    top = click.Context(main, info_name="pdsgen", **main.context_settings)
    parts = [_help_block("pdsgen", main.get_help(top))]
    for name in main.list_commands(top):
        command = main.get_command(top, name)
        context = click.Context(command, info_name=name, parent=top)
        parts.append(_help_block(f"pdsgen {name}", command.get_help(context)))
    return "\n".join(parts)


def _help_block(title: str, text: str) -> str:
    return f"## {title}\n\n```text\n{text}\n```\n"
