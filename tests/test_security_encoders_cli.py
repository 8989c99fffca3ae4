"""Hostile values on their way out (issue 48): every outbound case the issue names, through the
command line as an attacker would give it. Each output is well-formed and faithful - read back by
an independent reader (pvl, lxml, csv) - or the run is refused in one line on stderr naming the
keyword and the source, exit 2, with nothing partial left behind."""

from __future__ import annotations

import csv
import os
import re
import shutil
from pathlib import Path

import pvl
import pytest
from affine import Affine

from pdsgen.products.dtm import write_dtm

from helpers import CRS_SOUTH_POLAR, elevation_array, run_cli, write_raster

CRS = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs"
PARAMS = {"DATA_SET_ID": "TEST-M-DTM-5-V1.0", "DATA_SET_NAME": "TEST DTM V1.0",
          "PRODUCER_INSTITUTION_NAME": "SOME UNIVERSITY", "PRODUCER_ID": "SU", "PRODUCER_FULL_NAME": "JANE DOE",
          "RATIONALE_DESC": "Tests of the output encoders"}
TEXT = '[delivery]\ntitle = "Terrain of a test crater"\ndescription = "A test."\nauthors = ["Doe, Jane"]\n'
LATIN1 = b"caf\xe9\xe2\x80\xae"  # a Latin-1 byte (not UTF-8), then U+202E RIGHT-TO-LEFT OVERRIDE in UTF-8


