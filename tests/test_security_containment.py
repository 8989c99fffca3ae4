"""Containment (issue 38, items 2, 3 and 7's review part): a file a label names must resolve
inside the directory tree the user gave, symbolic links resolved the same way.

Each hostile delivery is made at test time with a canary outside the tree (a file holding a
unique string); every test asserts what can be seen from outside: the canary nowhere in any
output or stream, validate reporting an error, migrate/deliver/extras refusing the product in
one line with exit 2, no traceback, and review still writing its page."""

from __future__ import annotations

import os
import shutil
import uuid
from pathlib import Path

import pytest

from pdsgen.label.beside import find_beside, outside_tree
from pdsgen.storage.containment import contained

from helpers import run_cli

NASA = Path(__file__).parent / "data" / "nasa_validate" / "github292" / "table_character" / "invalid"
PDS4_LABEL = NASA / "minimal_test_product_lf.xml"
PDS4_DATA = "minimal_test_product_crlf.tab"


@pytest.fixture
def canary(tmp_path) -> str:
    """A unique string, and the files outside the tree that hold it."""
    token = "QZ" + uuid.uuid4().hex[:15].upper()  # 17 characters, a string field of the NASA table
    outside = tmp_path / "outside"
    outside.mkdir()
    rows = b"".join(f'{i:3d},"{token}"\r\n'.encode() for i in range(2))
    (outside / "CANARY.TAB").write_bytes(rows)
    (outside / "CANARY.FMT").write_text(
        f"OBJECT = COLUMN\r\n NAME = {token}\r\n DATA_TYPE = ASCII_INTEGER\r\n START_BYTE = 1\r\n"
        " BYTES = 3\r\nEND_OBJECT = COLUMN\r\nEND\r\n", newline="")
    (outside / "CANARY.JP2").write_bytes(b"\0\0\0\x0cjP  \r\n\x87\n" + token.encode())
    (outside / PDS4_DATA).write_bytes((NASA / PDS4_DATA).read_bytes().replace(b"This is a test   ",
                                                                               token.encode()))
    return token


def _pds3_label(tree: Path, table: str, structure: str | None = None, compressed: str | None = None) -> Path:
    """A detached ASCII table of two records (`table` its pointer's file name), optionally with an
    ^STRUCTURE and a COMPRESSED_FILE naming other files."""
    (tree / "PROD.TAB").write_bytes(b"".join(f'{i:3d},"{"INSIDE":17s}"\r\n'.encode() for i in range(2)))
    columns = (f' ^STRUCTURE = "{structure}"\r\n' if structure else
               " OBJECT = COLUMN\r\n  NAME = N\r\n  DATA_TYPE = ASCII_INTEGER\r\n  START_BYTE = 1\r\n"
               "  BYTES = 3\r\n END_OBJECT = COLUMN\r\n")
    extra = (f'OBJECT = COMPRESSED_FILE\r\n FILE_NAME = "{compressed}"\r\n RECORD_TYPE = UNDEFINED\r\n'
             " ENCODING_TYPE = JP2\r\nEND_OBJECT = COMPRESSED_FILE\r\n" if compressed else "")
    label = tree / "PROD.LBL"
    label.write_text(
        "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 25\r\nFILE_RECORDS = 2\r\n"
        f'^TABLE = "{table}"\r\nPRODUCT_ID = "PROD_1"\r\nTARGET_NAME = MARS\r\n{extra}'
        "OBJECT = TABLE\r\n INTERCHANGE_FORMAT = ASCII\r\n ROWS = 2\r\n COLUMNS = 1\r\n ROW_BYTES = 25\r\n"
        f"{columns}END_OBJECT = TABLE\r\nEND\r\n", newline="")
    return label


