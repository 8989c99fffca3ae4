"""Untidy volumes as genuine ones are: the genuine SBN_0233 parts (tests/data/volume_fbirtfspec)
changed at test time the ways other volumes differ - an index named `volindex` whose label names
the table in upper case while the disk holds lower case, paths right-justified in their column,
and a DATA_SET catalog without its PDS3 header."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from lxml import etree

from pdsgen.migrate.volume import migrate_volume

VOLUME = Path(__file__).parent / "data" / "volume_fbirtfspec"
PDS = "{http://pds.nasa.gov/pds4/pds/v1}"
PATH_FIELD = 42  # FILE_SPECIFICATION_NAME: START_BYTE 2, BYTES 42 (inside the quotes)


def _right_justified(row: bytes) -> bytes:
    path = row[1:1 + PATH_FIELD]
    return row[:1] + path.strip().rjust(PATH_FIELD) + row[1 + PATH_FIELD:]


def test_a_volindex_in_other_case_with_right_justified_paths_and_a_headless_catalog(tmp_path):
    volume = tmp_path / "SBN_0233"
    shutil.copytree(VOLUME, volume)
    index = volume / "index"
    label = (index / "index.lbl").read_text(encoding="ascii")
    (index / "index.lbl").unlink()
    (index / "volindex.lbl").write_text(label.replace('"index.tab"', '"VOLINDEX.TAB"'), encoding="ascii",
                                        newline="")
    rows = (index / "index.tab").read_bytes().split(b"\r\n")
    (index / "index.tab").unlink()
    (index / "volindex.tab").write_bytes(b"\r\n".join(_right_justified(r) if r else r for r in rows))
    assert b'"' + b"data/fieberbeyer2010/1358.lbl".rjust(PATH_FIELD) + b'"' in (index / "volindex.tab").read_bytes()
    catalog = volume / "catalog" / "dataset.cat"
    text = catalog.read_text(encoding="ascii")
    catalog.write_text(text[re.search(r"^OBJECT\s*=\s*DATA_SET\s*$", text, re.M).start():], encoding="ascii",
                       newline="")
    assert not catalog.read_text().startswith("PDS_VERSION_ID")

    out = tmp_path / "bundle"
    result = migrate_volume(volume, out, bundle_lid="urn:nasa:pds:fbirtfspec")
    assert result.index == "index/volindex.tab"
    assert result.unindexed == [] and len(result.missing) == 50
    assert result.refused == ()
    title = etree.parse(str(out / "bundle_fbirtfspec.xml")).getroot().findtext(f".//{PDS}title")
    assert title == "FIEBER-BEYER IRTF MAINBELT ASTEROID SPECTRA V3.0"
    assert (out / "index" / "volindex.xml").is_file()  # the index migrated as a product under its own name


def _crlf(*lines: str) -> str:
    return "\r\n".join(lines) + "\r\n"


def test_a_format_file_in_the_volume_label_directory_is_found_and_kept(tmp_path):
    """^STRUCTURE = "SPECTRUM.FMT" from DATA/D000/P1.LBL: the file is in the volume's LABEL/ (PDS3
    Standards Reference 19.3), two directories up; kept there, and the table read through it."""
    pds4_tools = pytest.importorskip("pds4_tools")
    volume = tmp_path / "VOL"
    (volume / "LABEL").mkdir(parents=True)
    (volume / "DATA" / "D000").mkdir(parents=True)
    (volume / "LABEL" / "SPECTRUM.FMT").write_text(_crlf(
        "OBJECT = COLUMN", '  NAME = "WAVELENGTH"', "  DATA_TYPE = ASCII_REAL", "  START_BYTE = 1", "  BYTES = 6",
        "END_OBJECT = COLUMN", "OBJECT = COLUMN", '  NAME = "REFLECTANCE"', "  DATA_TYPE = ASCII_REAL",
        "  START_BYTE = 8", "  BYTES = 6", "END_OBJECT = COLUMN"), newline="")
    (volume / "DATA" / "D000" / "P1.TAB").write_text("0.5000 0.2500\r\n0.6000 0.2750\r\n", newline="")
    (volume / "DATA" / "D000" / "P1.LBL").write_text(_crlf(
        "PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", "RECORD_BYTES = 15", "FILE_RECORDS = 2",
        '^TABLE = "P1.TAB"', 'PRODUCT_ID = "P1"', "OBJECT = TABLE", "  ROWS = 2", "  ROW_BYTES = 15",
        "  INTERCHANGE_FORMAT = ASCII", "  COLUMNS = 2", '  ^STRUCTURE = "SPECTRUM.FMT"', "END_OBJECT = TABLE",
        "END"), newline="")
    out = tmp_path / "bundle"
    result = migrate_volume(volume, out, bundle_lid="urn:nasa:pds:fmt_volume")
    assert result.refused == ()
    assert result.kept == ["LABEL/SPECTRUM.FMT"]
    assert (out / "LABEL" / "SPECTRUM.FMT").read_bytes() == (volume / "LABEL" / "SPECTRUM.FMT").read_bytes()
    table = pds4_tools.read(str(out / "DATA" / "D000" / "P1.xml"), quiet=True)[0].data
    assert list(table["REFLECTANCE"]) == [0.25, 0.275]


def test_browse_images_link_to_the_product_their_name_starts_with(tmp_path):
    """BROWSE/1358_PLOT.PNG previews the product of 1358.lbl (its name up to a '_'); an image no
    product's name starts is left out with its reason."""
    import numpy as np
    from PIL import Image

    volume = tmp_path / "SBN_0233"
    shutil.copytree(VOLUME, volume)
    (volume / "browse").mkdir()
    picture = Image.fromarray(np.arange(64, dtype=np.uint8).reshape(8, 8))
    picture.save(volume / "browse" / "1358_PLOT.PNG", format="PNG")
    picture.save(volume / "browse" / "9999_PLOT.PNG", format="PNG")
    out = tmp_path / "bundle"
    result = migrate_volume(volume, out, bundle_lid="urn:nasa:pds:fbirtfspec")
    browse = etree.parse(str(out / "browse" / "1358_PLOT.xml")).getroot()
    assert browse.findtext(f".//{PDS}lidvid_reference") == "urn:nasa:pds:fbirtfspec:data:fieberbeyer2010_1358_tab::1.0"
    assert browse.findtext(f".//{PDS}encoding_standard_id") == "PNG"
    assert [path for path, _ in result.left_out] == ["browse/9999_PLOT.PNG"]
    assert result.counts["Product_Browse"] == 1


