"""The options of `pdsgen mosaic`, in --help order (the vocabulary's form: products/options.py)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..missions import PRODUCT_KINDS
from ..missions.imars import METADATA_SUFFIX
from ..products import options as product_options
from ..products.options import ALLOW_DEVIATIONS, OVERWRITE, PARAMS, VICAR_OFFSETS, OptionSpec, label_option
from .plan import ORDERS, RESAMPLING_METHODS

MOSAIC_OPTIONS: tuple[OptionSpec, ...] = (
    OptionSpec("product_id", "product-id", required=True, always=True,
               help="Product ID of the mosaic (imars: <ID>_dtm.tif / <ID>_ori.tif; hrsc: hOOOO_NNNN)."),
    OptionSpec("kind", "kind", choices=PRODUCT_KINDS, default=None, always=True,
               help="Heights or images [default: decided from each input as `pdsgen extras` decides it]."),
    OptionSpec("order", "order", choices=ORDERS, default="given", show_default=True, always=True,
               help="given: later inputs lie on top (as gdal_merge.py); reverse: earlier ones do."),
    OptionSpec("resampling", "resampling", choices=RESAMPLING_METHODS, default=None, always=True,
               help="Resample inputs whose grid differs from the first's with this GDAL method "
                    "(refused otherwise); the label says so."),
    OptionSpec("nodata", "nodata", value_type=float, default=None, always=True,
               help="No-data value of all inputs and the mosaic, as gdal_merge.py -n [default: each input's "
                    "own in it, the first input's for the mosaic; ortho 0]."),
    PARAMS,
    OptionSpec("product_version", "version", keyword="version", default="1.0", show_default=True, always=True,
               help="PRODUCT_VERSION_ID."),
    OptionSpec("byte_order", "byte-order", choices=("lsb", "msb"), default=None, omit_unset=True,
               help="DTM sample byte order [default: lsb]."),
    OptionSpec("precision", "precision", value_type=float, default=None, omit_unset=True,
               help="hrsc/imars DTM: metres per stored integer step (SCALING_FACTOR) [default: 1]."),
    OptionSpec("reproject", "reproject", keyword="reproject_input", is_flag=True,
               help="hrsc: warp the mosaic into the HRSC projection and sphere instead of refusing it."),
    ALLOW_DEVIATIONS,
    OptionSpec("source_labels", "source-label", multiple=True, file=True, convert=tuple,
               help="hrsc-ax: XML image label of a tile's MAP/DTM keywords; one per tile, in the tiles' order."),
    VICAR_OFFSETS,
    label_option("pds3, pds4 or both (not imars)."),
    OVERWRITE,
)

MOSAIC_HELP = f"""Mosaic the rasters INPUT... (DTMs or orthoimages, any GDAL format, one CRS, one grid)
    into one product in OUTDIR: later inputs lie on top, no-data never covers data, the grid
    is the union of the inputs' - pixel for pixel what `gdal_merge.py -n ND -a_nodata ND
    -init ND` makes. generic/hirise/hrsc: the PDS3 .IMG DTM or JP2 orthoimage (PDS4 with
    --label) naming its sources; imars: <ID>_dtm.tif or <ID>_ori.tif with its {METADATA_SUFFIX} and a
    footprint (<ID>.geojson + Shapefile) of every source; hrsc-ax: VICAR tiles (.dsm or .pan)
    as one area product."""


def library_options(params: Mapping[str, Any]) -> dict[str, Any]:
    """write_mosaic's keywords from `pdsgen mosaic`'s parsed parameters (a manifest's [[mosaic]]
    job's too): the profile and the options it uses."""
    return {"profile": params["profile"], **product_options.library_options("mosaic", MOSAIC_OPTIONS, params)}
