"""`pdsgen demo`: make every product from a built-in synthetic Mars scene."""

from __future__ import annotations

import click

from ..demo import run_demo
from . import COMMANDS
from ._output import Outcome, output_options, told
from ._profile_options import output_option

DEFAULT_OUTDIR = "out/demo"


@click.command(short_help=COMMANDS["demo"])
@output_options
@click.argument("positional", metavar="[OUTDIR]", required=False, type=click.Path(file_okay=False))
@output_option("outdir", "--outdir", type=click.Path(file_okay=False),
               help=f"Where to write (also given as the argument OUTDIR)  [default: {DEFAULT_OUTDIR}]")
def demo(positional: str | None, outdir: str | None) -> Outcome:
    """Write a synthetic Mars DTM and orthoimage under OUTDIR/input/, then every
    product pdsgen can make from them into OUTDIR (-o/--output, or the argument)."""
    if positional and outdir and positional != outdir:
        raise click.UsageError(f"two output directories given ({positional} and -o {outdir}): give one")
    # the demo's own products must validate: its exit code is the validator's
    return told(run_demo(outdir or positional or DEFAULT_OUTDIR))
