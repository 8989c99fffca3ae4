"""`pdsgen dtm`: a DTM raster to a PDS3 .IMG with attached label."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import click

from ..pds4.model import LABEL_DIALECTS
from ..products.dtm import write_dtm
from ..products.result import ProductResult
from ..profiles import profile_names
from ..storage import internal, output_area
from . import COMMANDS
from ._output import Outcome, output_options, product_summary
from ._profile_options import label_fidelity_options, profile_options, refuse_unused_options

_COMMON = {"input_path", "outdir", "product_id", "source_ids", "product_version", "params_file", "overwrite"}
USED_BY_PROFILE = {
    "generic": _COMMON | {"allow_deviations", "byte_order", "label"},
    "hirise": _COMMON | {"allow_deviations", "byte_order", "institution", "label"},
    "hrsc": _COMMON | {"allow_deviations", "source_labels", "offset_convention", "byte_order", "kind",
                       "vertical_datum", "areoid", "precision", "reproject", "label"},
    "imars": _COMMON | {"kind", "vertical_datum", "areoid", "precision"},
    "hrsc-ax": (_COMMON - {"source_ids"}) | {"allow_deviations", "source_labels", "vicar_offsets", "byte_order",
                                             "label"},
}


@click.command(short_help=COMMANDS["dtm"])
@output_options
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False))
@click.option("-o", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@click.option("--profile", type=click.Choice(profile_names()), default="generic", show_default=True,
              help="Mission profile: names and keywords.")
@click.option("--product-id", help="Product ID (default: built by the profile; hrsc: h1234_0000).")
@click.option("--source-product-id", "source_ids", multiple=True,
              help="Source observation/product ID; repeat for each (hirise: two stereo images).")
@click.option("--institution", help="Producing institution letter for HiRISE product IDs.")
@click.option("--version", "product_version", default="1.0", show_default=True,
              help="PRODUCT_VERSION_ID (HiRISE IDs encode it as two digits).")
@click.option("--params", "params_file", type=click.Path(dir_okay=False),
              help="PVL or TOML file of producer/data-set keywords (see schemas/params.toml).")
@click.option("--byte-order", type=click.Choice(["lsb", "msb"]), default=None,
              help="lsb: PC_REAL / LSB_INTEGER; msb: IEEE_REAL / MSB_INTEGER. "
                   "[default: lsb; hrsc: msb]")
@click.option("--kind", type=click.Choice(["dt4", "da4"]), default="dt4", show_default=True,
              help="hrsc/imars: heights above the 3396.0 km sphere (dt4) or the areoid (da4).")
@click.option("--vertical-datum", type=click.Choice(["sphere", "areoid"]), default="sphere",
              show_default=True, help="hrsc: what the input heights are measured from.")
@click.option("--areoid", type=click.Path(dir_okay=False),
              help="hrsc: areoid heights above the 3396.0 km sphere (any GDAL raster), to convert datums.")
@click.option("--precision", type=float, default=1.0, show_default=True,
              help="hrsc/imars: metres per stored integer step (SCALING_FACTOR).")
@click.option("--reproject", is_flag=True,
              help="hrsc: warp the input into the HRSC projection and sphere instead of refusing it.")
@label_fidelity_options
@click.option("--label", type=click.Choice(LABEL_DIALECTS), default="pds3", show_default=True,
              help="pds3 (.IMG, attached label), pds4 (.img + .xml) or both (.IMG + a PDS4 .xml "
                   "describing it); hrsc: pds3 or both.")
@click.option("--overwrite", is_flag=True, help="Replace an existing product.")
@click.pass_context
def dtm(ctx, input_path, outdir, profile, product_id, source_ids, institution, product_version,
        params_file, byte_order, kind, vertical_datum, areoid, precision, reproject, source_labels,
        offset_convention, vicar_offsets, allow_deviations, label, overwrite) -> Outcome:
    """Convert the single-band elevation raster INPUT (any GDAL format, projected
    CRS: equirectangular, polar stereographic or sinusoidal) into a PDS3 DTM in OUTDIR:
    <PRODUCT_ID>.IMG (float32), or with --label pds4 a PDS4 one (<PRODUCT_ID>.img + .xml);
    for --profile hrsc hOOOO_NNNN_dt4.img / _da4.img
    (16-bit integers with MEX:DTM scaling); for --profile imars the iMars form:
    hOOOO_NNNN_da4_ucl.tif (int16 GeoTIFF), its .pvl metadata and hOOOO_NNNN.geojson;
    for --profile hrsc-ax the HRSC-AX tile's VICAR .dsm as HRSCAX_<tile>_DEM.IMG (float32
    ellipsoid heights, transverse Mercator)."""
    refuse_unused_options(ctx, profile, USED_BY_PROFILE.get(profile, USED_BY_PROFILE["generic"]))
    with output_area(outdir, overwrite) as area:  # an s3:// OUTDIR: staged here, uploaded when complete
        product = write_dtm(internal(input_path), area.directory, profile=profile, **library_options(ctx.params))
        lines, summary = area.shown([_summary(product)]), area.shown(product_summary("dtm", product))
    return Outcome(lines, summary, product.warnings)


def library_options(params: Mapping[str, Any]) -> dict[str, object]:
    """write_dtm's keywords from the command's parsed parameters: those the profile uses.

    `pdsgen batch` calls it too, so a manifest's job and the command make the same call.
    """
    given = {
        "product_id": params["product_id"], "source_product_ids": tuple(params["source_ids"]),
        "params": params["params_file"], "version": params["product_version"], "overwrite": params["overwrite"],
        "byte_order": params["byte_order"], "institution": params["institution"], "kind": params["kind"],
        "vertical_datum": params["vertical_datum"], "areoid": params["areoid"] and internal(params["areoid"]),
        "precision": params["precision"],
        "reproject_input": params["reproject"], "allow_dictionary_deviations": params["allow_deviations"] or None,
        "source_labels": tuple(params["source_labels"]), "offset_convention": params["offset_convention"],
        "vicar_offsets": params["vicar_offsets"],
        "label": params["label"],
    }
    return profile_options(given, USED_BY_PROFILE.get(params["profile"], USED_BY_PROFILE["generic"]))


def _summary(product: ProductResult) -> str:
    """The one line `pdsgen dtm` prints: the product's own, in the form its profile made."""
    return product.summary_line
