"""`pdsgen ortho`: an orthoimage to a lossless JPEG 2000 with a detached PDS3 label."""

from __future__ import annotations

import click

from ..products.hrsc import HrscImageProduct
from ..products.imars import ImarsProduct
from ..products.ortho import OrthoProduct, write_ortho
from ..profiles import profile_names
from ._profile_options import label_fidelity_options, profile_options, refuse_unused_options

_COMMON = {"input_path", "outdir", "product_id", "value_range", "params_file", "product_version", "overwrite"}
USED_BY_PROFILE = {
    "generic": _COMMON | {"allow_deviations", "bits", "observation_id", "source_dtm_id", "sequence", "gmljp2"},
    "hirise": _COMMON | {"allow_deviations", "bits", "observation_id", "source_dtm_id", "sequence", "gmljp2"},
    "hrsc": _COMMON | {"allow_deviations", "source_labels", "offset_convention", "bits", "source_ids", "reproject"},
    "imars": _COMMON | {"bits", "source_ids"},
}


@click.command(short_help="Make a PDS3 orthoimage (.JP2 + detached .LBL).")
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False))
@click.option("-o", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@click.option("--profile", type=click.Choice(profile_names()),
              default="generic", show_default=True, help="Mission profile: names and keywords.")
@click.option("--product-id", help="Product ID (default: built by the profile).")
@click.option("--bits", type=click.Choice(["8", "10", "16"]),
              help="DN bits (default: 8 for byte input, 16 for wider; floats 10 (hirise) or 16).")
@click.option("--range", "value_range", type=float, nargs=2, metavar="MIN MAX",
              help="Input values mapped onto the valid DNs; outside become saturation DNs "
                   "(default: integer DNs kept if they fit, else the data's min and max).")
@click.option("--observation-id", help="Source observation, e.g. ESP_042252_1930 (hirise product ID).")
@click.option("--source-dtm-id", help="Product ID of the DTM the image was orthorectified on.")
@click.option("--sequence", type=int, default=1, show_default=True,
              help="Sequence number NN of HiRISE ortho IDs.")
@click.option("--params", "params_file", type=click.Path(dir_okay=False),
              help="PVL or TOML file of producer/data-set keywords (see schemas/params.toml).")
@click.option("--version", "product_version", default="1.0", show_default=True, help="PRODUCT_VERSION_ID.")
@click.option("--gmljp2", is_flag=True, help="Also write a GMLJP2 box (the GeoJP2 box is always written).")
@click.option("--source-product-id", "source_ids", multiple=True,
              help="hrsc/imars: source product (e.g. H1234_0000_ND3) giving orbit and sequence.")
@click.option("--reproject", is_flag=True, help="hrsc: warp the input into the HRSC projection and sphere.")
@label_fidelity_options
@click.option("--overwrite", is_flag=True, help="Replace an existing product.")
@click.pass_context
def ortho(ctx, input_path, outdir, profile, product_id, bits, value_range, observation_id, source_dtm_id,
          sequence, params_file, product_version, gmljp2, source_ids, reproject, source_labels,
          offset_convention, allow_deviations, overwrite) -> None:
    """Convert the 1-band (RED) or 3-band (IRB) orthoimage INPUT (any GDAL format,
    projected CRS as for DTMs) into OUTDIR/<PRODUCT_ID>.JP2 and .LBL; for --profile
    hrsc the 8-bit nadir image hOOOO_NNNN_nd4.img (attached label, DN 0 = no data);
    for --profile imars hOOOO_NNNN_nd4_ucl.tif with its .pvl and footprint."""
    used = USED_BY_PROFILE.get(profile, USED_BY_PROFILE["generic"])
    refuse_unused_options(ctx, profile, used)
    given = {
        "product_id": product_id, "bits": int(bits) if bits else None, "value_range": value_range or None,
        "observation_id": observation_id, "source_dtm_id": source_dtm_id, "sequence": sequence,
        "params": params_file, "gmljp2": gmljp2, "version": product_version, "overwrite": overwrite,
        "source_product_ids": source_ids, "reproject_input": reproject,
    }
    options = profile_options(given, used)
    product = write_ortho(input_path, outdir, profile=profile, **options)
    for warning in getattr(product, "warnings", ()):
        click.echo(f"warning: {warning}", err=True)
    click.echo(_summary(product))


def _summary(product: object) -> str:
    """The one line `pdsgen ortho` prints, in the form of the product the profile made."""
    if isinstance(product, HrscImageProduct):
        return f"{product.path}  DN {product.valid_minimum} .. {product.valid_maximum}"
    if isinstance(product, ImarsProduct):
        return f"{product.tiff_path}  {product.pvl_path.name}  {product.footprint_path.name}"
    assert isinstance(product, OrthoProduct)
    return (f"{product.jp2_path}  {product.geometry.lines} x {product.geometry.samples} x {product.bands}  "
            f"{product.bits}-bit DN * {product.scaling_factor:.6g} + {product.offset:.6g}")
