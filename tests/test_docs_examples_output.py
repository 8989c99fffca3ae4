"""What the docs show a new user is what they get: the demo's printed lines in docs/install.md
are those of a run; the README and docs/install.md give one install route, with the pds4 extra
and its brackets quoted for the shell, as every install hint does; the README's delivery.toml
names the volume set's keys, and docs/delivery.md every key of the [delivery] table."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import tomllib

from pdsgen.deliver.text import TABLE, TEXT_KEYS

ROOT = Path(__file__).resolve().parents[1]
INSTALL = (ROOT / "docs" / "install.md").read_text(encoding="utf-8")
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_the_demo_prints_what_docs_install_shows(tmp_path):
    (shown,) = re.findall(r"^```\n(inputs in .*?)^```", INSTALL, re.S | re.M)
    run = subprocess.run([sys.executable, "-m", "pdsgen", "demo", "-o", "out/demo"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert run.stdout == shown


def _pip_installs(text: str) -> list[str]:
    return re.findall(r"pip install [^\n#`]*", text)


def test_one_install_route_with_the_pds4_extra_quoted():
    readme, install = _pip_installs(README), _pip_installs(INSTALL)
    assert "pip install '.[pds4]'" in [line.strip() for line in readme]
    assert "pip install '.[pds4]'" in [line.strip() for line in install]
    sources = [README, INSTALL, *(path.read_text(encoding="utf-8") for path in (ROOT / "docs").glob("*.md")),
               *(path.read_text(encoding="utf-8") for path in (ROOT / "src" / "pdsgen").rglob("*.py"))]
    for line in (line for text in sources for line in _pip_installs(text)):
        for package in re.findall(r"\S*\[[a-z0-9,]+\]\S*", line):  # brackets a shell would glob
            assert package[0] in "'\"" or package.startswith(("\"./", "./${")), line


def test_the_delivery_text_keys_are_shown():
    (block,) = [b for b in re.findall(r"```toml\n(.*?)```", README, re.S) if b.startswith("# delivery.toml")]
    table = tomllib.loads(block)[TABLE]
    assert set(table) <= set(TEXT_KEYS) and {"volume_series_name", "volume_set_name"} <= set(table)
    delivery = (ROOT / "docs" / "delivery.md").read_text(encoding="utf-8")
    assert all(f"`{key}`" in delivery for key in TEXT_KEYS)
