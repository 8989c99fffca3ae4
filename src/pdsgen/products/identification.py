"""The identification keywords every standard PDS3 label starts with."""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from .. import __version__
from ..errors import param
from ..geo.geometry import MapGeometry
from ..label.grammar import IDENTIFIER_RE
from ..label.values import Symbol
from ..missions import ProductIdRequest
from ..missions.generic import check_product_id, generic_product_id
from ..params import IDENTIFICATION_KEYWORDS, ParamValue

if TYPE_CHECKING:
    from .result import ProductResult

log = logging.getLogger(__name__)
ProductResultT = TypeVar("ProductResultT", bound="ProductResult")


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


def unstated_warning(label: Path, text: str, profile: str) -> str | None:
    """One warning for a product made without identification: its PDS3 label (`text`, of the file
    `label`) says "UNK" for every identification keyword its profile does not state (the generic
    profile: all of them), so the params file was not given. None when the params file or the
    profile states any (a delivery's DLV-007 still reports each one left UNK)."""
    from ..label.parser import parse_label

    root = parse_label(text).root
    values = {k: root.get(k) for k in IDENTIFICATION_KEYWORDS}
    unstated = [k for k, stmt in values.items()
                if stmt is not None and str(stmt.value.py).strip().upper() in ("UNK", "N/A")]
    if not unstated or len(unstated) < sum(stmt is not None for stmt in values.values()):
        return None
    return (f"{label}: {', '.join(unstated)} {'is' if len(unstated) == 1 else 'are'} \"UNK\" (not stated); write "
            f"them in a params file (pdsgen params {param('template', profile)} prints one to fill in) and make "
            f"the product again with it as {param('params')}")


def with_unstated_warning(result: ProductResultT, profile: str) -> ProductResultT:
    """`result` with `unstated_warning` added to its warnings: of the label text the writer kept
    (an attached label's), else of its detached .LBL file; nothing for a product without either."""
    text = getattr(result, "label_text", None)
    detached = next((path for path in result.files if path.suffix.upper() == ".LBL"), None)
    label = detached or result.files[0]
    if not isinstance(text, str):
        if detached is None:
            return result
        text = detached.read_text(encoding="ascii", errors="replace")
    if text.lstrip().startswith("<"):  # a PDS4-only product: its XML label is no PDS3 one
        return result
    warning = unstated_warning(label, text, profile)
    if warning is None or not dataclasses.is_dataclass(result):
        return result
    return dataclasses.replace(result, warnings=(*result.warnings, warning))
