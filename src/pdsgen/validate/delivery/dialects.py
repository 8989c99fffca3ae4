"""DLV-022/023/024: a delivery that is a PDS3 volume and a PDS4 bundle holds one product set,
each product told alike in both dialects."""

from __future__ import annotations

from pathlib import Path

from ...label.mapping import utc_datetime
from .model import DeliveryModel, Pds3Record, Pds4Record
from .parts import Found


def check_both_dialects(model: DeliveryModel, found: list[Found]) -> None:
    """A delivery that is a PDS3 volume and a PDS4 bundle holds one product set, each product
    told alike in both: DLV-024 a product of one dialect only; DLV-022 PDS3 START_TIME/STOP_TIME
    against PDS4 Time_Coordinates; DLV-023 the PDS3 map grid against cart: (the ground
    position of the upper-left pixel corner, to half a pixel). The model joins a PDS3 product
    and a PDS4 label when the label describes a file of the PDS3 product's name (X.IMG, X.JP2)."""
    for product in model.products:
        if product.label is None:
            if product.pds4 is not None:
                found.append(Found("DLV-024", product.pds4.path, "in the PDS4 bundle, but the PDS3 volume has no "
                                                                 "label of this product"))
        elif product.pds4 is None:
            found.append(Found("DLV-024", product.label, "in the PDS3 volume, but no PDS4 label of the bundle "
                                                         "describes this product"))
        elif product.pds3 is not None:
            _compare_times(product.label, product.pds3, product.pds4, found)
            _compare_grids(product.label, product.pds3, product.pds4, found)


def _compare_times(product: Path, pds3: Pds3Record, pds4: Pds4Record, found: list[Found]) -> None:
    for keyword, element, written in (("START_TIME", "start_date_time", pds4.times[0]),
                                      ("STOP_TIME", "stop_date_time", pds4.times[1])):
        text, line = pds3.time(keyword)
        mine, theirs = utc_datetime(text), utc_datetime(written)
        if mine is not None and theirs is not None and abs((mine - theirs).total_seconds()) > 1.0:
            found.append(Found("DLV-022", pds4.path, f"{element} {(written or '').strip()} differs from {keyword} "
                                                      f"{text} of the PDS3 label {product.name}"
                                                      + (f" (line {line})" if line else ""), None, element))


def _compare_grids(product: Path, pds3: Pds3Record, pds4: Pds4Record, found: list[Found]) -> None:
    grid = pds3.grid
    if grid is None or pds4.corner is None:
        return
    scale, samples, lines = grid.scale, grid.sample_offset, grid.line_offset
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

