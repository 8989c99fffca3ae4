"""The iMars mosaic form: `<ID>_dtm.tif` / `<ID>_ori.tif` with the PVL naming the strips, and a
footprint polygon per source strip.

The iMars mission names this writer (`Mission.mosaic_writer`), so `write_mosaic` has no iMars
case of its own.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from ..missions.imars import MISSION
from ..products.dispatch import ProductStatement, call_mission_writer
from ..products.options import ProductOptions
from ..products.result import ProductResult
from .plan import MosaicPlan, source_ids


def write_imars_mosaic(plan: MosaicPlan, vrt: Path, outdir: Path, product_id: str, statement: ProductStatement,
                       options: Mapping[str, Any]) -> ProductResult:
    """`<ID>_dtm.tif` / `<ID>_ori.tif` with the PVL naming the strips and how they were put
    together (`statement`), and their footprints."""
    from ..products.imars import ImarsMosaic, write_imars_dtm, write_imars_ori

    if plan.kind == "dtm" and plan.scale != 1.0:  # the strips' own precision unless told otherwise
        options = {"precision": plan.scale, **options}
    mosaic = ImarsMosaic(product_id, _Outlines(plan), _heights_within(plan, vrt))
    writer = functools.partial(write_imars_dtm if plan.kind == "dtm" else write_imars_ori, mosaic=mosaic,
                               statement=statement)
    built = ProductOptions.build(plan.kind, MISSION, {"source_product_ids": source_ids(plan), **options})
    return call_mission_writer(writer, vrt, outdir, built)


def _heights_within(plan: MosaicPlan, vrt: Path) -> tuple[float, float] | None:
    """Bounds of every valid height the mosaic presents, from its sources' sample type and
    common scaling alone (None: not bounded so - floating-point samples, or resampling that may
    overshoot).

    A source's transparent DN never shows; it is its own no-data value or the mosaic's (vrt.py),
    so only a value both are (or the mosaic's, for a source without one) is left out of its
    range. The heights are DN * scale + offset as the VRT presents them, in float32."""
    import numpy as np

    from ..formats.raster import open_raster

    if plan.kind != "dtm" or plan.resampling not in (None, "nearest"):
        return None
    if not all(np.dtype(source.dtype).kind in "iu" for source in plan.inputs):
        return None
    with open_raster(vrt) as mosaic:
        fill = mosaic.nodata
    lows, highs = [], []
    for source in plan.inputs:
        limits = np.iinfo(source.dtype)
        low, high = int(limits.min), int(limits.max)
        hidden = fill if source.nodata is None or source.nodata == fill else None
        low, high = low + (hidden == low), high - (hidden == high)
        lows.append(low)
        highs.append(high)
    ends = np.array([min(lows) * plan.scale + plan.offset, max(highs) * plan.scale + plan.offset], np.float32)
    return float(ends.min()), float(ends.max())


class _Outlines(Sequence[tuple[str, list[dict[str, Any]], dict[str, Any]]]):
    """The sources' footprint features, traced when first asked for: the writer asks after the
    GeoTIFF is written, so their polygons are not held in memory while it is."""

    def __init__(self, plan: MosaicPlan) -> None:
        self._plan = plan
        self._traced: tuple[tuple[str, list[dict[str, Any]], dict[str, Any]], ...] | None = None

    def _features(self) -> tuple[tuple[str, list[dict[str, Any]], dict[str, Any]], ...]:
        if self._traced is None:
            self._traced = tuple(_outlines(self._plan))
        return self._traced

    def __getitem__(self, index):
        return self._features()[index]

    def __len__(self) -> int:
        return len(self._features())


def _outlines(plan: MosaicPlan) -> Iterator[tuple[str, list[dict[str, Any]], dict[str, Any]]]:
    """Each source's valid data outlined (a decimated read of that source alone)."""
    import numpy as np

    from ..formats.footprint import valid_data_outline
    from ..formats.raster import open_raster

    for source in plan.inputs:
        nodata = source.nodata

        def valid(values: np.ndarray, nodata: float | None = nodata) -> np.ndarray:
            finite = np.isfinite(values) if values.dtype.kind == "f" else np.ones(values.shape, bool)
            return finite if nodata is None or math.isnan(nodata) else finite & (values != nodata)

        with open_raster(source.path) as dataset:
            polygons = valid_data_outline(dataset, valid)
        yield source.product_id, polygons, {"file": Path(source.name).name}
