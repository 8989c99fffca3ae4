"""`pdsgen extras`: preview JPEGs and README.TXT for DTM and orthoimage products."""

from __future__ import annotations

import logging

import click

from ..extras import KINDS, NOMAP, make_extras
from ..extras.readme_txt import README_NAME
from ..extras.result import ExtrasResult
from ..storage import local_inputs, output_area
from . import COMMANDS
from ._messages import in_cli_words
from ._output import Outcome, output_options, told
from ._profile_options import profile_option


@click.command(short_help=COMMANDS["extras"])
@output_options
@click.argument("products", metavar="PRODUCT...", nargs=-1, required=True,
                type=click.Path(dir_okay=False))
@click.option("-o", "--outdir", required=True, type=click.Path(file_okay=False),
              help="Output directory.")
@click.option("--credit", help="Credit line on annotated images [default: params CREDIT, else the "
                               "--profile's, else that of the mission the label names, else the "
                               "label's mission and PRODUCER_INSTITUTION_NAME].")
@click.option("--params", "params_file", type=click.Path(dir_okay=False),
              help="PVL or TOML file of producer keywords (contact, known artifacts ...).")
@click.option("--browse-width", type=int,
              help="Browse width in pixels [default: 1024 for DTMs, 2048 for orthoimages].")
@click.option("--thumb-width", type=int, default=128, show_default=True,
              help="Thumbnail width in pixels.")
@click.option("--azimuth", type=float, default=315.0, show_default=True,
              help="Light direction for shaded relief, degrees clockwise from image up.")
@click.option("--altitude", type=float, default=45.0, show_default=True,
              help="Light elevation above the horizon for shaded relief, degrees.")
@click.option("--exaggeration", type=float,
              help="Vertical exaggeration of the shaded relief [default: 1, raised "
                   "automatically when the relief is too faint at preview scale].")
@click.option("--kind", type=click.Choice((*KINDS, NOMAP)),
              help="Treat every PRODUCT as this kind [default: from the label, metadata or "
                   "values; refused when they do not say]. nomap: PRODUCTs are one HiRISE "
                   "observation's RED and/or IRB NOMAP mosaics (not map-projected).")
@click.option("--product-id", help="With --kind nomap: the observation ID (e.g. "
                                   "PSP_005000_1000) when the file names carry none.")
@profile_option("Mission conventions (credit line) [default: from each product's label].", default=None)
@click.option("--overwrite", is_flag=True, help="Replace existing Extras files.")
def extras(products, outdir, credit, params_file, browse_width, thumb_width, azimuth, altitude,
           exaggeration, kind, product_id, profile, overwrite) -> Outcome:
    """Write the Extras of each PRODUCT (a PDS3 .IMG/.LBL/.JP2 or a GeoTIFF) into OUTDIR.

    One line per product on stderr says whether it was taken for a DTM or an
    orthoimage, and why.
    """
    # GDAL's own messages reach rasterio's logger; the user sees pdsgen's one-line
    # errors instead (a NullHandler keeps Python's last-resort printer quiet).
    logging.getLogger("rasterio").addHandler(logging.NullHandler())
    # s3:// PRODUCTs are fetched with the files beside them; an s3:// OUTDIR is staged and uploaded
    with local_inputs(products) as inputs, output_area(outdir, overwrite, shared=(README_NAME,)) as area:
        written = make_extras(inputs.paths, area.directory, credit=credit, params=params_file,
                              browse_width=browse_width, thumb_width=thumb_width, azimuth=azimuth,
                              altitude=altitude, exaggeration=exaggeration, kind=kind,
                              profile=profile, product_id=product_id, overwrite=overwrite,
                              report=lambda line: click.echo(f"pdsgen: {inputs.shown(in_cli_words(line))}", err=True))
        return told(ExtrasResult.of(written), area)
