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
