"""The documentation site builds as `make docs` builds it (mkdocs build --strict): every page
in the navigation, every link and anchor resolving; its home page is README.md and its
command reference the commands' own help, so neither can differ from its source."""

from __future__ import annotations

import html.parser
import shutil
import subprocess
import sys
from pathlib import Path
from urllib.parse import unquote, urlsplit

import click
import yaml

from pdsgen.cli import COMMANDS, main

ROOT = Path(__file__).resolve().parents[1]
MKDOCS = [sys.executable, "-m", "mkdocs"]


def _build(config: Path, site: Path) -> subprocess.CompletedProcess:
    return subprocess.run([*MKDOCS, "build", "--strict", "-f", str(config), "-d", str(site)], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)


def test_make_docs_builds_the_site_strict(tmp_path):
    makefile = (ROOT / "Makefile").read_text()
    assert "\tmkdocs build --strict" in makefile.replace("$(VENV)/bin/", "")
    built = _build(ROOT / "mkdocs.yml", tmp_path / "site")
    assert built.returncode == 0, built.stderr
    assert "WARNING" not in built.stderr, built.stderr
    home = (tmp_path / "site" / "index.html").read_text(encoding="utf-8")
    assert "Walk-through: your own DTM and orthoimage to a delivery" in home
    assert 'src="images/review_page.png"' in home  # README's docs/ links, relative to the site


def test_the_command_reference_is_every_command_and_visible_option(tmp_path):
    built = _build(ROOT / "mkdocs.yml", tmp_path / "site")
    assert built.returncode == 0, built.stderr
    reference = (tmp_path / "site" / "commands.html").read_text(encoding="utf-8")
    assert reference.count("-h, --help") == len(COMMANDS) + 1  # the group and every command take -h
    top = click.Context(main, info_name="pdsgen")
    for name in COMMANDS:
        command = main.get_command(top, name)
        assert f"Usage: pdsgen {name} " in reference, name
        for parameter in command.params:
            if isinstance(parameter, click.Option) and not parameter.hidden:
                assert parameter.opts[0] in reference, (name, parameter.opts)
            if isinstance(parameter, click.Option) and parameter.hidden:
                assert f"  {parameter.opts[0]} " not in reference, (name, parameter.opts)


def test_a_broken_link_or_anchor_fails_the_build(tmp_path):
    """The checks `make docs` relies on: a copy of the site with one bad link, then one bad
    anchor, does not build."""
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text())
    for bad in ("[gone](no-such-page.md)", "[gone](products.md#no-such-heading)"):
        docs = tmp_path / "docs"
        shutil.rmtree(docs, ignore_errors=True)
        shutil.copytree(ROOT / "docs", docs)
        (docs / "batch.md").write_text((docs / "batch.md").read_text() + f"\n{bad}\n")
        copy = {**config, "docs_dir": str(docs), "hooks": [str(ROOT / h) for h in config["hooks"]]}
        (tmp_path / "mkdocs.yml").write_text(yaml.safe_dump(copy))
        built = _build(tmp_path / "mkdocs.yml", tmp_path / "site")
        assert built.returncode != 0 and "batch.md" in built.stderr, (bad, built.stderr)


class _Links(html.parser.HTMLParser):
    """Every href and src of a page, and the ids it defines."""

    def __init__(self) -> None:
        super().__init__()
        self.links: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if name in ("href", "src") and value:
                self.links.append(value)
            if name == "id" and value:
                self.ids.add(value)


def test_the_site_opens_from_disk_every_link_a_file(tmp_path):
    """Opened as files (build/site/index.html in a browser, no server), every link of every page
    leads to a file that exists - a page, not a directory listing - and to an anchor it has;
    and no table shows a literal backslash-bar."""
    site = tmp_path / "site"
    built = _build(ROOT / "mkdocs.yml", site)
    assert built.returncode == 0, built.stderr
    # 404.html is a web server's page (its links absolute from the server's root), never opened from disk
    pages = {page: _Links() for page in site.rglob("*.html") if page.name != "404.html"}
    for page, parsed in pages.items():
        parsed.feed(page.read_text(encoding="utf-8"))
    followed = 0
    for page, parsed in pages.items():
        assert "\\|" not in page.read_text(encoding="utf-8"), page
        for link in parsed.links:
            parts = urlsplit(link)
            if parts.scheme or link.startswith("//"):
                continue  # another site
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            assert target.is_file(), f"{page.relative_to(site)}: {link} is no file"
            if parts.fragment and target in pages:
                assert parts.fragment in pages[target].ids, f"{page.relative_to(site)}: {link}"
            followed += 1
    assert followed > 500 and (site / "install.html").is_file() and not (site / "install").exists()
