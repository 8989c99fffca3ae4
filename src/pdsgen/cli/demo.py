"""`pdsgen demo`: make every product from a built-in synthetic Mars scene."""

from __future__ import annotations

import click

from ..demo import run_demo


@click.command(short_help="Make every product from a built-in synthetic Mars scene.")
@click.argument("outdir", type=click.Path(file_okay=False), default="out/demo")
def demo(outdir: str) -> None:
    """Write a synthetic Mars DTM and orthoimage under OUTDIR/input/, then every
    product pdsgen can make from them into OUTDIR."""
    result = run_demo(outdir)
    click.echo(f"inputs in {outdir}/input: " + ", ".join(p.name for p in result.inputs))
    for line in result.lines:
        click.echo(line)
    if result.validation is not None and result.validation.exit_code:
        raise SystemExit(result.validation.exit_code)  # the demo's own products must validate
