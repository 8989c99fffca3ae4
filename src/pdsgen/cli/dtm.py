"""`pdsgen dtm`: a DTM raster to a PDS3 .IMG with attached label."""

from __future__ import annotations

import click

from ..products.dtm import DtmProduct, write_dtm
from ..products.hrsc import HrscDtmProduct
from ..products.imars import ImarsProduct
from ..profiles import profile_names
from ._profile_options import label_fidelity_options, profile_options, refuse_unused_options

_COMMON = {"input_path", "outdir", "product_id", "source_ids", "product_version", "params_file", "overwrite"}
USED_BY_PROFILE = {
    "generic": _COMMON | {"allow_deviations", "byte_order"},
    "hirise": _COMMON | {"allow_deviations", "byte_order", "institution"},
    "hrsc": _COMMON | {"allow_deviations", "source_labels", "offset_convention", "byte_order", "kind",
                       "vertical_datum", "areoid", "precision", "reproject"},
    "imars": _COMMON | {"kind", "vertical_datum", "areoid", "precision"},
}


@click.command(short_help="Make a PDS3 DTM (.IMG with attached label).")
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
@click.option("--overwrite", is_flag=True, help="Replace an existing product.")
@click.pass_context
def dtm(ctx, input_path, outdir, profile, product_id, source_ids, institution, product_version,
        params_file, byte_order, kind, vertical_datum, areoid, precision, reproject, source_labels,
        offset_convention, allow_deviations, overwrite) -> None:
    """Convert the single-band elevation raster INPUT (any GDAL format, projected
    CRS: equirectangular, polar stereographic or sinusoidal) into a PDS3 DTM in OUTDIR:
    <PRODUCT_ID>.IMG (float32); for --profile hrsc hOOOO_NNNN_dt4.img / _da4.img
    (16-bit integers with MEX:DTM scaling); for --profile imars the iMars form:
    hOOOO_NNNN_da4_ucl.tif (int16 GeoTIFF), its .pvl metadata and hOOOO_NNNN.geojson."""
    refuse_unused_options(ctx, profile, USED_BY_PROFILE.get(profile, USED_BY_PROFILE["generic"]))
    given = {
        "product_id": product_id, "source_product_ids": source_ids, "params": params_file,
        "version": product_version, "overwrite": overwrite, "byte_order": byte_order, "institution": institution,
        "kind": kind, "vertical_datum": vertical_datum, "areoid": areoid, "precision": precision,
        "reproject_input": reproject, "allow_dictionary_deviations": allow_deviations or None,
        "source_labels": source_labels, "offset_convention": offset_convention,
    }
    used = USED_BY_PROFILE.get(profile, USED_BY_PROFILE["generic"])
    options = profile_options(given, used)
    product = write_dtm(input_path, outdir, profile=profile, **options)
    for warning in getattr(product, "warnings", ()):
        click.echo(f"warning: {warning}", err=True)
    click.echo(_summary(product))


def _summary(product: object) -> str:
    """The one line `pdsgen dtm` prints, in the form of the product the profile made."""
    if isinstance(product, ImarsProduct):
        return f"{product.tiff_path}  {product.pvl_path.name}  {product.footprint_path.name}"
    if isinstance(product, HrscDtmProduct):
        return (f"{product.path}  {product.geometry.lines} x {product.geometry.samples}  "
                f"DN {product.valid_minimum} .. {product.valid_maximum} "
                f"(x {product.encoding.scaling_factor:g} + {product.encoding.offset:g} m)")
    assert isinstance(product, DtmProduct)
    return (f"{product.path}  {product.geometry.lines} x {product.geometry.samples}  "
            f"valid {product.valid_minimum} .. {product.valid_maximum} m")
