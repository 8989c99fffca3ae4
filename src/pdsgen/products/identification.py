"""The identification keywords every standard PDS3 label starts with."""

from __future__ import annotations

from collections.abc import Mapping

from .. import __version__
from ..geo.geometry import MapGeometry
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
