"""`pdsgen mosaic`: strips or tiles of one kind into one product, placed as gdal_merge.py places them."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import click

from ..mosaic import KINDS, ORDERS, RESAMPLING_METHODS, write_mosaic
from ..pds4.model import LABEL_DIALECTS
from ..products.result import ProductResult
from ..profiles import profile_names
from ..storage import local_inputs, output_area
from . import COMMANDS
from ._output import Outcome, product_summary
from ._output import output_options as _output_options
from ._profile_options import (
    allow_deviations_option,
    profile_options,
    refuse_unused_options,
    vicar_offsets_option,
)

_COMMON = {"inputs", "outdir", "profile", "product_id", "kind", "order", "resampling", "nodata", "params_file",
           "product_version", "overwrite"}
USED_BY_PROFILE = {
    "generic": _COMMON | {"label", "byte_order", "allow_deviations"},
    "hirise": _COMMON | {"label", "byte_order", "allow_deviations"},
    "hrsc": _COMMON | {"label", "precision", "reproject", "allow_deviations"},
    "imars": _COMMON | {"precision"},
    "hrsc-ax": _COMMON | {"label", "byte_order", "source_labels", "vicar_offsets", "allow_deviations"},
}


@click.command(short_help=COMMANDS["mosaic"])
@_output_options
@click.argument("inputs", metavar="INPUT...", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option("-o", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@click.option("--profile", type=click.Choice(profile_names()), default="generic", show_default=True,
              help="Mission profile: the product form, names and keywords.")
@click.option("--product-id", required=True,
              help="Product ID of the mosaic (imars: <ID>_dtm.tif / <ID>_ori.tif; hrsc: hOOOO_NNNN).")
@click.option("--kind", type=click.Choice(KINDS), default=None,
              help="Heights or images [default: decided from each input as `pdsgen extras` decides it].")
@click.option("--order", type=click.Choice(ORDERS), default="given", show_default=True,
              help="given: later inputs lie on top (as gdal_merge.py); reverse: earlier ones do.")
@click.option("--resampling", type=click.Choice(RESAMPLING_METHODS), default=None,
              help="Resample inputs whose grid differs from the first's with this GDAL method "
                   "(refused otherwise); the label says so.")
@click.option("--nodata", type=float, default=None,
              help="No-data value of all inputs and the mosaic, as gdal_merge.py -n [default: each input's "
                   "own in it, the first input's for the mosaic; ortho 0].")
@click.option("--params", "params_file", type=click.Path(dir_okay=False),
              help="PVL or TOML file of producer/data-set keywords (see schemas/params.toml).")
@click.option("--version", "product_version", default="1.0", show_default=True, help="PRODUCT_VERSION_ID.")
@click.option("--byte-order", type=click.Choice(["lsb", "msb"]), default=None,
              help="DTM sample byte order [default: lsb].")
@click.option("--precision", type=float, default=None,
              help="hrsc/imars DTM: metres per stored integer step (SCALING_FACTOR) [default: 1].")
@click.option("--reproject", is_flag=True,
              help="hrsc: warp the mosaic into the HRSC projection and sphere instead of refusing it.")
@allow_deviations_option
@click.option("--source-label", "source_labels", multiple=True, type=click.Path(dir_okay=False),
              help="hrsc-ax: XML image label of a tile's MAP/DTM keywords; one per tile, in the tiles' order.")
@vicar_offsets_option
@click.option("--label", type=click.Choice(LABEL_DIALECTS), default="pds3", show_default=True,
              help="pds3, pds4 or both (not imars).")
@click.option("--overwrite", is_flag=True, help="Replace an existing product.")
@click.pass_context
def mosaic(ctx, inputs, outdir, profile, product_id, kind, order, resampling, nodata, params_file,
           product_version, byte_order, precision, reproject, allow_deviations, source_labels, vicar_offsets,
           label, overwrite) -> Outcome:
    """Mosaic the rasters INPUT... (DTMs or orthoimages, any GDAL format, one CRS, one grid)
    into one product in OUTDIR: later inputs lie on top, no-data never covers data, the grid
    is the union of the inputs' - pixel for pixel what `gdal_merge.py -n ND -a_nodata ND
    -init ND` makes. generic/hirise/hrsc: the PDS3 .IMG DTM or JP2 orthoimage (PDS4 with
    --label) naming its sources; imars: <ID>_dtm.tif or <ID>_ori.tif with its _ucl.pvl and a
    footprint (<ID>.geojson + Shapefile) of every source; hrsc-ax: VICAR tiles (.dsm or .pan)
    as one area product."""
    used = USED_BY_PROFILE.get(profile, USED_BY_PROFILE["generic"])
    refuse_unused_options(ctx, profile, used)
    options: dict[str, Any] = library_options(ctx.params)
    # Objects in a bucket are fetched as extras fetches them: an input's label (a PDS3 .IMG, an
    # iMars strip's tags) is read by Python to name and classify it, and a mosaic reads every
    # pixel of every input anyway. An s3:// OUTDIR: staged here, uploaded when complete.
    with local_inputs(inputs) as sources, output_area(outdir, overwrite) as area:
        product = write_mosaic(sources.paths, area.directory, **options)
        lines, summary = area.shown([sources.shown(_summary(product))]), area.shown(product_summary("mosaic", product))
    return Outcome(lines, summary, product.warnings)


def library_options(params: Mapping[str, Any]) -> dict[str, Any]:
    """write_mosaic's keywords from the command's parsed parameters: those the profile uses.

    `pdsgen batch` calls it too, so a manifest's [[mosaic]] job and the command make the same call."""
    profile = params["profile"]
    kind = params["kind"]
    given: dict[str, object] = {
        "profile": profile, "product_id": params["product_id"], "kind": kind, "order": params["order"],
        "resampling": params["resampling"], "nodata": params["nodata"], "params": params["params_file"],
        "version": params["product_version"], "overwrite": params["overwrite"], "label": params["label"],
        "byte_order": params["byte_order"], "precision": params["precision"],
        "reproject_input": params["reproject"], "allow_dictionary_deviations": params["allow_deviations"] or None,
        "source_labels": tuple(params["source_labels"]), "vicar_offsets": params["vicar_offsets"],
    }
    options = profile_options(given, USED_BY_PROFILE.get(profile, USED_BY_PROFILE["generic"]))
    return {name: value for name, value in options.items()  # unset: the writer's own default
            if not (name in ("byte_order", "precision") and value is None)}


def _summary(product: ProductResult) -> str:
    """The one line `pdsgen mosaic` prints: the directory, every file written, the mosaic's size."""
    files = "  ".join(path.name for path in product.files)
    return f"{product.files[0].parent}/  {files}  {product.geometry.lines} x {product.geometry.samples}"
