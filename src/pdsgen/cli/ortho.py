"""`pdsgen ortho`: an orthoimage to a lossless JPEG 2000 with a detached PDS3 label."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import click

from ..products.options import ORTHO_HELP, ORTHO_OPTIONS, ortho_inputs, ortho_shared_files
from ..products.ortho import write_ortho
from ..storage import output_area
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

# Each profile's options: the vocabulary's entries its mission declares for its orthoimages.
USED_BY_PROFILE = UsedByProfile("ortho", ORTHO_OPTIONS, structural={"input_path", "outdir"})

# Files one orthoimage updates for its whole directory: fetched from, and written back to, an s3:// OUTDIR.
SHARED_FILES = ortho_shared_files()


@click.command(cls=ProfileCommand, used_by_profile=USED_BY_PROFILE, short_help=COMMANDS["ortho"],
               help=ORTHO_HELP)
@output_options
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False))
@click.argument("more_inputs", metavar="[INPUT]...", nargs=-1, type=click.Path(dir_okay=False))
@output_option("outdir", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@profile_option("Mission profile: names and keywords.")
@vocabulary_options(ORTHO_OPTIONS)
@click.pass_context
def ortho(ctx, outdir, profile, overwrite, **_options) -> Outcome:
    with output_area(outdir, overwrite, shared=SHARED_FILES) as area:  # s3:// OUTDIR: uploaded when complete
        product = write_ortho(ortho_inputs(ctx.params), area.directory, profile=profile, **library_options(ctx.params))
        return told(warned_in_cli_words(product), area)


def library_options(params: Mapping[str, Any]) -> dict[str, object]:
    """write_ortho's keywords from the command's parsed parameters: those the profile uses.

    `pdsgen batch` calls it too, so a manifest's job and the command make the same call.
    """
    return USED_BY_PROFILE.library_options(params)
