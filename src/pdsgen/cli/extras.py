"""`pdsgen extras`: preview JPEGs and README.TXT for DTM and orthoimage products."""

from __future__ import annotations

import logging

import click

from ..extras import make_extras
from ..extras.options import OVERWRITE_EXTRAS, RENDERING_OPTIONS, library_options
from ..extras.readme_txt import README_NAME
from ..extras.result import ExtrasResult
from ..storage import local_inputs, output_area
from . import COMMANDS
from ._messages import in_cli_words, one_line
from ._output import Outcome, is_quiet, output_options, told
from ._profile_options import click_option, output_option, profile_option, vocabulary_options


@click.command(short_help=COMMANDS["extras"])
@output_options
@click.argument("products", metavar="PRODUCT...", nargs=-1, required=True,
                type=click.Path(dir_okay=False))
@output_option("outdir", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@vocabulary_options(RENDERING_OPTIONS)
@profile_option("Mission conventions (credit line) [default: from each product's label].", default=None)
@click_option(OVERWRITE_EXTRAS)
@click.pass_context
def extras(ctx, products, outdir, overwrite, **_options) -> Outcome:
    """Write the Extras of each PRODUCT (a PDS3 .IMG/.LBL/.JP2 or a GeoTIFF) into OUTDIR.

    One line per product on stderr says whether it was taken for a DTM or an
    orthoimage, and why (not with -q); one line per file written on stdout.
    """
    # GDAL's own messages reach rasterio's logger; the user sees pdsgen's one-line
    # errors instead (a NullHandler keeps Python's last-resort printer quiet).
    logging.getLogger("rasterio").addHandler(logging.NullHandler())
    # s3:// PRODUCTs are fetched with the files beside them; an s3:// OUTDIR is staged and uploaded
    with local_inputs(products) as inputs, output_area(outdir, overwrite, shared=(README_NAME,)) as area:
        report = None if is_quiet() else (
            lambda line: click.echo(f"pdsgen: {one_line(inputs.shown(in_cli_words(line)))}", err=True))
        written = make_extras(inputs.paths, area.directory, **library_options(ctx.params), report=report)
        return told(ExtrasResult.of(written), area)
