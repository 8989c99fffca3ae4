"""`pdsgen demo`: make every product from a built-in synthetic Mars scene."""

from __future__ import annotations

import click

from ..demo import run_demo
from . import COMMANDS
from ._output import Outcome, output_options, told


@click.command(short_help=COMMANDS["demo"])
@output_options
@click.argument("outdir", type=click.Path(file_okay=False), default="out/demo")
def demo(outdir: str) -> Outcome:
    """Write a synthetic Mars DTM and orthoimage under OUTDIR/input/, then every
    product pdsgen can make from them into OUTDIR."""
    return told(run_demo(outdir))  # the demo's own products must validate: its exit code is the validator's
