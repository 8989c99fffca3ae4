"""The documentation site builds as `make docs` builds it (mkdocs build --strict): every page
in the navigation, every link and anchor resolving; its home page is README.md and its
command reference the commands' own help, so neither can differ from its source."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

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
    reference = (tmp_path / "site" / "commands" / "index.html").read_text(encoding="utf-8")
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
