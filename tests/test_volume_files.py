"""A volume file's document_standard_id / encoding_standard_id from its bytes, checked on files
real writers made: Pillow's PNG, GIF, JPEG and TIFF, GDAL's PDF and JPEG 2000, and text."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from pdsgen.migrate.volume_files import document_standard, image_encoding


@pytest.fixture(scope="module")
def images(tmp_path_factory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("formats")
    picture = Image.fromarray(np.arange(64, dtype=np.uint8).reshape(8, 8))
    made = {}
    for kind, name in (("PNG", "a.png"), ("GIF", "a.gif"), ("JPEG", "a.jpg"), ("TIFF", "a.tif")):
        picture.save(root / name, format=kind)
        made[kind] = root / name
    for kind, name, driver in (("PDF", "a.pdf", "PDF"), ("JP2", "a.jp2", "JP2OpenJPEG")):
        subprocess.run(["gdal_translate", "-q", "-of", driver, str(made["PNG"]), str(root / name)], check=True)
        made[kind] = root / name
    return made


def test_images_are_told_by_their_bytes_not_their_names(images, tmp_path):
    for kind in ("PNG", "GIF", "JPEG", "TIFF", "JP2"):
        renamed = tmp_path / f"image_{kind}.IMG"  # a name that says nothing
        renamed.write_bytes(images[kind].read_bytes())
        assert image_encoding(renamed) == kind
    assert image_encoding(images["PDF"]) is None


def test_document_standards(images, tmp_path):
    assert document_standard(images["PDF"]) == "PDF"
    pdfa = tmp_path / "a_pdfa.pdf"  # the XMP packet of a PDF/A declares its part
    pdfa.write_bytes(images["PDF"].read_bytes() + b"\n<x:xmpmeta><pdfaid:part>1</pdfaid:part></x:xmpmeta>\n")
    assert document_standard(pdfa) == "PDF/A"
    for kind in ("PNG", "GIF", "JPEG", "TIFF"):
        assert document_standard(images[kind]) == kind
    text = tmp_path / "AAREADME.TXT"
    text.write_bytes(b"PDS_VERSION_ID = PDS3\r\nEND\r\nplain text\r\n")
    assert document_standard(text) == "7-Bit ASCII Text"
    accented = tmp_path / "notes.txt"
    accented.write_text("Fieber-Beyer, Pâris\n", encoding="utf-8")
    assert document_standard(accented) == "UTF-8 Text"
    page = tmp_path / "index.htm"
    page.write_bytes(b"  <!DOCTYPE html>\n<html><body>volume</body></html>\n")
    assert document_standard(page) == "HTML"
    latin1 = tmp_path / "old.txt"
    latin1.write_bytes("Pâris".encode("latin-1"))
    assert document_standard(latin1) is None  # no PDS4 value fits: left out with its reason
    binary = tmp_path / "tool.exe"
    binary.write_bytes(b"MZ\x90\x00\x03\x00")
    assert document_standard(binary) is None
