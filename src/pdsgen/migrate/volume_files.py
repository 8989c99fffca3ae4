"""What a file of a PDS3 volume is, told by its place in the volume and by its own bytes.

A volume's parts (PDS3 Standards Reference, chapter 19) each become a part of the PDS4
bundle or are left out with a stated reason; `VOLUME_PARTS` is the one table of that,
which docs/migrate-volume.md shows (a test compares the two). The formats of documents
and browse images come from the files' first bytes, never from their names alone.
"""

from __future__ import annotations

import codecs
from pathlib import Path

from ..archive import layout
from ..formats.sniff import file_head
from ..validate.pds4.document_checks import marked_pdf_a

SOFTWARE_REASON = ("software is not migrated: PDS4 archives take no executables, and a Product_Software "
                   "needs facts a PDS3 volume does not state")
# volume part -> (bundle part, what becomes of it). Order: as a reader meets them.
VOLUME_PARTS: tuple[tuple[str, str, str], ...] = (
    ("data product (PDS3 label, attached or detached)", "data collection (one per DATA_SET_ID when "
                                                        "VOLDESC.CAT names several)",
     "the PDS4 label `pdsgen migrate` writes, beside byte-identical copies of its files"),
    ("INDEX/ table (INDEX.TAB, or an index named otherwise)", "data collection",
     "migrated as a product; its rows are the manifest the products are checked against"),
    ("VOLDESC.CAT", "document collection", "Product_Document (format from the bytes: 7-Bit ASCII Text)"),
    ("AAREADME.TXT, ERRATA.TXT, other .TXT/.ASC/.CAT/.PDF/.HTM files", "document collection",
     "Product_Document (format from the bytes), unless a product's label names the file as its data"),
    ("CATALOG/*.CAT", "document collection", "Product_Document; the DATA_SET catalog gives the bundle's "
                                            "title, description, citation and keywords"),
    ("DOCUMENT/*", "document collection", "Product_Document (7-Bit ASCII Text, UTF-8 Text, PDF, PDF/A, HTML, "
                                         "images ...); a PDS3 label of a document travels as a second file"),
    ("BROWSE/*, EXTRAS/* images", "browse collection", "Product_Browse (Encoded_Image), linked to the data "
                                                      "product whose PRODUCT_ID or label name starts the "
                                                      "image's name (up to a '.' or '_')"),
    ("LABEL/*.FMT and other .FMT files", "kept at their paths", "no PDS4 class: the PDS3 labels naming them "
                                                               "still read them; not in any inventory"),
    ("SOFTWARE/", "left out", SOFTWARE_REASON),
    ("MD5SUMS.TXT, REVIEW pages", "made anew", "the bundle's own checksum manifest replaces them"),
    ("any other file (a browse image of no product, a document of no PDS4 format)", "left out",
     "no label describes it; reported by name with the reason (and in the crosswalk)"),
    ("(none)", "bundle label", "Product_Bundle from VOLDESC.CAT and the DATA_SET catalog, DATA_SET_ID and "
                              "VOLUME_ID as aliases, context references PDS registers"),
    ("(none)", "miscellaneous collection", "the crosswalk: Product_Ancillary, a Table_Delimited of every "
                                          "PDS3 file -> the LIDVID holding it and its role, or why it was left out"),
)

# Directories of a volume by role (upper case; a volume on disk may have any case).
DOCUMENT_DIRS = frozenset({"DOCUMENT", "CATALOG"})
BROWSE_DIRS = frozenset({"BROWSE", "EXTRAS"})
INDEX_DIRS = frozenset({"INDEX"})
SOFTWARE_DIRS = frozenset({"SOFTWARE"})
TOP_DOCUMENTS = frozenset({"VOLDESC.CAT", "AAREADME.TXT", "ERRATA.TXT", "AAREADME.HTM", "AAREADME.PDF"})
MADE_ANEW = frozenset({layout.MANIFEST.upper()})  # the bundle writes its own manifest
# Documents wherever they lie (INDEX/INDXINFO.TXT, an attached TEXT label); one a detached
# label names as its data stays data.
DOCUMENT_SUFFIXES = frozenset({".TXT", ".ASC", ".CAT", ".PDF", ".HTM", ".HTML"})

# first bytes -> Encoded_Image encoding_standard_id
_IMAGE_MAGIC = ((b"\xff\xd8\xff", "JPEG"), (b"\x89PNG\r\n\x1a\n", "PNG"), (b"GIF87a", "GIF"), (b"GIF89a", "GIF"),
                (b"\x00\x00\x00\x0cjP  \r\n\x87\n", "JP2"), (b"\xffO\xffQ", "J2C"), (b"II*\x00", "TIFF"),
                (b"MM\x00*", "TIFF"))
_MS_WORD = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1"  # OLE2: .doc (and .xls)
_SNIFF = 1 << 16


def image_encoding(path: Path) -> str | None:
    """The image format of a file by its first bytes (JPEG, PNG, GIF, JP2, J2C, TIFF); None if none."""
    head = file_head(path, 16) or b""
    return next((code for magic, code in _IMAGE_MAGIC if head.startswith(magic)), None)


def document_standard(path: Path) -> str | None:
    """Document_File's document_standard_id from the file's bytes; None when no PDS4 value fits.

    PDF/A is a PDF whose XMP metadata declares a pdfaid part; HTML is text that opens with
    <html or <!DOCTYPE html; text is 7-Bit ASCII when every byte is, else UTF-8 when it
    decodes so."""
    head = file_head(path, _SNIFF) or b""
    if head.startswith(b"%PDF-"):
        return "PDF/A" if marked_pdf_a(path) else "PDF"
    image = image_encoding(path)
    if image in ("JPEG", "PNG", "GIF", "TIFF"):
        return image
    if head.startswith(_MS_WORD):
        return "Microsoft Word" if path.suffix.lower() == ".doc" else None
    if head.startswith(b"{\\rtf"):
        return "Rich Text"
    if head.startswith(b"%!PS"):
        return "Encapsulated Postscript" if b"EPSF" in head[:40] else "Postscript"
    return _text_standard(path, head)


def _text_standard(path: Path, head: bytes) -> str | None:
    """HTML, 7-Bit ASCII or UTF-8 Text for a file of text (no NUL byte anywhere), None for any
    other bytes; read in blocks, so a large file costs no more memory than a small one."""
    ascii_only = True
    utf8: codecs.IncrementalDecoder | None = codecs.getincrementaldecoder("utf-8")()
    with open(path, "rb") as stream:
        while block := stream.read(1 << 20):
            if b"\x00" in block:
                return None
            ascii_only = ascii_only and block.isascii()
            if utf8 is not None:
                try:
                    utf8.decode(block)
                except UnicodeDecodeError:
                    utf8 = None
    if head.lstrip()[:14].lower().startswith((b"<!doctype html", b"<html")):
        return "HTML"
    if ascii_only:
        return "7-Bit ASCII Text"
    try:
        return "UTF-8 Text" if utf8 is not None and utf8.decode(b"", final=True) == "" else None
    except UnicodeDecodeError:
        return None
