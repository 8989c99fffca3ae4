"""`pdsgen dtm`: a DTM raster to a PDS3 .IMG with attached label."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import click

from ..products.dtm import write_dtm
from ..products.options import DTM_HELP, DTM_OPTIONS
from ..storage import internal, output_area
from . import COMMANDS
from ._output import Outcome, output_options, told
from ._profile_options import (
    ProfileCommand,
    UsedByProfile,
    output_option,
    profile_option,
    vocabulary_options,
    warned_in_cli_words,
)

# Each profile's options: the vocabulary's entries its mission declares for its DTMs.
USED_BY_PROFILE = UsedByProfile("dtm", DTM_OPTIONS, structural={"input_path", "outdir"})


@click.command(cls=ProfileCommand, used_by_profile=USED_BY_PROFILE, short_help=COMMANDS["dtm"],
               help=DTM_HELP)
@output_options
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False))
@output_option("outdir", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@profile_option("Mission profile: names and keywords.")
@vocabulary_options(DTM_OPTIONS)
@click.pass_context
def dtm(ctx, input_path, outdir, profile, overwrite, **_options) -> Outcome:
    with output_area(outdir, overwrite) as area:  # an s3:// OUTDIR: staged here, uploaded when complete
        product = write_dtm(internal(input_path), area.directory, profile=profile, **library_options(ctx.params))
        return told(warned_in_cli_words(product), area)


def library_options(params: Mapping[str, Any]) -> dict[str, object]:
    """write_dtm's keywords from the command's parsed parameters: those the profile uses.

    `pdsgen batch` calls it too, so a manifest's job and the command make the same call.
    """
    return USED_BY_PROFILE.library_options(params)
