"""The mosaic as a GDAL virtual raster (VRT) that the standard product writers read.

Each placement is a ComplexSource whose NODATA pixels are transparent, listed bottom
first, so a later input lies on top and a no-data pixel never covers data; where no
input lies the band's own no-data value shows: gdal_merge.py's `-n ND -init ND`. The
writers read the VRT in row strips; GDAL opens a source only when a strip overlaps it
(SourceProperties let it defer the open) and reads only the overlapping part, so memory
is bounded by a strip of the output, not by the number or size of the inputs.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np
from rasterio.dtypes import _gdal_typename

from ..formats.raster import temporary_vrt
from .plan import MosaicPlan, Placement, Window2


def vrt_text(plan: MosaicPlan, nodata: float, dtype: str | None = None, own_nodata: bool = False) -> str:
    """The VRT XML of `plan` with `nodata` as the value that is both transparent and the fill,
    samples of `dtype` (default: the first input's, as gdal_merge.py's output). `own_nodata`:
    each input's own no-data value is transparent in it (inputs without one: `nodata`), so
    inputs of different producers never lay their no-data over another's data."""
    t = plan.transform
    data_type = _gdal_typename(np.dtype(dtype or plan.dtype).name)
    # Heights stored as DNs with a scale or offset are presented as the heights the DTM writers
    # expect (float32), each source's no-data DN still transparent (NODATA applies before scaling);
    # an image's DNs stay DNs, its scale and offset carried as the band's.
    scaled = (plan.scale, plan.offset) != (1.0, 0.0)
    heights = scaled and plan.kind == "dtm"
    scaling = f"<ScaleOffset>{plan.offset!r}</ScaleOffset><ScaleRatio>{plan.scale!r}</ScaleRatio>" if heights else ""
    band_scaling = f"<Offset>{plan.offset!r}</Offset><Scale>{plan.scale!r}</Scale>" if scaled and not heights else ""
    bands = []
    for band in range(1, plan.band_count + 1):
        sources = "".join(_source(p, band, _transparent(p, nodata, own_nodata), plan.resampling, scaling)
                          for p in plan.placements)
        bands.append(f'<VRTRasterBand dataType="{"Float32" if heights else data_type}" band="{band}">'
                     f"<NoDataValue>{_number(nodata)}</NoDataValue>{band_scaling}{sources}</VRTRasterBand>")
    return (f'<VRTDataset rasterXSize="{plan.width}" rasterYSize="{plan.height}">'
            f"<SRS>{escape(plan.crs.to_wkt())}</SRS>"
            f"<GeoTransform>{t.c!r}, {t.a!r}, 0.0, {t.f!r}, 0.0, {t.e!r}</GeoTransform>"
            + "".join(bands) + "</VRTDataset>")


def _transparent(placement: Placement, nodata: float, own_nodata: bool) -> float:
    own = placement.source.nodata
    return float(own) if own_nodata and own is not None else nodata


def _source(placement: Placement, band: int, nodata: float, resampling: str | None, scaling: str) -> str:
    source = placement.source
    props = (f'<SourceProperties RasterXSize="{source.width}" RasterYSize="{source.height}" '
             f'DataType="{_gdal_typename(np.dtype(source.dtype).name)}"/>')
    method = f' resampling="{resampling}"' if resampling else ""
    return (f"<ComplexSource{method}>"
            f'<SourceFilename relativeToVRT="0">{escape(str(source.path.resolve()))}</SourceFilename>'
            f"<SourceBand>{band}</SourceBand>{props}"
            f"<SrcRect {_rect(placement.source_window)}/><DstRect {_rect(placement.target_window)}/>"
            f"<NODATA>{_number(nodata)}</NODATA>{scaling}</ComplexSource>")


def _rect(window: Window2) -> str:
    return (f'xOff="{_number(window.x)}" yOff="{_number(window.y)}" '
            f'xSize="{_number(window.width)}" ySize="{_number(window.height)}"')


def _number(value: float) -> str:
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    return str(int(value)) if float(value).is_integer() else repr(float(value))


@contextmanager
def mosaic_vrt(plan: MosaicPlan, nodata: float, name: str, dtype: str | None = None,
               own_nodata: bool = False) -> Iterator[Path]:
    """The plan's VRT as `name`.vrt in a private temporary directory, removed afterwards; a
    problem a writer reports about it is reported naming the inputs (formats.raster.temporary_vrt)."""
    names = ", ".join(i.name for i in plan.inputs)  # the user's files (an HRSC-AX tile, not its VRT)
    text = vrt_text(plan, nodata, dtype, own_nodata)
    with temporary_vrt(text, name, f"the mosaic of {names}", prefix="pdsgen-mosaic-") as path:
        yield path
