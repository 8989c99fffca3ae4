"""The facts of a delivery's layout: directory and file names, index columns, LID rules.

One home for them: `pdsgen deliver` writes by these names and the validator's
delivery rules (validate/families/delivery_rules.py) recognise and check by them,
with their own code for everything they compute.
"""

from __future__ import annotations

import re

# PDS3 volume layout (PDS3 Standards Reference, chapter 19: volume organisation)
DATA_DIR = "DATA"
EXTRAS_DIR = "EXTRAS"
INDEX_DIR = "INDEX"
DOCUMENT_DIR = "DOCUMENT"
MISCELLANEOUS_DIR = "MISCELLANEOUS"
# Catalog files (DSMAP.CAT ...) a product label points to: where a PDS3 reader looks for a
# catalog pointer's file not beside the label (PDS3 Standards Reference, chapter 14).
CATALOG_DIR = "CATALOG"
INDEX_TABLE = "INDEX.TAB"
INDEX_LABEL = "INDEX.LBL"
VOLDESC = "VOLDESC.CAT"
AAREADME = "AAREADME.TXT"
# The checksum manifest: `md5  relative/path` lines (md5sum -c reads them), written last.
MANIFEST = "MD5SUMS.TXT"
# In a PDS4 bundle the manifest is a product: its Product_Ancillary label (pds4/checksum_manifest.py),
# written after it and, as the manifest itself, listed in no manifest.
MANIFEST_LABEL = "MD5SUMS.xml"
# The review page (pdsgen review), written after the manifest and not listed in it: it shows
# whether the manifest checks, and is remade by every run.
REVIEW_PAGE = "REVIEW.html"
# A delivery of many products has its review in pages: REVIEW.html, then REVIEW-2.html ...
_REVIEW_PAGES = re.compile(r"REVIEW(?:-[1-9][0-9]*)?\.html")


def is_review_page(name: str) -> bool:
    """A page of the delivery's review (REVIEW.html, REVIEW-2.html ...): made by every run, never
    in the manifest."""
    return _REVIEW_PAGES.fullmatch(name) is not None


def publication_rank(relative: str) -> int:
    """Where a delivery cannot be swapped in at once (an object store has no rename), the
    order its files are published in: products, previews and documents (0), then the
    labels, tables and inventories that index them (1), the checksum manifest last (2)."""
    name = relative.rsplit("/", 1)[-1]
    if relative in (MANIFEST, MANIFEST_LABEL):
        return 2
    if relative.startswith(f"{INDEX_DIR}/") or name == VOLDESC or name.startswith(("bundle_", "collection_")):
        return 1
    return 0


# A delivery is released once this file is at its root: the person who hands the delivery over
# makes it (`touch OUT/.released`). Until then a re-run of `pdsgen deliver` keeps every version;
# after it, what changed gets the next version (and the new version is not released). It is no
# part of the delivery: not in the manifest, and the validator's manifest check passes it over.
RELEASED_MARKER = ".released"

# Text a person must write is marked so; `pdsgen validate` reports any left in.
PLACEHOLDER = "[TO BE WRITTEN: {what}]"
PLACEHOLDER_PATTERN = re.compile(r"\[TO BE WRITTEN: [^\]]*\]")

# PDS3 VOLUME_ID: at most 11 characters, upper-case letters, digits and underscores.
VOLUME_ID_PATTERN = re.compile(r"[A-Z][A-Z0-9_]{0,10}")


# PDS4: one collection per kind. name -> (collection_type, bundle reference_type, directory)
COLLECTIONS = {
    "data": ("Data", "bundle_has_data_collection", DATA_DIR),
    "browse": ("Browse", "bundle_has_browse_collection", EXTRAS_DIR),
    "document": ("Document", "bundle_has_document_collection", DOCUMENT_DIR),
    # the checksum manifest's label (in the bundle's root, beside the manifest)
    # (the PDS4 collection type for products that are neither data, browse nor documents)
    "miscellaneous": ("Miscellaneous", "bundle_has_miscellaneous_collection", MISCELLANEOUS_DIR),
}


def collection_label_name(collection: str) -> str:
    return f"collection_{collection}.xml"


def inventory_name(collection: str) -> str:
    return f"collection_{collection}_inventory.csv"


def bundle_label_name(bundle_lid: str) -> str:
    return f"bundle_{bundle_lid.rsplit(':', 1)[-1]}.xml"


# A bundle LID: urn:nasa:pds:<bundle>, lower case (PDS4 Standards Reference 6D.2).
BUNDLE_LID_PATTERN = re.compile(r"urn:nasa:pds:[a-z0-9][a-z0-9._-]*")
# The part of a LID a product or collection adds: lower case letters, digits, '.', '_', '-'.
LID_PART = re.compile(r"[^a-z0-9._-]")


def lid_part(name: str) -> str:
    """A product's name as one LID segment (lower case; other characters become '_')."""
    return LID_PART.sub("_", name.lower())


# PDS3 index columns: (NAME, DATA_TYPE, description). Values are taken from each product's
# label (the first occurrence of the keyword, at any depth) except the first two.
INDEX_COLUMNS = (
    ("VOLUME_ID", "CHARACTER", "The volume holding the product."),
    ("FILE_SPECIFICATION_NAME", "CHARACTER", "Path of the product's label in the volume."),
    ("PRODUCT_ID", "CHARACTER", "The product's PRODUCT_ID."),
    ("DATA_SET_ID", "CHARACTER", "The data set the product belongs to."),
    ("PRODUCT_CREATION_TIME", "CHARACTER", "When the product was made (label, else file time)."),
    ("TARGET_NAME", "CHARACTER", "The body the product shows."),
    ("MAP_PROJECTION_TYPE", "CHARACTER", "The map projection of the product."),
    ("MAP_SCALE", "ASCII_REAL", "Map scale in metres per pixel."),
    ("MAP_RESOLUTION", "ASCII_REAL", "Map resolution in pixels per degree."),
    ("MINIMUM_LATITUDE", "ASCII_REAL", "Southernmost latitude of the product, degrees."),
    ("MAXIMUM_LATITUDE", "ASCII_REAL", "Northernmost latitude of the product, degrees."),
    ("WESTERNMOST_LONGITUDE", "ASCII_REAL", "Westernmost longitude of the product, degrees."),
    ("EASTERNMOST_LONGITUDE", "ASCII_REAL", "Easternmost longitude of the product, degrees."),
    ("LINES", "ASCII_INTEGER", "Number of lines of the image."),
    ("LINE_SAMPLES", "ASCII_INTEGER", "Number of samples per line of the image."),
)
# Written for a value the label does not hold: "N/A" in character columns, and in numeric
# columns the MISSING_CONSTANT the column then declares.
NOT_APPLICABLE = "N/A"
MISSING_NUMBER = "-9999"
