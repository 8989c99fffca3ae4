"""The `pdsgen` command: a thin click layer over the library functions.

Each subcommand lives in its own module and only parses options and calls one
library function; modules are imported only when their command runs, so a
conversion does not pay for the imports of every other command. Errors the user
can fix (`PdsgenError`) become one line on stderr and exit code 2.
"""

from __future__ import annotations

import atexit
import contextlib
import gc
import importlib
import os
import sys
import threading
import warnings
from typing import NoReturn

import click
from click.shell_completion import CompletionItem

from .. import __version__
from ..errors import PdsgenError
from ..label.data_dictionary import shipped_version as shipped_dictionary_version

# command name (also its module under pdsgen.cli) -> the one-line help `pdsgen --help`
# and shell completion show. Kept here, and used by each command's decorator, so that
# listing or completing commands imports none of them (a Tab press stays instant).
COMMANDS = {
    "batch": "Make many products from a TOML manifest, on Dask.",
    "deliver": "Make a PDS3 volume and/or PDS4 bundle around products.",
    "demo": "Make every product from a built-in synthetic Mars scene.",
    "dtm": "Make a PDS3 DTM (.IMG with attached label).",
    "extras": "Make preview JPEGs, orthoimage quick-look JP2s and README.TXT.",
    "migrate": "Describe PDS3 products in PDS4 labels, their files unchanged.",
    "mosaic": "Mosaic strips or tiles into one DTM or orthoimage product.",
    "ortho": "Make a PDS3 orthoimage (.JP2 + detached .LBL).",
    "params": "Print a profile's params file template to fill in.",
    "review": "Write a self-contained HTML page to look over a delivery.",
    "validate": "Check PDS3 and PDS4 labels, label sets, deliveries and their data.",
}


class _Group(click.Group):
    """Lazily loaded subcommands; PdsgenError reported as one line, never a traceback."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(COMMANDS)

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name not in COMMANDS:
            return None
        module = importlib.import_module(f"{__name__}.{name}")
        _start_up_done()
        return getattr(module, name.replace("-", "_"))

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """The command list from COMMANDS, without importing every command module."""
        with formatter.section("Commands"):
            formatter.write_dl([(name, COMMANDS[name]) for name in self.list_commands(ctx)])

    def shell_complete(self, ctx: click.Context, incomplete: str) -> list[CompletionItem]:
        """Command names (with their help) from COMMANDS, then the group's own options."""
        names = [CompletionItem(name, help=COMMANDS[name])
                 for name in self.list_commands(ctx) if name.startswith(incomplete)]
        return names + click.Command.shell_complete(self, ctx, incomplete)

    def main(self, *args, **kwargs):
        """Usage errors as one line (click's default is a usage block of several lines)."""
        kwargs["standalone_mode"] = False
        # rasterio warns (two lines, with its source line) on opening a raster without a
        # geotransform; pdsgen reports what that means for the product itself, in one line.
        warnings.filterwarnings("ignore", message="Dataset has no geotransform")
        # glymur warns on import when OpenJPEG is missing; commands that need OpenJPEG say
        # so in one line with what to install (formats.jp2.require_openjpeg).
        warnings.filterwarnings("ignore", message="The openjp2 library")
        try:
            result = super().main(*args, **kwargs)
        except click.exceptions.NoArgsIsHelpError as exc:
            click.echo(exc.ctx.get_help() if exc.ctx else str(exc))
            sys.exit(0)
        except click.UsageError as exc:
            from ._messages import one_line  # a value typed may hold a line break

            where = f" (see '{exc.ctx.command_path} --help')" if exc.ctx else ""
            click.echo(f"pdsgen: error: {one_line(exc.format_message())}{where}", err=True)
            sys.exit(2)
        except click.ClickException as exc:
            from ._messages import one_line

            click.echo(f"pdsgen: error: {one_line(exc.format_message())}", err=True)
            sys.exit(exc.exit_code)
        except click.Abort:
            click.echo("pdsgen: aborted", err=True)
            sys.exit(1)
        sys.exit(result if isinstance(result, int) else 0)

    def invoke(self, ctx: click.Context):
        try:
            with _rasterio_without_boto3():
                return super().invoke(ctx)
        except PdsgenError as exc:
            from ..storage.locations import display_text
            from ._messages import in_cli_words, one_line

            click.echo(f"pdsgen: error: {one_line(display_text(in_cli_words(str(exc))))}", err=True)
            sys.exit(2)
        except OSError as exc:
            # a file the system refused (permission, read-only file system, disk full) is the
            # user's to fix, as a PdsgenError is: one line naming it, never a traceback
            from ._messages import one_line

            click.echo(f"pdsgen: error: {one_line(os_error_line(exc))}", err=True)
            sys.exit(2)
        except KeyboardInterrupt:
            # the writers' staging has already removed its temporary files on the way out
            click.echo("pdsgen: interrupted (no partial output left)", err=True)
            sys.exit(130)


