"""The identification keywords every standard PDS3 label starts with."""

from __future__ import annotations

from collections.abc import Callable, Mapping

from .. import __version__
from ..geo.geometry import MapGeometry
from ..missions import ProductIdRequest
from ..missions.generic import check_product_id, generic_product_id
from .params import ParamValue


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
        return check_product_id(explicit)
    if naming_rule is not None:
        return naming_rule(request)
    return generic_product_id(request.stem)
