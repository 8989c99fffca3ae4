"""Which archive's conventions a label follows, for the rules whose verdict depends on it.

HRSC (Mars Express) products are recognised by any one of: INSTRUMENT_ID = HRSC, a
`MEX:DTM` group, a DATA_SET_ID starting `MEX-M-HRSC`, or a file name of the HRSC
level-4 form `hOOOO_NNNN_xx4` (pds3-products.md section 7). Their archive defines its
own conventions (DSMAP.CAT): the older one-pixel-apart offset formula, the 3396.0 km
sphere, sinusoidal/polar stereographic by latitude.
"""

from __future__ import annotations

from ..missions import LabelFacts, detect_mission, hirise
from ..missions.hrsc import NAME_RE as HRSC_NAME
from ..missions.hrsc import name_kind as hrsc_kind
from .context import FileContext

__all__ = ["HRSC_NAME", "hrsc_kind", "is_hrsc"]


def hrsc_orbit(name: str) -> str | None:
    """`h1234_0000` of an HRSC product id or file name (its orbit and sequence), lower case."""
    match = HRSC_NAME.match(name)
    return f"h{int(match.group('orbit')):04d}_{match.group('sequence')}" if match else None


def is_hirise(ctx: FileContext) -> bool:
    """True for a HiRISE product: the instrument or data set says so (the mission's own
    detection), or the PRODUCT_ID is a HiRISE observation or DTM id (missions/hirise.py)."""
    root = ctx.root
    facts = LabelFacts(instrument_id=(root.text("INSTRUMENT_ID") or "").strip(),
                       data_set_id=(root.text("DATA_SET_ID") or "").strip())
    product = (root.text("PRODUCT_ID") or "").strip()
    return hirise.is_hirise(facts) or bool(hirise.PRODUCT_ID_RE.match(product))


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