def os_error_line(exc: OSError) -> str:
    """An OSError as the user reads it: the path the system refused, and why in its words
    (`out/r.json: read-only file system`); the second path of a rename as well."""
    reason = (exc.strerror or str(exc) or type(exc).__name__).lower()
    paths = [os.fspath(name) for name in (exc.filename, exc.filename2) if name is not None]
    return f"{' -> '.join(str(path) for path in paths)}: {reason}" if paths else reason


def _print_version(ctx: click.Context, param: click.Parameter, value: bool) -> None:
    """pdsgen's version and the data dictionary the validator checks against (read from
    the shipped dictionary when asked, so other commands do not pay for it)."""
    if not value or ctx.resilient_parsing:
        return
    click.echo(f"pdsgen, version {__version__}\nPDS3 data dictionary (PSDD): {shipped_dictionary_version()}")
    ctx.exit()


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--version", is_flag=True, expose_value=False, is_eager=True, callback=_print_version,
              help="Show the version (and the data dictionary's) and exit.")
def main() -> None:
    """Make PDS3 and PDS4 archive products from planetary DTMs and orthoimages, and check them."""


def run(args: list[str] | None = None, prog_name: str | None = None) -> NoReturn:
    """The installed command's entry point: `main`, then end the process without tearing the
    interpreter down.

    Once a command has finished, Python would spend ~40 ms unloading numpy, rasterio, jinja2
    and the rest (a sixth of a small DTM's whole run, measured with bench/dtm_write.py), work
    nobody sees. Everything a user could notice is done first: exit handlers run (temporary
    directories, Dask and logging shut down) and stdout/stderr are flushed; only then does the
    process end. A live non-daemon thread, or a stream that cannot be flushed, takes Python's
    ordinary exit instead, which waits for the thread or reports the stream as it always does.
    """
    _keep_blas_to_one_thread()
    _start_up_begins()
    _START_UP["own_process"] = True  # rasterio would import boto3 on every command: see _Group.invoke
    try:
        main(args=args, prog_name=prog_name)
        code: str | int | None = 0
    except SystemExit as exc:
        code = exc.code
    _end(code)


_START_UP = {"collector_paused": False, "own_process": False}


def _start_up_begins() -> None:
    """Pause the cyclic garbage collector while the command's modules are imported.

    Importing numpy, rasterio, jinja2 and pdsgen creates hundreds of thousands of objects
    that live as long as the process; the collector would walk them again and again while
    they are made (0.02 s of a 64 x 64 DTM's 0.23 s, measured). See _start_up_done."""
    if gc.isenabled():
        gc.disable()
        _START_UP["collector_paused"] = True


def _keep_blas_to_one_thread() -> None:
    """numpy's OpenBLAS starts a thread per core on import, which spins after each call;
    pdsgen does no linear algebra, and on a busy encoder those threads only take CPU from it
    (0.1 s per orthoimage measured). Set by the command's process before any command imports
    numpy (not on importing this module: a program using the library keeps its own
    environment); a value the user exported wins."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def _rasterio_without_boto3() -> contextlib.AbstractContextManager[None]:
    """In the command's own process (started by `run`), keep rasterio from importing boto3
    while the command is imported and runs (storage.objects.boto3_kept_from_rasterio);
    a program calling `main` keeps its modules as they are. Entered after --help and
    --version are answered, so they do not import pdsgen.storage."""
    if not _START_UP["own_process"]:
        return contextlib.nullcontext()
    from ..storage.objects import boto3_kept_from_rasterio

    return boto3_kept_from_rasterio()


def _start_up_done() -> None:
    """The command is imported: set the objects made so far aside for good (gc.freeze) and
    let the collector run again for the command's own work, whatever its length."""
    if _START_UP["collector_paused"]:
        _START_UP["collector_paused"] = False
        gc.freeze()
        gc.enable()


def _end(code: str | int | None) -> NoReturn:
    if any(thread.is_alive() and not thread.daemon for thread in threading.enumerate()
           if thread is not threading.main_thread()):
        sys.exit(code)
    status = _exit_status(code)
    atexit._run_exitfuncs()
    try:
        for stream in (sys.stdout, sys.stderr):
            if stream is not None:  # None: the process was started with that descriptor closed
                stream.flush()
    except (OSError, ValueError):
        sys.exit(status)
    os._exit(status)


def _exit_status(code: str | int | None) -> int:
    """The status sys.exit(code) would end with (None: 0; text: printed, then 1)."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code
    if sys.stderr is not None:
        print(code, file=sys.stderr)
    return 1
