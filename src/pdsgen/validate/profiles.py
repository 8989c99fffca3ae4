"""Which archive's conventions a label follows, for the rules whose verdict depends on it.

HRSC (Mars Express) products are recognised by any one of: INSTRUMENT_ID = HRSC, a
`MEX:DTM` group, a DATA_SET_ID starting `MEX-M-HRSC`, or a file name of the HRSC
level-4 form `hOOOO_NNNN_xx4` (pds3-products.md section 7). Their archive defines its
own conventions (DSMAP.CAT): the older one-pixel-apart offset formula, the 3396.0 km
sphere, sinusoidal/polar stereographic by latitude.
"""

from __future__ import annotations

import re

from .context import FileContext

HRSC_NAME = re.compile(r"^h(?P<orbit>\d{4,5})_(?P<sequence>\d{4})_(?P<kind>[a-z]{2}\d)", re.IGNORECASE)


def hrsc_kind(name: str) -> str | None:
    """The product kind of an HRSC file name (`dt4`, `da4`, `nd4`, `ir4` ...), lower case."""
    match = HRSC_NAME.match(name)
    return match.group("kind").lower() if match else None


def hrsc_orbit(name: str) -> str | None:
    """`h1234_0000` of an HRSC product id or file name (its orbit and sequence), lower case."""
    match = HRSC_NAME.match(name)
    return f"h{int(match.group('orbit')):04d}_{match.group('sequence')}" if match else None


# HiRISE observation and product ids (pds3-products.md section 3): PSP_/ESP_ observations,
# DTEEC/DTEPC... DTMs; the RDR, DTM and ortho files are named after PRODUCT_ID.
HIRISE_ID = re.compile(r"^(?:(?:PSP|ESP|AEB|TRA|INS|CAL)_\d{6}_\d{4}|DT[EP][A-Z]{2}_\d{6}_\d{4}_\d{6}_\d{4})",
                       re.IGNORECASE)


def is_hirise(ctx: FileContext) -> bool:
    """True for a HiRISE product (by instrument, data set or product id)."""
    root = ctx.root
    instrument = (root.text("INSTRUMENT_ID") or "").strip().upper()
    data_set = (root.text("DATA_SET_ID") or "").strip().upper()
    product = (root.text("PRODUCT_ID") or "").strip()
    return instrument == "HIRISE" or "-HIRISE-" in data_set or bool(HIRISE_ID.match(product))


def is_hrsc(ctx: FileContext) -> bool:
    """True when the label (or its file name) says it is an HRSC product."""
    cached = ctx.__dict__.get("_is_hrsc")
    if cached is not None:
        return cached
    root = ctx.root
    instrument = (root.text("INSTRUMENT_ID") or "").strip().upper()
    data_set = (root.text("DATA_SET_ID") or "").strip().upper()
    kind = hrsc_kind(ctx.path.name)
    found = (
        instrument == "HRSC"
        or data_set.startswith("MEX-M-HRSC")
        or any(True for _ in root.find("MEX:DTM"))
        or (kind is not None and kind.endswith("4"))
    )
    ctx.__dict__["_is_hrsc"] = found
    return found
