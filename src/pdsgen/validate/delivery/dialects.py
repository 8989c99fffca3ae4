"""DLV-022/023/024: a delivery that is a PDS3 volume and a PDS4 bundle holds one product set,
each product told alike in both dialects."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from ...archive import layout
from ...label.tree import Block
from .bundle import Pds4Record
from .index import pds3_products
from .parts import Found, first, read_pds3

if TYPE_CHECKING:
    from ...label.read import LabelCache


def check_both_dialects(root: Path, labels: list[Pds4Record], found: list[Found],
                         cache: LabelCache | None) -> None:
    """A delivery that is a PDS3 volume and a PDS4 bundle holds one product set, each product
    told alike in both: DLV-024 a product of one dialect only; DLV-022 PDS3 START_TIME/STOP_TIME
    against PDS4 Time_Coordinates; DLV-023 the PDS3 map grid against cart: (the ground
    position of the upper-left pixel corner, to half a pixel). A PDS3 product and a PDS4 label
    are one product when the label describes a file of the PDS3 product's name (X.IMG, X.JP2)."""
    observational: dict[tuple[str, str], Pds4Record] = {}
    data = root / layout.DATA_DIR
    for label in labels:  # the data products: those of DATA/, where the volume's are (_pds3_products)
        if label.product_class == "Product_Observational" and data in label.path.parents:
            for path in label.described:
                observational.setdefault(_product_key(Path(path)), label)
    paired: set[int] = set()
    for product in pds3_products(root):
        pds4 = observational.get(_product_key(product))
        if pds4 is None:
            found.append(Found("DLV-024", product, "in the PDS3 volume, but no PDS4 label of the bundle describes "
                                                    "this product"))
            continue
        paired.add(id(pds4))
        pds3 = read_pds3(product, cache)  # the run's cache: each label parsed once
        if pds3 is not None:
            _compare_times(product, pds3, pds4, found)
            _compare_grids(product, pds3, pds4, found)
    for label in {id(label): label for label in observational.values()}.values():
        if id(label) not in paired:
            found.append(Found("DLV-024", label.path, "in the PDS4 bundle, but the PDS3 volume has no label of this "
                                                       "product"))


def _product_key(path: Path) -> tuple[str, str]:
    return os.path.normpath(path.parent), path.name.split(".", 1)[0].upper()


def _compare_times(product: Path, pds3: Block, pds4: Pds4Record, found: list[Found]) -> None:
    from ..families.identity_rules import parse_time

    for keyword, element, written in (("START_TIME", "start_date_time", pds4.times[0]),
                                      ("STOP_TIME", "stop_date_time", pds4.times[1])):
        text, line = first(pds3, keyword)
        mine, theirs = parse_time(text), parse_time(written)
        if mine is not None and theirs is not None and abs((mine - theirs).total_seconds()) > 1.0:
            found.append(Found("DLV-022", pds4.path, f"{element} {(written or '').strip()} differs from {keyword} "
                                                      f"{text} of the PDS3 label {product.name}"
                                                      + (f" (line {line})" if line else ""), None, element))


def _compare_grids(product: Path, pds3: Block, pds4: Pds4Record, found: list[Found]) -> None:
    projection = next(pds3.find("IMAGE_MAP_PROJECTION"), None)
    if projection is None or pds4.corner is None:
        return
    scale_value = projection.value("MAP_SCALE")
    samples, lines = projection.number("SAMPLE_PROJECTION_OFFSET"), projection.number("LINE_PROJECTION_OFFSET")
    if scale_value is None or not isinstance(samples, (int, float)) or not isinstance(lines, (int, float)):
        return
    try:
        scale = float(str(scale_value.py)) * (1000.0 if "KM" in (scale_value.unit or "").upper() else 1.0)
    except ValueError:
        return
    if abs(pds4.corner[2] - scale) > 1e-6 * scale:
        return  # MAP_SCALE at another radius than the projection's (HRSC's DLR convention): not this check's model
    ulx, uly = -(samples + 0.5) * scale, (lines + 0.5) * scale  # the corner, half a pixel beyond the first centre
    east, north = (pds4.corner[0] - ulx) / scale, (pds4.corner[1] - uly) / scale
    if abs(east) > 0.5 or abs(north) > 0.5:
        x, y, resolution = pds4.corner
        found.append(Found("DLV-023", pds4.path, f"cart: upper-left corner ({x:.3f}, {y:.3f}) m at {resolution:g} "
                                                  f"m/pixel lies {east:+.2f} pixel east, {north:+.2f} pixel north of "
                                                  f"the grid of the PDS3 label {product.name} ({ulx:.3f}, {uly:.3f}) m "
                                                  f"at {scale:g} m/pixel"))

