"""The `pdsgen` command: a thin click layer over the library functions.

Each subcommand lives in its own module and only parses options and calls one
library function; modules are imported only when their command runs, so a
conversion does not pay for the imports of every other command. Errors the user
can fix (`PdsgenError`) become one line on stderr and exit code 2.
"""

from __future__ import annotations

import importlib
import sys

import click

from .. import __version__
from ..errors import PdsgenError

# command name -> module (under pdsgen.cli) defining a click command of that name
COMMANDS = {
    "dtm": "dtm",
    "ortho": "ortho",
    "demo": "demo",
    "extras": "extras",
    "validate": "validate",
}


class _Group(click.Group):
    """Lazily loaded subcommands; PdsgenError reported as one line, never a traceback."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(COMMANDS)

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name not in COMMANDS:
            return None
        module = importlib.import_module(f"{__name__}.{COMMANDS[name]}")
        return getattr(module, name.replace("-", "_"))

    def main(self, *args, **kwargs):
        """Usage errors as one line (click's default is a usage block of several lines)."""
        kwargs["standalone_mode"] = False
        try:
            result = super().main(*args, **kwargs)
        except click.exceptions.NoArgsIsHelpError as exc:
            click.echo(exc.ctx.get_help() if exc.ctx else str(exc))
            sys.exit(0)
        except click.UsageError as exc:
            where = f" (see '{exc.ctx.command_path} --help')" if exc.ctx else ""
            click.echo(f"pdsgen: error: {exc.format_message()}{where}", err=True)
            sys.exit(2)
        except click.ClickException as exc:
            click.echo(f"pdsgen: error: {exc.format_message()}", err=True)
            sys.exit(exc.exit_code)
        except click.Abort:
            click.echo("pdsgen: aborted", err=True)
            sys.exit(1)
        sys.exit(result if isinstance(result, int) else 0)

    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except PdsgenError as exc:
            click.echo(f"pdsgen: error: {exc}", err=True)
            sys.exit(2)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="pdsgen")
def main() -> None:
    """Make PDS3 archive products from planetary DTMs and orthoimages, and check them."""
