"""The identification keywords every standard PDS3 label starts with."""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping, Sequence

from .. import __version__
from ..geo.geometry import MapGeometry
from ..label.grammar import IDENTIFIER_RE
from ..label.values import Symbol
from ..missions import ProductIdRequest
from ..missions.generic import check_product_id, generic_product_id
from ..params import ParamValue

log = logging.getLogger(__name__)


def identification_keywords(
    defaults: Mapping[str, str], keywords: Mapping[str, ParamValue], geometry: MapGeometry, version: str
) -> dict[str, ParamValue]:
    ident: dict[str, ParamValue] = {
        **defaults,
        "TARGET_NAME": geometry.target_name or defaults.get("TARGET_NAME", "MARS"),
        "PRODUCT_VERSION_ID": version,
        "SOFTWARE_NAME": f"pdsgen {__version__}",
    }
    ident.update({k: v for k, v in keywords.items() if k != "SOURCE_PRODUCT_ID"})
    return ident


def choose_product_id(
    explicit: str | None, naming_rule: Callable[[ProductIdRequest], str] | None, request: ProductIdRequest
) -> str:
    """The product ID given (checked), else the mission's naming rule's, else one from the file name."""
    if explicit:
        chosen, why = check_product_id(explicit), "given"
    elif naming_rule is not None:
        chosen, why = naming_rule(request), "the mission's naming rule"
    else:
        chosen, why = generic_product_id(request.stem), "the input file name"
    log.info("product ID %s (%s)", chosen, why)
    return chosen


def source_id_values(sources: Sequence[str]) -> list[Symbol | str] | str:
    """SOURCE_PRODUCT_ID as written: bare where it is a PDS identifier, else quoted; N/A if none."""
    if not sources:
        return "N/A"
    return [Symbol(s) if IDENTIFIER_RE.fullmatch(s) else s for s in sources]
