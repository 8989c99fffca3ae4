"""--quiet, --verbose and --json: how much a product command says, and in which form.

Every product command (dtm, ortho, extras, demo) returns an `Outcome` - its lines
for people and its summary for scripts - and `output_options` prints the one the
user asked for. Verbose mode shows the library's own log records ("pdsgen" logger:
what was read, chosen and written) on stderr, each with the seconds since start,
so a script reading --json on stdout is never disturbed by it.
"""

from __future__ import annotations

import functools
import json
import logging
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from ..progress import terminal_bar, wanted

if TYPE_CHECKING:  # an annotation only: `pdsgen validate` loads no product module
    from ..products.result import ProductResult

# click parameter names of these options: every profile uses them.
OUTPUT_OPTIONS = frozenset({"quiet", "verbose", "as_json"})


@dataclass
class Outcome:
    """What a command has to tell: lines for people, a summary for scripts, its exit code."""

    lines: list[str]
    summary: dict[str, Any]
    warnings: tuple[str, ...] = ()
    exit_code: int = 0


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
        with terminal_bar(wanted(quiet, as_json)):  # large DTM/JP2 writes draw a bar on a terminal
            outcome = command(*args, **kwargs)
        for warning in outcome.warnings:
            click.echo(f"warning: {warning}", err=True)
        if as_json:
            click.echo(json.dumps(outcome.summary, indent=2))
        elif not quiet:
            for line in outcome.lines:
                click.echo(line)
        if outcome.exit_code:
            raise SystemExit(outcome.exit_code)

    return wrapper


def files_summary(paths: Iterable[Path]) -> list[dict[str, Any]]:
    """Each written file as {"path", "bytes"}: what a script needs to pick the files up."""
    return [{"path": str(path), "bytes": path.stat().st_size} for path in paths]


def product_summary(command: str, product: ProductResult) -> dict[str, Any]:
    """The --json summary of one product a writer returned.

    `checks.label_rules` is "passed" for products whose label the writer checked
    with the validator's rules before publishing (it refuses them otherwise); the
    deviations it was told to keep are listed under `warnings`.
    """
    return {
        "command": command,
        "product_id": product.product_id,
        "lines": product.geometry.lines,
        "samples": product.geometry.samples,
        "files": files_summary(product.files),
        "checks": {
            "label_rules": "passed" if product.label_checked else "not run",
            "warnings": list(product.warnings),
        },
    }


class _ElapsedFormatter(logging.Formatter):
    def __init__(self) -> None:
        super().__init__()
        self.start = time.monotonic()

    def format(self, record: logging.LogRecord) -> str:
        return f"[{time.monotonic() - self.start:6.2f} s] {record.getMessage()}"


def log_to_stderr() -> None:
    """--verbose: the library's log records ('pdsgen' logger) on stderr, with elapsed seconds."""
    handler = logging.StreamHandler()  # stderr
    handler.setFormatter(_ElapsedFormatter())
    logger = logging.getLogger("pdsgen")
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
