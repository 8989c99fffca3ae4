"""README.TXT describes every product whose Extras are in the directory, across calls."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.errors import PdsgenError
from pdsgen.extras import make_extras
from pdsgen.extras.readme_index import parse_readme
from pdsgen.extras.readme_txt import entry_files, render_readme
from test_extras_helpers import crater_field, write_geotiff


@pytest.fixture()
def two_products(tmp_path: Path) -> tuple[Path, Path]:
    (tmp_path / "in").mkdir()
    dtm = write_geotiff(tmp_path / "in" / "first_dtm.tif", crater_field(60, 80))
    rows, cols = np.mgrid[0:50, 0:70]
    image = (20 + (rows * 3 + cols * 2) % 200).astype(np.uint8)
    ortho = write_geotiff(tmp_path / "in" / "second_ortho.tif", image)
    return dtm, ortho


def hidden_files(outdir: Path) -> list[str]:
    """Names a delivery would ship without anyone seeing them."""
    return sorted(p.name for p in outdir.iterdir() if p.name.startswith("."))


def product_ids(readme: Path) -> list[str]:
    return re.findall(r"^Product ID:\s+(\S+)", readme.read_text(), flags=re.MULTILINE)


def test_second_call_adds_its_product_to_readme_without_overwrite(two_products, tmp_path: Path):
    dtm, ortho = two_products
    out = tmp_path / "out"
    runner = CliRunner()
    first = runner.invoke(main, ["extras", str(dtm), "-o", str(out), "--credit", "Team A"])
    assert first.exit_code == 0, first.output
    second = runner.invoke(main, ["extras", str(ortho), "-o", str(out), "--credit", "Team B"])
    assert second.exit_code == 0, second.output
    readme = out / "README.TXT"
    assert product_ids(readme) == ["first_dtm", "second_ortho"]
    text = readme.read_text()
    assert "first_dtm.ca.jpg" in text and "second_ortho.abrowse.jpg" in text
    assert "Team A; Team B" in text
    assert hidden_files(out) == []  # no hidden state


def test_product_given_again_replaces_its_entry(two_products, tmp_path: Path):
    dtm, ortho = two_products
    out = tmp_path / "out"
    make_extras([dtm, ortho], out, browse_width=40)
    before = (out / "README.TXT").read_text()
    assert ("first_dtm.br.jpg Heights as grey levels (dark low, light high), browse "
            "(40 x 30 pixels)") in " ".join(before.split())
    with pytest.raises(PdsgenError, match="use `overwrite=True`"):  # the JPEGs still need it
        make_extras([dtm], out, browse_width=60)
    assert (out / "README.TXT").read_text() == before
    make_extras([dtm], out, browse_width=60, overwrite=True, azimuth=200.0)
    after = " ".join((out / "README.TXT").read_text().split())
    assert product_ids(out / "README.TXT") == ["first_dtm", "second_ortho"]
    assert "first_dtm.br.jpg Heights as grey levels (dark low, light high), browse " \
           "(60 x 45 pixels)" in after and "(40 x 30 pixels)" not in after
    assert "azimuth 200 degrees" in after


def test_params_keywords_of_an_earlier_call_are_kept(two_products, tmp_path: Path):
    dtm, ortho = two_products
    params = tmp_path / "in" / "params.toml"
    params.write_text('TECHNICAL_CONTACT = "J. Doe, Example Lab"\nPROJECT_NAME = "Site X"\n')
    out = tmp_path / "out"
    make_extras([dtm], out, params=params)
    make_extras([ortho], out, params={"PROJECT_NAME": "Site Y"})
    text = (out / "README.TXT").read_text()
    assert text.startswith("Site Y\n") and "J. Doe, Example Lab" in text


def test_products_whose_extras_were_removed_are_dropped(two_products, tmp_path: Path):
    dtm, ortho = two_products
    out = tmp_path / "out"
    make_extras([dtm], out)
    for jpg in out.glob("first_dtm.*.jpg"):
        jpg.unlink()
    make_extras([ortho], out)
    assert product_ids(out / "README.TXT") == ["second_ortho"]


def test_readme_is_read_back_exactly(two_products, tmp_path: Path):
    dtm, ortho = two_products
    out = tmp_path / "out"
    make_extras([dtm, ortho], out, browse_width=40,
                params={"KNOWN_ARTIFACTS": "Seams along the image edges. " * 6,
                        "TECHNICAL_CONTACT": "J. Doe",
                        "PROJECT_NAME": "A project name long enough to be wrapped " * 3})
    data = (out / "README.TXT").read_bytes()
    entries, keywords = parse_readme(data.decode("ascii"))
    assert [e["product_id"] for e in entries] == ["first_dtm", "second_ortho"]
    assert keywords["TECHNICAL_CONTACT"] == "J. Doe"
    assert keywords["PROJECT_NAME"] == " ".join(["A project name long enough to be wrapped"] * 3)
    files = [entry_files(e, out) for e in entries]
    assert render_readme(entries, files, keywords) == data  # the grammar round-trips


def test_readme_not_written_by_pdsgen_is_a_user_error_before_anything_is_written(
        two_products, tmp_path: Path):
    _, ortho = two_products
    out = tmp_path / "out"
    out.mkdir()
    (out / "README.TXT").write_text("Volume notes written by hand.\n")
    result = CliRunner().invoke(main, ["extras", str(ortho), "-o", str(out)])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1
    assert "README.TXT" in result.stderr and "Traceback" not in result.output
    assert not list(out.glob("second_ortho.*"))


def test_four_parallel_runs_into_one_directory_all_end_in_readme(tmp_path: Path):
    """Four real processes, started together, each adding one product (a batch)."""
    (tmp_path / "in").mkdir()
    names = [f"scene_{i}" for i in range(4)]
    inputs = [write_geotiff(tmp_path / "in" / f"{n}.tif", crater_field(60, 80, seed=i))
              for i, n in enumerate(names)]
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    runs = [subprocess.Popen([sys.executable, "-m", "pdsgen", "extras", str(path), "-o", str(out),
                              "--browse-width", "64"], env=env, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, text=True) for path in inputs]
    for run in runs:
        _, err = run.communicate(timeout=300)
        assert run.returncode == 0, err
    assert sorted(product_ids(out / "README.TXT")) == names
    assert hidden_files(out) == []


def test_record_of_earlier_versions_is_removed_and_unlabelled_products_get_no_credit(
        two_products, tmp_path: Path):
    dtm, _ = two_products
    out = tmp_path / "out"
    out.mkdir()
    (out / ".pdsgen-extras.json").write_text('{"format": "pdsgen extras README index 1"}')
    make_extras([dtm], out)
    assert hidden_files(out) == []
    text = (out / "README.TXT").read_text()
    assert re.search(r"^Image credit:\s+none$", text, flags=re.MULTILINE)  # nobody named
    assert "University of Arizona" not in text


def test_a_call_taken_back_keeps_what_another_run_added_meanwhile(two_products, tmp_path: Path):
    """Run A fails after publishing (here: its report callback raises) while run B has added
    its product in between: A's previews go, B's entry and previews stay in README.TXT."""
    dtm, ortho = two_products
    out = tmp_path / "out"

    def another_run_then_fail(line: str) -> None:
        make_extras([ortho], out, credit="Team B")  # a concurrent run, finished in between
        raise KeyboardInterrupt  # A is stopped before it returns

    with pytest.raises(KeyboardInterrupt):
        make_extras([dtm], out, credit="Team A", report=another_run_then_fail)
    assert product_ids(out / "README.TXT") == ["second_ortho"]
    assert not list(out.glob("first_dtm.*")) and list(out.glob("second_ortho.*"))
    assert "Team B" in (out / "README.TXT").read_text() and "Team A" not in (out / "README.TXT").read_text()
    assert hidden_files(out) == []


def test_a_replacement_taken_back_restores_the_entry_it_replaced(two_products, tmp_path: Path):
    dtm, _ = two_products
    out = tmp_path / "out"
    make_extras([dtm], out, credit="Team A")
    before = (out / "README.TXT").read_bytes()

    def fail(line: str) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        make_extras([dtm], out, credit="Team C", overwrite=True, report=fail)
    assert (out / "README.TXT").read_bytes() == before  # the earlier entry and previews are back
    assert hidden_files(out) == []
