"""`pdsgen demo`: make every product from a built-in synthetic Mars scene."""

from __future__ import annotations

import click

from ..demo import run_demo
from . import COMMANDS
from ._output import Outcome, files_summary, output_options


@click.command(short_help=COMMANDS["demo"])
@output_options
@click.argument("outdir", type=click.Path(file_okay=False), default="out/demo")
def demo(outdir: str) -> Outcome:
    """Write a synthetic Mars DTM and orthoimage under OUTDIR/input/, then every
    product pdsgen can make from them into OUTDIR."""
    result = run_demo(outdir)
    lines = [f"inputs in {outdir}/input: " + ", ".join(p.name for p in result.inputs), *result.lines]
    validation = result.validation
    summary = {
        "command": "demo",
        "inputs": files_summary(result.inputs),
        "files": files_summary(result.products),
        "checks": {"validate": validation.summary_line() if validation else "not run",
                   "exit_code": validation.exit_code if validation else None},
    }
    # the demo's own products must validate: its exit code is the validator's
    return Outcome(lines, summary, exit_code=validation.exit_code if validation else 0)