def test_a_lid_longer_than_the_standard_allows_is_shortened_and_reported(tmp_path):
    volume = tmp_path / "SBN_0233"
    shutil.copytree(VOLUME, volume)
    label = volume / "data" / "fieberbeyer2010" / "335.lbl"
    long_id = "FIEBERBEYER2010_335_" + "X" * 240
    label.write_bytes(label.read_bytes().replace(b'"FIEBERBEYER2010_335_TAB"', f'"{long_id}"'.encode()))
    out = tmp_path / "bundle"
    result = migrate_volume(volume, out, bundle_lid="urn:nasa:pds:fbirtfspec")
    assert result.refused == ()
    lid = etree.parse(str(out / "data" / "fieberbeyer2010" / "335.xml")).getroot().findtext(
        f".//{PDS}logical_identifier")
    assert len(lid) == 255 and lid.startswith("urn:nasa:pds:fbirtfspec:data:fieberbeyer2010_335_xxx")
    assert [c for c in result.collisions if "longer than 255" in c and lid in c]


def test_a_refused_product_is_listed_and_its_table_is_not_taken_for_a_document(tmp_path):
    """A truncated data file (genuine 335.tab cut to 3,000 bytes): the product is refused with the
    reason, its table left out as that product's file, and the other products migrated."""
    volume = tmp_path / "SBN_0233"
    shutil.copytree(VOLUME, volume)
    table = volume / "data" / "fieberbeyer2010" / "335.tab"
    table.write_bytes(table.read_bytes()[:3000])
    out = tmp_path / "bundle"
    result = migrate_volume(volume, out, bundle_lid="urn:nasa:pds:fbirtfspec")
    assert len(result.refused) == 1 and "335.lbl" in result.refused[0] and "truncated" in result.refused[0]
    assert result.exit_code == 2
    assert result.left_out == [("data/fieberbeyer2010/335.tab",
                                "a data file of the refused product data/fieberbeyer2010/335.lbl")]
    assert not (out / "data" / "fieberbeyer2010" / "335.xml").exists()
    assert (out / "data" / "fieberbeyer2010" / "1358.xml").is_file()
    assert result.counts["Product_Observational"] == 4  # 1358, 1447, the index and the checksum table