def _hostile_pds3(tmp_path: Path, how: str) -> Path:
    """The tree holding one PDS3 product whose label reaches the canary `how`."""
    tree = tmp_path / "tree"
    tree.mkdir()
    outside = tmp_path / "outside"
    if how == "dotdot":
        _pds3_label(tree, "../outside/CANARY.TAB")
    elif how == "absolute":
        _pds3_label(tree, str(outside / "CANARY.TAB"))
    elif how == "symlink":
        _pds3_label(tree, "LINKED.TAB")
        (tree / "LINKED.TAB").symlink_to(outside / "CANARY.TAB")
    elif how == "structure":
        _pds3_label(tree, "PROD.TAB", structure="../outside/CANARY.FMT")
    elif how == "structure_link":
        _pds3_label(tree, "PROD.TAB", structure="PROD.FMT")
        (tree / "PROD.FMT").symlink_to(outside / "CANARY.FMT")
    elif how == "compressed":
        _pds3_label(tree, "PROD.TAB", compressed="../outside/CANARY.JP2")
    return tree


HOW = ["dotdot", "absolute", "symlink", "structure", "structure_link", "compressed"]


def _nowhere(token: str, *places: Path | str) -> None:
    """The canary is in no stream given and in no file under any directory given."""
    for place in places:
        if isinstance(place, str):
            assert token not in place
            continue
        for path in [place] if place.is_file() else (place.rglob("*") if place.exists() else []):
            if path.is_file() and not path.is_symlink():
                assert token.encode() not in path.read_bytes(), path


def _one_line_refusal(done, label_name: str) -> None:
    assert done.returncode == 2, (done.stdout, done.stderr)
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and label_name in lines[0] and "outside" in lines[0], done.stderr
    assert "Traceback" not in done.stderr


# -- the rule itself ---------------------------------------------------------------------------

def test_contained_resolves_links_and_climbs_before_deciding(tmp_path, canary):
    tree = tmp_path / "tree"
    (tree / "sub").mkdir(parents=True)
    (tree / "sub" / "inside.dat").write_bytes(b"x")
    (tree / "hop").symlink_to(tree / "sub" / "inside.dat")
    (tree / "out").symlink_to(tmp_path / "outside" / "CANARY.TAB")
    (tree / "chain").symlink_to(tree / "out")
    assert contained(tree / "hop", tree) == tree / "hop"
    assert contained(tree / "sub" / ".." / "sub" / "inside.dat", tree) is not None
    for hostile in (tree / "out", tree / "chain", tree / ".." / "outside" / "CANARY.TAB",
                    tmp_path / "outside" / "CANARY.TAB", tmp_path / "tree-sibling"):
        assert contained(hostile, tree) is None
    assert find_beside(tree, "out") is None and find_beside(tree, "../outside/CANARY.TAB") is None
    assert find_beside(tree, str(tmp_path / "outside" / "CANARY.TAB")) is None
    assert outside_tree(tree, "../outside/CANARY.TAB") is not None and outside_tree(tree, "out") is not None
    assert outside_tree(tree, "../nowhere") is None  # nothing there to read (PTR-002 tells a missing data file)
    assert outside_tree(tree, "missing.dat") is None and outside_tree(tree, "hop") is None


# -- migrate and deliver: the most serious (they copied the outside file) -------------------------

@pytest.mark.parametrize("how", HOW)
def test_migrate_refuses_a_label_naming_a_file_outside(tmp_path, canary, how):
    tree = _hostile_pds3(tmp_path, how)
    out = tmp_path / "out"
    done = run_cli("migrate", tree / "PROD.LBL", "-o", out, "--bundle-lid", "urn:nasa:pds:hostile")
    _one_line_refusal(done, "PROD.LBL")
    _nowhere(canary, done.stdout, done.stderr, out)
    assert not out.exists() or not any(out.iterdir())


@pytest.mark.parametrize("how", HOW)
@pytest.mark.parametrize("dialect", ["--pds4", "--both"])
def test_deliver_never_holds_a_file_from_outside(tmp_path, canary, how, dialect):
    tree = _hostile_pds3(tmp_path, how)
    out = tmp_path / "delivery"
    done = run_cli("deliver", tree, dialect, "-o", out, "--bundle-lid", "urn:nasa:pds:hostile",
                   "--volume-id", "HOSTILE_1")
    assert done.returncode == 2, (done.stdout, done.stderr)
    assert len(done.stderr.strip().splitlines()) == 1 and "outside" in done.stderr and "Traceback" not in done.stderr
    _nowhere(canary, done.stdout, done.stderr, out, tmp_path / "tree")
    assert not out.exists()


