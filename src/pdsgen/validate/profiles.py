"""Which archive's conventions a label follows, for the rules whose verdict depends on it.

HRSC (Mars Express) products are recognised by any one of: INSTRUMENT_ID = HRSC, a
`MEX:DTM` group, a DATA_SET_ID starting `MEX-M-HRSC`, or a file name of the HRSC
level-4 form `hOOOO_NNNN_xx4` (pds3-products.md section 7). Their archive defines its
own conventions (DSMAP.CAT): the older one-pixel-apart offset formula, the 3396.0 km
sphere, sinusoidal/polar stereographic by latitude.
"""

from __future__ import annotations

import re

from ..missions import LabelFacts, detect_mission
from ..missions.hrsc import NAME_RE as HRSC_NAME
from ..missions.hrsc import name_kind as hrsc_kind
from .context import FileContext

__all__ = ["HRSC_NAME", "hrsc_kind", "is_hrsc"]


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
    cached = ctx.cache.get("_is_hrsc")
    if cached is not None:
        return cached
    root = ctx.root
    found = detect_mission(LabelFacts(
        instrument_id=root.text("INSTRUMENT_ID") or "",
        data_set_id=root.text("DATA_SET_ID") or "",
        group_names=frozenset({"MEX:DTM"}) if any(True for _ in root.find("MEX:DTM")) else frozenset(),
        file_name=ctx.path.name,
    )) == "hrsc"
    ctx.cache["_is_hrsc"] = found
    return found
