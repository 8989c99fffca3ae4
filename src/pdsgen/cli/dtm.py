"""`pdsgen dtm`: a DTM raster to a PDS3 .IMG with attached label."""

from __future__ import annotations

import click

from ..dtm import write_dtm
from ..profiles import PROFILES


@click.command(short_help="Make a PDS3 DTM (.IMG with attached label).")
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False))
@click.option("-o", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@click.option("--profile", type=click.Choice(sorted(PROFILES)),
              default="generic", show_default=True, help="Mission profile: names and keywords.")
@click.option("--product-id", help="Product ID (default: built by the profile).")
@click.option("--source-product-id", "source_ids", multiple=True,
              help="Source observation/product ID; repeat for each (hirise: two stereo images).")
@click.option("--institution", help="Producing institution letter for HiRISE product IDs.")
@click.option("--version", "product_version", default="1.0", show_default=True,
              help="PRODUCT_VERSION_ID (HiRISE IDs encode it as two digits).")
@click.option("--params", "params_file", type=click.Path(dir_okay=False),
              help="PVL or TOML file of producer/data-set keywords (see schemas/params.toml).")
@click.option("--byte-order", type=click.Choice(["lsb", "msb"]), default="lsb", show_default=True,
              help="lsb writes PC_REAL, msb writes IEEE_REAL.")
@click.option("--overwrite", is_flag=True, help="Replace an existing product.")
def dtm(input_path, outdir, profile, product_id, source_ids, institution, product_version,
        params_file, byte_order, overwrite) -> None:
    """Convert the single-band elevation raster INPUT (any GDAL format, projected
    CRS: equirectangular, polar stereographic or sinusoidal) into
    OUTDIR/<PRODUCT_ID>.IMG."""
    product = write_dtm(
        input_path, outdir, profile=profile, product_id=product_id,
        source_product_ids=source_ids, params=params_file, byte_order=byte_order,
        institution=institution, version=product_version, overwrite=overwrite,
    )
    click.echo(f"{product.path}  {product.geometry.lines} x {product.geometry.samples}  "
               f"valid {product.valid_minimum} .. {product.valid_maximum} m")