def test_deliver_pds3_refuses_a_symbolic_link_leading_out(tmp_path, canary):
    tree = _hostile_pds3(tmp_path, "symlink")
    out = tmp_path / "delivery"
    done = run_cli("deliver", tree, "--pds3", "-o", out, "--volume-id", "HOSTILE_1")
    _one_line_refusal(done, "LINKED.TAB")
    _nowhere(canary, done.stdout, done.stderr, out)


@pytest.mark.parametrize("name", ["../outside/" + PDS4_DATA, "ABSOLUTE"])
def test_deliver_refuses_a_pds4_file_name_outside(tmp_path, canary, name):
    tree = tmp_path / "tree"
    tree.mkdir()
    name = str(tmp_path / "outside" / PDS4_DATA) if name == "ABSOLUTE" else name
    (tree / "prod.xml").write_text(PDS4_LABEL.read_text().replace(f"<file_name>{PDS4_DATA}<", f"<file_name>{name}<"))
    out = tmp_path / "delivery"
    done = run_cli("deliver", tree, "--pds4", "-o", out, "--bundle-lid", "urn:nasa:pds:hostile")
    _one_line_refusal(done, "prod.xml")
    _nowhere(canary, done.stdout, done.stderr, out)


# -- validate: an error, and the outside file is not read ------------------------------------------

@pytest.mark.parametrize("how", HOW)
@pytest.mark.parametrize("fmt", ["text", "json", "sarif", "github"])
def test_validate_reports_a_pds3_name_leaving_the_tree(tmp_path, canary, how, fmt):
    tree = _hostile_pds3(tmp_path, how)
    done = run_cli("validate", tree, "--format", fmt)
    assert done.returncode == 1, (done.stdout, done.stderr)
    assert "PTR-009" in done.stdout and "Traceback" not in done.stderr
    _nowhere(canary, done.stdout, done.stderr)


@pytest.mark.parametrize("name", ["../outside/" + PDS4_DATA, "ABSOLUTE", "LINK"])
@pytest.mark.parametrize("fmt", ["text", "json", "sarif", "github"])
def test_validate_reports_a_pds4_file_name_leaving_the_tree(tmp_path, canary, name, fmt):
    tree = tmp_path / "tree"
    tree.mkdir()
    if name == "LINK":
        (tree / PDS4_DATA).symlink_to(tmp_path / "outside" / PDS4_DATA)
        name = PDS4_DATA
    name = str(tmp_path / "outside" / PDS4_DATA) if name == "ABSOLUTE" else name
    (tree / "prod.xml").write_text(PDS4_LABEL.read_text().replace(f"<file_name>{PDS4_DATA}<", f"<file_name>{name}<"))
    done = run_cli("validate", tree, "--format", fmt, "--offline")
    assert done.returncode == 1, (done.stdout, done.stderr)
    assert "PDS4-064" in done.stdout and "Traceback" not in done.stderr
    assert fmt == "sarif" or "PDS4-052" not in done.stdout  # SARIF lists every rule; the others the findings
    _nowhere(canary, done.stdout, done.stderr)


def test_genuine_pds4_table_beside_its_label_is_still_read(tmp_path):
    shutil.copy(PDS4_LABEL, tmp_path)
    shutil.copy(NASA / PDS4_DATA, tmp_path)
    done = run_cli("validate", tmp_path / PDS4_LABEL.name, "--offline")
    assert "PDS4-052" in done.stdout and "PDS4-064" not in done.stdout


# -- extras and review -------------------------------------------------------------------------

@pytest.mark.parametrize("how", ["dotdot", "absolute", "symlink"])
def test_extras_refuses_a_label_naming_a_file_outside(tmp_path, canary, how):
    tree = tmp_path / "tree"
    tree.mkdir()
    target = {"dotdot": "../outside/CANARY.IMG", "absolute": str(tmp_path / "outside" / "CANARY.IMG"),
              "symlink": "CANARY.IMG"}[how]
    (tmp_path / "outside" / "CANARY.IMG").write_bytes(canary.encode() * 64)
    if how == "symlink":
        (tree / "CANARY.IMG").symlink_to(tmp_path / "outside" / "CANARY.IMG")
    (tree / "PROD.LBL").write_text(
        f'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = UNDEFINED\r\n^IMAGE = "{target}"\r\nPRODUCT_ID = PROD\r\n'
        "OBJECT = IMAGE\r\n LINES = 4\r\n LINE_SAMPLES = 4\r\n SAMPLE_TYPE = UNSIGNED_INTEGER\r\n"
        " SAMPLE_BITS = 8\r\nEND_OBJECT = IMAGE\r\nEND\r\n", newline="")
    out = tmp_path / "extras"
    done = run_cli("extras", tree / "PROD.LBL", "-o", out)
    _one_line_refusal(done, "PROD.LBL")
    _nowhere(canary, done.stdout, done.stderr, out)


