"""`pdsgen validate`: check PDS3 labels, label sets and their data, for people and for CI."""

from __future__ import annotations

import sys

import click

from ..errors import PdsgenError
from ..validate import render, rules, validate_paths
from ..validate.runner import terminal_progress


def _list_rules() -> str:
    lines = [f"{r.id:<11} {r.severity:<8} {r.summary}" for r in rules().values()]
    return "\n".join(lines) + "\n"


@click.command(short_help="Check PDS3 labels, label sets and their data.")
@click.argument("paths", nargs=-1, type=click.Path())
@click.option("--format", "fmt", type=click.Choice(["text", "json", "junit"]), default="text",
              show_default=True, help="Report format: text for people, json or junit for CI.")
@click.option("--strict", is_flag=True, help="Fail (exit 1) on warnings too.")
@click.option("--jobs", "-j", type=click.IntRange(min=1), default=1, show_default=True,
              help="Files checked in parallel (processes).")
@click.option("--labels-only", is_flag=True,
              help="Check label text only; do not open the data files it points to.")
@click.option("--dictionary", "dictionaries", multiple=True, type=click.Path(dir_okay=False),
              help="Extra data dictionary (PSDD .full format) merged over the built-in one; repeatable.")
@click.option("--schemas", "schemas", multiple=True, type=click.Path(file_okay=False),
              help="Directory of PDS4 schemas (.xsd/.sch) for Information Model versions pdsgen does not "
                   "ship (1O00 is shipped); repeatable.")
@click.option("--list-rules", "list_rules", is_flag=True, help="Print the rule table and exit.")
@click.option("--output", "-o", type=click.Path(dir_okay=False),
              help="Write the report to this file instead of standard output.")
def validate(paths: tuple[str, ...], fmt: str, strict: bool, jobs: int, labels_only: bool,
             dictionaries: tuple[str, ...], schemas: tuple[str, ...], list_rules: bool, output: str | None) -> None:
    """Validate PATHS (label files, or directories searched recursively): PDS3 labels,
    and PDS4 .xml labels (XML Schema, Schematron, and the data they describe).

    Exit status: 0 no errors (and no warnings with --strict), 1 problems found,
    2 usage error.
    """
    if list_rules:
        click.echo(_list_rules(), nl=False)
        return
    if not paths:
        raise PdsgenError(None, "give at least one label file or directory to validate")
    progress = terminal_progress if sys.stderr.isatty() else None
    report = validate_paths(paths, strict=strict, jobs=jobs, labels_only=labels_only,
                            progress=progress, dictionaries=dictionaries, schemas=schemas)
    text = render(report, fmt)
    if output:
        try:
            with open(output, "w", encoding="utf-8") as fh:
                fh.write(text)
        except OSError as exc:
            raise PdsgenError(output, f"cannot write the report: {exc.strerror}") from None
    else:
        click.echo(text, nl=False)
    sys.exit(report.exit_code)
