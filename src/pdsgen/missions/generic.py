"""The generic profile: no mission; names come from the input file, keywords are UNK."""

from __future__ import annotations

import re

from ..errors import PdsgenError, param
from .base import Mission, ProductIdRequest

# A PDS product ID pdsgen accepts: 1-40 letters, digits, '_', '-' or '.'.
PRODUCT_ID_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9_\-.]{0,39}")

KEYWORDS = {
    "DATA_SET_ID": "UNK",
    "DATA_SET_NAME": "UNK",
    "PRODUCER_INSTITUTION_NAME": "UNK",
    "PRODUCER_ID": "UNK",
    "PRODUCER_FULL_NAME": "UNK",
    "INSTRUMENT_HOST_NAME": "UNK",
    "INSTRUMENT_HOST_ID": "UNK",
    "INSTRUMENT_NAME": "UNK",
    "INSTRUMENT_ID": "UNK",
    "RATIONALE_DESC": "UNK",
}
DTM_NOTE = (
    "Pixel values are elevations in meters. Physical value = "
    "DN * SCALING_FACTOR + OFFSET. Pixels equal to MISSING_CONSTANT hold no data."
)


def generic_product_id(stem: str) -> str:
    """A PDS-safe product ID from a file name: upper case, [A-Z0-9_] only."""
    cleaned = re.sub(r"[^A-Z0-9_]+", "_", stem.upper()).strip("_")
    if not cleaned:
        raise PdsgenError(None, f"cannot derive a product ID from {stem!r}; give {param('product_id')}")
    return cleaned[:40]


def check_product_id(product_id: str) -> str:
    if not PRODUCT_ID_PATTERN.fullmatch(product_id):
        raise PdsgenError(
            None, f"product ID {product_id!r} must be 1-40 letters, digits, '_', '-' or '.'"
        )
    return product_id


def _from_file_name(request: ProductIdRequest) -> str:
    return generic_product_id(request.stem)


MISSION = Mission(
    name="generic",
    dtm_keywords=KEYWORDS,
    dtm_note=DTM_NOTE,
    credit="",
    ortho_keywords=KEYWORDS,
    ortho_description="Orthorectified image",
    dtm_product_id=_from_file_name,
    ortho_product_id=_from_file_name,
)
