"""--quiet, --verbose and --json: how much a command says, and in which form.

Every command's library call returns a `CommandResult` (pdsgen/results.py): its files,
its lines for people, its warnings and its facts for scripts. `told` turns any result
into the command's `Outcome` and `output_options` prints the one the user asked for -
the lines, or the one JSON shape of `CommandResult.as_json` - with no code of the
command's own. Verbose mode shows the library's own log records ("pdsgen" logger:
what was read, chosen and written) on stderr, each with the seconds since start,
so a script reading --json on stdout is never disturbed by it.
"""

from __future__ import annotations

import functools
import json
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import click

from ..progress import terminal_bar, wanted

if TYPE_CHECKING:  # an annotation only: `pdsgen validate` loads no command result
    from ..results import CommandResult

# click parameter names of these options: every profile uses them.
OUTPUT_OPTIONS = frozenset({"quiet", "verbose", "as_json"})
# Where output_options leaves --json for `told` and --quiet for `is_quiet` (the command itself never
# sees the flags).
_JSON_WANTED = "pdsgen.as_json"
_QUIET = "pdsgen.quiet"


@dataclass
class Outcome:
    """What a command has to tell: lines for people, a summary for scripts, its exit code."""

    lines: list[str]
    summary: dict[str, Any]  # the --json document (made under --json only: it sizes every file)
    warnings: tuple[str, ...] = ()
    exit_code: int = 0
    refused: tuple[str, ...] = ()  # what the command refused and went on after, in the command line's words


class ShowsPaths(Protocol):
    """An input or output area: `shown(text)` names its local copies as the user named them."""

    def shown(self, text: str) -> str: ...


def told(result: CommandResult, *places: ShowsPaths) -> Outcome:
    """What a command tells of its result, whichever command it is: the result's lines,
    warnings and refusals, and (under --json only: it sizes every file) its JSON document.

    Called inside the command's input and output areas (`places`, innermost first: an
    s3:// input's local copy, an s3:// OUTDIR's staging directory), whose paths are shown
    as the user named them; the files are sized before the staging directory goes.
    """
    context = click.get_current_context()
    show = _showing(places)
    summary = show(result.as_json(context.command.name or "")) if context.meta.get(_JSON_WANTED) else {}
    return Outcome(show(list(result.summary_lines)), summary, show(tuple(result.warnings)), result.exit_code,
                   show(_in_cli_words(result.refused)))


def echo_json(result: CommandResult, *places: ShowsPaths) -> None:
    """Print a result's --json document on stdout, for a command that tells the rest of its run
    itself (`pdsgen validate` streams its report): the same document `told` makes."""
    context = click.get_current_context()
    click.echo(json.dumps(_showing(places)(result.as_json(context.command.name or "")), indent=2))


def is_quiet() -> bool:
    """Whether the running command was given -q/--quiet: a command telling more than its result
    (the Extras' line on the kind each product was taken for) says nothing of it then."""
    return bool(click.get_current_context().meta.get(_QUIET))


def _in_cli_words(messages: tuple[str, ...]) -> tuple[str, ...]:
    """Library messages naming options as the command line spells them (loaded only when there are any)."""
    if not messages:
        return ()
    from ._messages import in_cli_words

    return tuple(in_cli_words(message) for message in messages)


def _showing(places: tuple[ShowsPaths, ...]) -> Callable[[Any], Any]:
    """Every string in a value (lines, a JSON document), each place's `shown` applied in turn."""

    def show(value: Any) -> Any:
        if isinstance(value, Path):
            value = str(value)
        if isinstance(value, str):
            for place in places:
                value = place.shown(value)
            return value
        if isinstance(value, dict):
            return {key: show(item) for key, item in value.items()}
        if isinstance(value, list | tuple):
            return type(value)(show(item) for item in value)
        return value

    return show


def output_options(command: Callable[..., Outcome]) -> Callable[..., None]:
    """Add --quiet / --verbose / --json to a command returning an `Outcome`."""

    @click.option("--json", "as_json", is_flag=True,
                  help="Print a JSON summary of what was written (paths, sizes, product ID, checks) on stdout.")
    @click.option("-v", "--verbose", is_flag=True,
                  help="Tell on stderr what was read, chosen and written, with timings.")
    @click.option("-q", "--quiet", is_flag=True, help="Print nothing but warnings and errors.")
    @functools.wraps(command)
    def wrapper(*args: Any, quiet: bool, verbose: bool, as_json: bool, **kwargs: Any) -> None:
        if quiet and verbose:
            raise click.UsageError("--quiet and --verbose exclude each other")
        if verbose:
            log_to_stderr()
        click.get_current_context().meta.update({_JSON_WANTED: as_json, _QUIET: quiet})
        with terminal_bar(wanted(quiet, as_json)):  # large DTM/JP2 writes draw a bar on a terminal
            outcome = command(*args, **kwargs)
        from ._messages import one_line  # every line a command prints leaves through the terminal encoder

        if outcome.refused or outcome.warnings:
            for error in outcome.refused:
                click.echo(f"pdsgen: error: {one_line(str(error))}", err=True)
            for warning in outcome.warnings:
                click.echo(f"warning: {one_line(str(warning))}", err=True)
        if as_json:
            click.echo(json.dumps(outcome.summary, indent=2))
        elif not quiet:
            for line in outcome.lines:
                click.echo(one_line(line))
        if outcome.exit_code:
            raise SystemExit(outcome.exit_code)

    return wrapper


class _ElapsedFormatter(logging.Formatter):
    def __init__(self) -> None:
        super().__init__()
        self.start = time.monotonic()

    def format(self, record: logging.LogRecord) -> str:
        from ._messages import one_line

        return f"[{time.monotonic() - self.start:6.2f} s] {one_line(record.getMessage())}"


def log_to_stderr() -> None:
    """--verbose: the library's log records ('pdsgen' logger) on stderr, with elapsed seconds."""
    handler = logging.StreamHandler()  # stderr
    handler.setFormatter(_ElapsedFormatter())
    logger = logging.getLogger("pdsgen")
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