@pytest.fixture(scope="module")
def raster(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("raster")
    return write_raster(root / "in.tif", elevation_array(30, 20, seed=4), CRS, Affine(1.0, 0, 0, 0, -1.0, 0))


@pytest.fixture(scope="module")
def products(tmp_path_factory, raster) -> Path:
    """Two small DTMs with PDS3 labels (read-only: tests copy what they change)."""
    source = tmp_path_factory.mktemp("products")
    for name in ("A_DTM", "B_DTM"):
        write_dtm(raster, source, product_id=name, label="pds3", params=PARAMS, overwrite=True)
    return source


def _refused(run, *named: str) -> str:
    """The one stderr line of a refusal that names every one of `named`."""
    assert run.returncode == 2, run.stdout + run.stderr
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdsgen: error: "), run.stderr
    assert all(name in lines[0] for name in named), (named, lines[0])
    assert "Traceback" not in run.stderr
    return lines[0]


def test_a_control_character_in_the_delivery_text_is_refused_naming_key_and_file(tmp_path, products):
    text = tmp_path / "delivery.toml"
    text.write_text('[delivery]\ntitle = "Terrain\\u001b[2J of a crater"\n')
    run = run_cli("deliver", products, "-o", tmp_path / "d", "--volume-id", "TEST_0001", "--text", text)
    line = _refused(run, "[delivery] title", str(text), "\\x1b")
    assert "\x1b" not in line and not (tmp_path / "d").exists()


@pytest.mark.parametrize("label", ["pds3", "pds4"])
def test_a_control_character_in_params_is_refused_naming_keyword_and_file(tmp_path, raster, label):
    params = tmp_path / "params.toml"
    params.write_text('PRODUCER_FULL_NAME = "JANE\\u0000DOE"\n')
    run = run_cli("dtm", raster, "-o", tmp_path / "out", "--params", params, "--label", label)
    _refused(run, "PRODUCER_FULL_NAME", str(params), "\\x00")
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def _edit_label(path: Path, keyword: bytes, value: bytes) -> None:
    """Give KEYWORD's quoted value of an attached label the raw bytes `value`, keeping the file's
    length (the padding after END gives or takes)."""
    data = path.read_bytes()
    end = data.index(b"\r\nEND\r\n") + 7
    head, count = re.subn(rb'(\n\s*' + keyword + rb'\s*=\s*)"[^"]*"', lambda m: m.group(1) + b'"' + value + b'"',
                          data[:end], count=1)
    grown = len(head) - end
    assert count == 1 and data[end:end + grown] == b" " * grown
    path.write_bytes(head + data[end + grown:])


def test_a_control_character_in_a_label_value_makes_no_pds4_label(tmp_path, products):
    source = tmp_path / "source"
    shutil.copytree(products, source)
    _edit_label(source / "A_DTM.IMG", b"DATA_SET_NAME", b"\x1b[31mTEST DTM")
    run = run_cli("migrate", source / "A_DTM.IMG", "-o", tmp_path / "out")
    _refused(run, str(source / "A_DTM.IMG"), "\\x1b", "XML 1.0 cannot carry")
    assert not list(tmp_path.glob("out/*.xml"))


def test_a_control_character_in_a_catalog_makes_no_bundle_label(tmp_path, products):
    """A PDS3 volume whose VOLDESC.CAT holds a control character: its PDS4 migration is refused
    naming the volume (XML 1.0 cannot carry it), and no label is left behind."""
    volume = tmp_path / "volume"
    made = run_cli("deliver", products, "-o", volume, "--volume-id", "TEST_0001", "--label", "pds3", "-q")
    assert made.returncode == 0, made.stderr
    catalog = volume / "VOLDESC.CAT"
    catalog.write_bytes(catalog.read_bytes().replace(b'VOLUME_ID            = "TEST_0001"',
                                                     b'VOLUME_ID            = "TEST\x07_0001"'))
    run = run_cli("migrate", volume, "-o", tmp_path / "out", "--bundle-lid", "urn:nasa:pds:test")
    _refused(run, str(volume), "\\x07", "XML 1.0 cannot carry")
    assert not list(tmp_path.glob("out/**/*.xml"))


def test_a_line_break_in_an_index_value_does_not_split_its_row(tmp_path, products):
    """A label value continued on the next line (CR LF inside the quotes): INDEX.TAB holds it as
    a PVL reader reads it (pvl, independent), each row RECORD_BYTES long."""
    source = tmp_path / "source"
    shutil.copytree(products, source)
    _edit_label(source / "B_DTM.IMG", b"TARGET_NAME", b"MARS\r\n  CRATER")
    run = run_cli("deliver", source, "-o", tmp_path / "d", "--volume-id", "TEST_0001", "--label", "pds3", "-q")
    assert run.returncode == 0, run.stderr
    table = (tmp_path / "d" / "INDEX" / "INDEX.TAB").read_bytes()
    label = pvl.load(str(tmp_path / "d" / "INDEX" / "INDEX.LBL"))
    rows = table.split(b"\r\n")[:-1]
    assert len(rows) == label["INDEX_TABLE"]["ROWS"] == 2
    assert {len(row) + 2 for row in rows} == {label["INDEX_TABLE"]["ROW_BYTES"]}
    names = [column["NAME"] for column in label["INDEX_TABLE"].getall("COLUMN")]
    with open(tmp_path / "d" / "INDEX" / "INDEX.TAB", newline="") as stream:
        read = {row[2].strip(): dict(zip(names, (cell.strip() for cell in row), strict=True))
                for row in csv.reader(stream)}
    as_pvl_reads = pvl.loads((source / "B_DTM.IMG").read_bytes().split(b"\r\nEND\r\n")[0].decode() + "\r\nEND")
    assert read["B_DTM"]["TARGET_NAME"] == as_pvl_reads["TARGET_NAME"] == "MARS CRATER"


@pytest.mark.parametrize("value", [b"MARS\x00", b"MARS\x1b[2J"])
def test_nul_or_esc_in_an_index_value_is_refused_naming_column_and_product(tmp_path, products, value):
    source = tmp_path / "source"
    shutil.copytree(products, source)
    _edit_label(source / "B_DTM.IMG", b"TARGET_NAME", value)
    run = run_cli("deliver", source, "-o", tmp_path / "d", "--volume-id", "TEST_0001", "--label", "pds3")
    _refused(run, "B_DTM.IMG: TARGET_NAME", f"\\x{value[4]:02x}")
    assert not (tmp_path / "d").exists()


def test_a_character_reference_in_an_old_bundle_title_cannot_forge_a_volume_statement(tmp_path, products):
    out = tmp_path / "d"
    text = tmp_path / "delivery.toml"
    text.write_text(TEXT)
    common = ["--volume-id", "TEST_0001", "--bundle-lid", "urn:nasa:pds:test", "--label", "both", "-q"]
    first = run_cli("deliver", products, "-o", out, "--text", text, *common)
    assert first.returncode == 0, first.stderr
    [bundle] = out.glob("bundle_*.xml")
    forged = "T&#34;&#13;&#10;  VOLUME_ID = &#34;FORGED_VOL"
    bundle.write_text(bundle.read_text().replace("<title>Terrain of a test crater</title>", f"<title>{forged}</title>"))
    before = {path: path.read_bytes() for path in out.rglob("*") if path.is_file()}
    again = run_cli("deliver", products, "-o", out, *common)
    _refused(again, "title", "bundle_", "double quote")
    assert {path: path.read_bytes() for path in out.rglob("*") if path.is_file()} == before
    assert [v for k, v in pvl.load(str(out / "VOLDESC.CAT"))["VOLUME"].items() if k == "VOLUME_ID"] == ["TEST_0001"]


def test_a_matcher_parameter_name_cannot_write_a_second_product_info(tmp_path):
    heights = elevation_array(40, 30, seed=11)
    source = write_raster(tmp_path / "in.tif", heights, CRS_SOUTH_POLAR,
                          Affine(100.0, 0, -20000.0, 0, -100.0, 150000.0))
    params = tmp_path / "params.toml"
    params.write_text('EXTRACTION_METHOD = "CASP-GO"\n[MATCHER_PARAMETERS]\n'
                      '"W\\nEND_OBJECT = Algorithm\\nOBJECT = ProductInfo\\n  ProductId = FORGED\\n'
                      'END_OBJECT = ProductInfo\\nOBJECT = Algorithm\\n  X" = 1\n')
    run = run_cli("dtm", source, "-o", tmp_path / "out", "--profile", "imars", "--product-id", "h0022_0000",
                  "--kind", "da4", "--vertical-datum", "areoid", "--params", params)
    _refused(run, "MATCHER_PARAMETERS", str(params), "not a PVL keyword")
    assert not list(tmp_path.glob("out/*.pvl"))


# -- names that are not UTF-8 -------------------------------------------------------------------

@pytest.fixture(scope="module")
def latin1_tree(tmp_path_factory, products) -> Path:
    """A product whose label's name holds a Latin-1 byte and U+202E."""
    root = tmp_path_factory.mktemp("latin1")
    tree = root / "tree"
    tree.mkdir()
    shutil.copy(products / "A_DTM.IMG", os.fsdecode(os.fsencode(tree) + b"/A_DTM_" + LATIN1 + b".IMG"))
    return tree


def _escaped(text: str) -> None:
    """The name shown escaped: the byte as \\xe9, the override as \\u202e, never raw."""
    assert "A_DTM_caf\\xe9\\u202e.IMG" in text
    assert "\u202e" not in text and "\udce9" not in text


def test_validate_text_github_and_output_file_show_the_name_escaped(tmp_path, latin1_tree):
    text = run_cli("validate", latin1_tree)
    assert "Traceback" not in text.stderr
    _escaped(text.stdout)
    github = run_cli("validate", latin1_tree, "--format", "github")
    _escaped(github.stdout)
    assert all(line.startswith("::") or "file(s) checked" in line for line in github.stdout.splitlines())
    written = run_cli("validate", latin1_tree, "-o", tmp_path / "report.txt")
    assert "Traceback" not in written.stderr
    _escaped((tmp_path / "report.txt").read_text(encoding="utf-8"))


@pytest.mark.parametrize("command", [("validate", "--format", "html"), ("review",)])
def test_the_review_page_shows_the_name_escaped_and_links_its_bytes(tmp_path, latin1_tree, command):
    page = tmp_path / "page.html"
    run = run_cli(command[0], latin1_tree, *command[1:], "-o", page)
    assert "Traceback" not in run.stderr, run.stderr
    html = page.read_text(encoding="utf-8")
    _escaped(html)
    import lxml.html

    links = [a.get("href") for a in lxml.html.fromstring(html).iter("a") if a.get("href")]
    assert any(link.endswith("A_DTM_caf%E9%E2%80%AE.IMG") for link in links)


def test_extras_of_a_latin1_name_write_readme_escaped(tmp_path, latin1_tree):
    [product] = latin1_tree.iterdir()
    run = run_cli("extras", product, "-o", tmp_path / "extras", "-q")
    assert "Traceback" not in run.stderr, run.stderr
    if run.returncode == 0:
        readme = (tmp_path / "extras" / "README.TXT").read_bytes()
        assert readme.isascii() and b"A_DTM_caf\\xe9\\u202e.IMG" in readme
    else:
        _refused(run, "A_DTM_caf\\xe9\\u202e.IMG")


def test_deliver_refuses_a_latin1_name_for_index_tab_in_one_line(tmp_path, latin1_tree):
    run = run_cli("deliver", latin1_tree, "-o", tmp_path / "d", "--volume-id", "TEST_0001", "--label", "pds3")
    _refused(run, "FILE_SPECIFICATION_NAME", "\\xe9")
    assert not (tmp_path / "d").exists()



def test_a_product_command_refuses_a_latin1_input_in_one_line(tmp_path, raster):
    """GDAL is given names as UTF-8: a Latin-1 input is refused by name, escaped, not a traceback."""
    source = os.fsdecode(os.fsencode(tmp_path) + b"/heights_" + LATIN1 + b".tif")
    shutil.copy(raster, source)
    run = run_cli("dtm", source, "-o", tmp_path / "out")
    _refused(run, "heights_caf\\xe9\\u202e.tif", "not UTF-8")
    assert not (tmp_path / "out").exists()