def _review_tree(tmp_path: Path, name: str) -> Path:
    tree = tmp_path / "tree"
    tree.mkdir()
    _pds3_label(tree, "PROD.TAB")  # a genuine product beside the hostile one
    (tree / "prod.xml").write_text(PDS4_LABEL.read_text().replace(f"<file_name>{PDS4_DATA}<", f"<file_name>{name}<"))
    return tree


@pytest.mark.parametrize("name", ["missing.tab", "../outside/" + PDS4_DATA])
def test_review_shows_a_product_whose_file_is_missing_or_outside_and_writes_the_page(tmp_path, canary, name):
    tree = _review_tree(tmp_path, name)
    page = tmp_path / "review.html"
    done = run_cli("review", tree, "-o", page)
    assert done.returncode in (0, 1), (done.stdout, done.stderr)
    assert "Traceback" not in done.stderr and page.is_file()
    html = page.read_text()
    assert "PROD_1" in html and "prod" in html
    assert ("PDS4-010" if name == "missing.tab" else "PDS4-064") in html
    _nowhere(canary, done.stdout, done.stderr, page)


def test_review_passes_over_a_symbolic_link_leading_out(tmp_path, canary):
    tree = _review_tree(tmp_path, PDS4_DATA)
    shutil.copy(NASA / PDS4_DATA, tree)
    os.symlink(tmp_path / "outside" / "CANARY.TAB", tree / "STRAY.TAB")
    page = tmp_path / "review.html"
    done = run_cli("review", tree, "-o", page)
    assert done.returncode in (0, 1) and page.is_file(), done.stderr
    _nowhere(canary, done.stdout, done.stderr, page)


def test_an_index_table_outside_is_read_by_neither_validate_nor_review(tmp_path, canary):
    tree = tmp_path / "tree"
    (tree / "INDEX").mkdir(parents=True)
    _pds3_label(tree, "PROD.TAB")
    (tree / "INDEX" / "INDEX.LBL").write_text(
        "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 25\r\nFILE_RECORDS = 2\r\n"
        '^INDEX_TABLE = "../../outside/CANARY.TAB"\r\nOBJECT = INDEX_TABLE\r\n INTERCHANGE_FORMAT = ASCII\r\n'
        " ROWS = 2\r\n COLUMNS = 2\r\n ROW_BYTES = 25\r\n"
        " OBJECT = COLUMN\r\n  NAME = VOLUME_ID\r\n  DATA_TYPE = ASCII_INTEGER\r\n  START_BYTE = 1\r\n  BYTES = 3\r\n"
        " END_OBJECT = COLUMN\r\n OBJECT = COLUMN\r\n  NAME = PRODUCT_ID\r\n  DATA_TYPE = CHARACTER\r\n"
        "  START_BYTE = 6\r\n  BYTES = 17\r\n END_OBJECT = COLUMN\r\nEND_OBJECT = INDEX_TABLE\r\nEND\r\n", newline="")
    (tree / "VOLDESC.CAT").write_text("PDS_VERSION_ID = PDS3\r\nOBJECT = VOLUME\r\n VOLUME_ID = HOSTILE_1\r\n"
                                      "END_OBJECT = VOLUME\r\nEND\r\n", newline="")
    for fmt in ("text", "json"):
        done = run_cli("validate", tree, "--format", fmt)
        assert done.returncode in (0, 1) and "Traceback" not in done.stderr, done.stderr
        _nowhere(canary, done.stdout, done.stderr)
    page = tmp_path / "review.html"
    done = run_cli("review", tree, "-o", page)
    assert page.is_file() and "Traceback" not in done.stderr, done.stderr
    _nowhere(canary, done.stdout, done.stderr, page)


