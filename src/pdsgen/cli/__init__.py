"""The `pdsgen` command: a thin click layer over the library functions.

Each subcommand lives in its own module and only parses options and calls one
library function. Errors the user can fix (`PdsgenError`) become one line on
stderr and exit code 2.
"""

from __future__ import annotations

import sys

import click

from .. import __version__
from ..errors import PdsgenError


class _Group(click.Group):
    """A click group that reports PdsgenError as one line, never a traceback."""

    def invoke(self, ctx: click.Context):  # type: ignore[override]
        try:
            return super().invoke(ctx)
        except PdsgenError as exc:
            click.echo(f"pdsgen: error: {exc}", err=True)
            sys.exit(2)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="pdsgen")
def main() -> None:
    """Make PDS3 archive products from planetary DTMs and orthoimages, and check them."""


def _register() -> None:
    from .demo import demo
    from .dtm import dtm
    from .extras import extras

    main.add_command(dtm)
    main.add_command(demo)
    main.add_command(extras)


_register()
