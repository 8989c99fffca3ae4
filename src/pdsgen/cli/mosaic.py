"""`pdsgen mosaic`: strips or tiles of one kind into one product, placed as gdal_merge.py places them."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import click

from ..mosaic import write_mosaic
from ..mosaic.options import MOSAIC_HELP, MOSAIC_OPTIONS
from ..mosaic.options import library_options as mosaic_library_options
from ..products.result import ListedProduct
from ..storage import local_inputs, output_area
from . import COMMANDS
from ._output import Outcome, told
from ._output import output_options as _output_options
from ._profile_options import ProfileCommand, UsedByProfile, output_option, profile_option, vocabulary_options

# Each profile's options: the vocabulary's entries its mission declares for its mosaics.
USED_BY_PROFILE = UsedByProfile("mosaic", MOSAIC_OPTIONS, structural={"inputs", "outdir", "profile"})


@click.command(cls=ProfileCommand, used_by_profile=USED_BY_PROFILE, short_help=COMMANDS["mosaic"],
               help=MOSAIC_HELP)
@_output_options
@click.argument("inputs", metavar="INPUT...", nargs=-1, required=True, type=click.Path(dir_okay=False))
@output_option("outdir", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@profile_option("Mission profile: the product form, names and keywords.")
@vocabulary_options(MOSAIC_OPTIONS)
@click.pass_context
def mosaic(ctx, inputs, outdir, profile, overwrite, **_options) -> Outcome:
    options: dict[str, Any] = library_options(ctx.params)
    # Objects in a bucket are fetched as extras fetches them: an input's label (a PDS3 .IMG, an
    # iMars strip's tags) is read by Python to name and classify it, and a mosaic reads every
    # pixel of every input anyway. An s3:// OUTDIR: staged here, uploaded when complete.
    with local_inputs(inputs) as sources, output_area(outdir, overwrite) as area:
        product = write_mosaic(sources.paths, area.directory, **options)
        return told(ListedProduct(product), sources, area)


def library_options(params: Mapping[str, Any]) -> dict[str, Any]:
    """write_mosaic's keywords from the command's parsed parameters: those the profile uses
    (mosaic.options.library_options, which a manifest's [[mosaic]] job calls too)."""
    return mosaic_library_options(params)