# -- the tree given: a volume checked whole, or a label given alone widened by --root -----------

def _volume(tmp_path: Path) -> tuple[Path, Path, Path]:
    """A volume-shaped tree (as genuine Cassini volumes are): DATA/X/PROD.LBL whose table's
    ^STRUCTURE names ../../LABEL/T.FMT, and DATA/Y/PROD.LBL whose table is the canary outside
    the volume. (volume, genuine label, hostile label)"""
    volume = tmp_path / "VOLUME"
    genuine, hostile = volume / "DATA" / "X", volume / "DATA" / "Y"
    for directory in (genuine, hostile, volume / "LABEL"):
        directory.mkdir(parents=True)
    (volume / "LABEL" / "T.FMT").write_text(
        "OBJECT = COLUMN\r\n NAME = N\r\n DATA_TYPE = ASCII_INTEGER\r\n START_BYTE = 1\r\n BYTES = 3\r\n"
        "END_OBJECT = COLUMN\r\nEND\r\n", newline="")
    _pds3_label(genuine, "PROD.TAB", structure="../../LABEL/T.FMT")
    _pds3_label(hostile, "../../../outside/CANARY.TAB")
    return volume, genuine / "PROD.LBL", hostile / "PROD.LBL"


def _ptr009_files(done) -> set[str]:
    import json

    assert "Traceback" not in done.stderr, done.stderr
    return {f["file"] for report in json.loads(done.stdout)["files"] for f in report["findings"]
            if f["rule"] == "PTR-009"}


def test_validate_trusts_the_directory_given_or_the_root(tmp_path, canary):
    volume, genuine, hostile = _volume(tmp_path)
    whole = run_cli("validate", volume, "--format", "json")
    assert _ptr009_files(whole) == {str(hostile)}  # the volume's own format file is inside the tree given
    _nowhere(canary, whole.stdout, whole.stderr)
    alone = run_cli("validate", genuine, "--format", "json")
    assert alone.returncode == 1 and _ptr009_files(alone) == {str(genuine)}  # ../../LABEL leaves the label's directory
    for given in (genuine, hostile):
        widened = run_cli("validate", given, "--root", volume, "--format", "json")
        assert _ptr009_files(widened) == ({str(hostile)} if given == hostile else set())
        _nowhere(canary, widened.stdout, widened.stderr)
    assert _ptr009_files(run_cli("validate", volume / "DATA", "--root", volume, "--format", "json")) == {str(hostile)}


def test_migrate_trusts_the_label_directory_or_the_root(tmp_path, canary):
    volume, genuine, hostile = _volume(tmp_path)
    out = tmp_path / "out"
    _one_line_refusal(run_cli("migrate", genuine, "-o", out, "--bundle-lid", "urn:nasa:pds:vol"), "PROD.LBL")
    done = run_cli("migrate", genuine, "-o", out, "--bundle-lid", "urn:nasa:pds:vol", "--root", volume)
    assert done.returncode == 0, (done.stdout, done.stderr)
    assert (out / "PROD.TAB").read_bytes() == (genuine.parent / "PROD.TAB").read_bytes()
    assert "<name>N</name>" in (out / "PROD.xml").read_text()  # the columns of the volume's format file
    refused = tmp_path / "refused"
    for extra in ((), ("--root", volume)):
        done = run_cli("migrate", hostile, "-o", refused, "--bundle-lid", "urn:nasa:pds:vol", *extra)
        _one_line_refusal(done, "PROD.LBL")
        _nowhere(canary, done.stdout, done.stderr, refused, out)


def test_deliver_trusts_the_directory_given(tmp_path, canary):
    volume, genuine, hostile = _volume(tmp_path)
    shutil.rmtree(hostile.parent)
    out = tmp_path / "delivery"
    done = run_cli("deliver", volume, "--pds4", "-o", out, "--bundle-lid", "urn:nasa:pds:vol")
    assert done.returncode == 0, (done.stdout, done.stderr)
    copies = [p for p in out.rglob("PROD.TAB")]
    assert copies and all(p.read_bytes() == (genuine.parent / "PROD.TAB").read_bytes() for p in copies)
