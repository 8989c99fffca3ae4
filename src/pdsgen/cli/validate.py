"""`pdsgen validate`: check PDS3 labels, label sets and their data, for people and for CI."""

from __future__ import annotations

import logging
import sys
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any, TextIO, cast

import click

from ..errors import PdsgenError
from ..pds4.detect import default_schema_cache
from ..progress import TerminalBar
from ..progress import wanted as progress_wanted
from ..storage import local_inputs
from ..validate import config as configuration
from ..validate import rules
from ..validate.dictionary import version as dictionary_version
from ..validate.report import (
    FORMATS,
    FileReport,
    Tally,
    failing_severities,
    fails,
    finding_line,
    terminal_safe,
    write_stream,
)
from ..validate.runner import ValidationJob, iter_reports
from . import COMMANDS
from ._output import echo_json, log_to_stderr

log = logging.getLogger("pdsgen.validate")

SEVERITY_POLICY = (
    "Severity policy: ERROR = a reader would misread the data, or the label breaks a hard "
    "PDS3 rule; WARNING = a deviation that genuine archives contain; INFO = notes."
)


def _list_rules() -> str:
    lines = [SEVERITY_POLICY, f"Data dictionary: {dictionary_version()}", ""]
    for r in rules().values():
        lines.append(f"{r.id:<11} {r.severity:<8} {r.summary}")
        if r.note:
            lines.append(f"{'':<20} ({r.note})")
    return "\n".join(lines) + "\n"


@contextmanager
def _files_progress(quiet: bool) -> Iterator[TerminalBar | None]:
    """The count of files checked, on stderr when it is a terminal (see pdsgen.progress.wanted);
    cleared when the run ends, however it ends."""
    bar = TerminalBar() if progress_wanted(quiet) else None
    try:
        yield bar
    finally:
        if bar is not None:
            bar.close()


def _giving_way(reports: Iterable[FileReport], bar: TerminalBar) -> Iterator[FileReport]:
    """Reports whose lines start on a clean line: the count is cleared before each is written
    (it is drawn again, at most ten times a second, by the next file)."""
    for report in reports:
        bar.close()
        yield report


@contextmanager
def _output(path: str | None):
    """Standard output, or the file written under a temporary name and renamed when the
    report is complete (a run that stops early leaves no partial report)."""
    if not path:
        yield sys.stdout
        return
    from ..storage.staging import staged_file  # only for a report file: not on every validate's start-up

    target = Path(path)
    with staged_file(target, target.with_name(f".{target.name}.partial")) as tmp:
        try:
            fh: IO[str] = open(tmp, "w", encoding="utf-8")
        except OSError as exc:
            raise PdsgenError(path, f"cannot write the report: {exc.strerror}") from None
        with fh:
            yield fh


@click.command(short_help=COMMANDS["validate"])
@click.argument("paths", nargs=-1, type=click.Path())
@click.option("--format", "fmt", type=click.Choice(FORMATS), default="text", show_default=True,
              help="Report format: text for people; json, junit, sarif (code scanning) or github "
                   "(workflow annotations) for CI; html: a review page (as pdsgen review writes).")
@click.option("--strict", is_flag=True,
              help="Fail (exit 1) on warnings too, and keep over-long lines an error for any label.")
@click.option("--fail-on", type=click.Choice(["error", "warning"]), default=None,
              help="Lowest severity that fails the run (default: the configuration's, else error).")
@click.option("--select", multiple=True, metavar="IDS",
              help="Only these rule ids or families (comma-separated; repeatable).")
@click.option("--ignore", multiple=True, metavar="IDS",
              help="Leave out these rule ids or families (comma-separated; repeatable).")
@click.option("--severity", "severities", multiple=True, metavar="RULE=LEVEL",
              help="Report a rule (or family) at another severity: error, warning or info; repeatable.")
@click.option("--config", "config_path", type=click.Path(dir_okay=False),
              help="Configuration file (default: pdsgen.toml or pyproject.toml [tool.pdsgen.validate] "
                   "in the working directory or a parent).")
@click.option("--no-config", is_flag=True, help="Do not read a configuration file.")
@click.option("--baseline", "baseline_path", type=click.Path(dir_okay=False),
              help="Report only findings not recorded in this baseline file.")
@click.option("--write-baseline", "write_baseline_path", type=click.Path(dir_okay=False),
              help="Record this run's findings as the baseline (the run then passes).")
@click.option("--jobs", "-j", type=click.IntRange(min=1), default=1, show_default=True,
              help="Files checked in parallel (processes).")
@click.option("--scheduler", metavar="ADDRESS",
              help="Check the files on this Dask scheduler's workers (e.g. tcp://10.0.0.5:8786), a partition "
                   "each; the checks across files run here. The report is that of a run without it.")
@click.option("--labels-only", is_flag=True,
              help="Check label text only; do not open the data files it points to.")
@click.option("--dictionary", "dictionaries", multiple=True, type=click.Path(dir_okay=False),
              help="Extra data dictionary (PSDD .full format) merged over the built-in one; repeatable.")
@click.option("--schemas", "schemas", multiple=True, type=click.Path(file_okay=False),
              help="Directory of PDS4 schemas (.xsd/.sch), searched first (recursively); repeatable. pdsgen "
                   "ships the core schema of every IM version from 1.0.0.0 to 1.24.0.0 and every "
                   "version of the discipline dictionaries.")
@click.option("--schema-cache", type=click.Path(file_okay=False),
              help="Directory of downloaded PDS4 schemas (default: ~/.cache/pdsgen/pds4-schemas).")
@click.option("--offline", is_flag=True,
              help="Never download a PDS4 schema; one not found locally is reported and its namespace "
                   "left unchecked.")
@click.option("--skip-non-labels", is_flag=True,
              help="Pass over named files that are not labels (an ordinary .xml, a bare .img), as a "
                   "directory search does; with none left, check nothing and pass (pre-commit hooks).")
@click.option("--root", type=click.Path(file_okay=False, exists=True),
              help="Trusted tree: files labels name may lie anywhere inside it (default: the directory given, "
                   "or a label's own directory).")
@click.option("--list-rules", "list_rules", is_flag=True,
              help="Print the severity policy and the rule table, and exit.")
@click.option("--output", "-o", type=click.Path(dir_okay=False),
              help="Write the report to this file instead of standard output.")
@click.option("--json", "as_json", is_flag=True,
              help="Print the run as every command's --json does (files written, counts, findings) on "
                   "stdout instead of the text report; a --format report then needs --output.")
@click.option("-q", "--quiet", is_flag=True,
              help="Text report: only the findings that fail the run, no summary line, no progress "
                   "(--format other than text, and --output, still get the whole report; with --output, "
                   "no summary line on stderr either).")
@click.option("-v", "--verbose", is_flag=True,
              help="Tell on stderr which configuration, dictionary, rules and baseline are used, "
                   "and how long the run took.")
def validate(paths: tuple[str, ...], fmt: str, strict: bool, fail_on: str | None, select: tuple[str, ...],
             ignore: tuple[str, ...], severities: tuple[str, ...], config_path: str | None, no_config: bool,
             baseline_path: str | None, write_baseline_path: str | None, jobs: int, scheduler: str | None,
             labels_only: bool,
             dictionaries: tuple[str, ...], schemas: tuple[str, ...], skip_non_labels: bool, schema_cache: str | None,
             offline: bool, root: str | None, list_rules: bool, output: str | None, as_json: bool, quiet: bool,
             verbose: bool) -> None:
    """Validate PATHS (label files, or directories searched recursively): PDS3 labels,
    and PDS4 labels of any name (XML Schema, Schematron, and the data they describe).

    With --output the report goes to the file and its summary line to stderr (unless -q), so a CI
    log says why a run failed. Exit status: 0 no errors (and no warnings with --strict or
    fail-on = "warning"), 1 problems found, 2 usage error.
    """
    if list_rules:
        click.echo(_list_rules(), nl=False)
        return
    if not paths:
        raise PdsgenError(None, "give at least one label file or directory to validate")
    if quiet and verbose:
        raise click.UsageError("--quiet and --verbose exclude each other")
    if as_json and fmt != "text" and not output:
        raise click.UsageError(f"--json prints the run on stdout: give the --format {fmt} report an --output file")
    if verbose:
        log_to_stderr()
    started = time.monotonic()
    settings = configuration.load(config_path, search=not no_config)
    settings = configuration.override(settings, select, ignore, severities, "warning" if strict else fail_on)
    baseline = configuration.Baseline.read(baseline_path) if baseline_path else None
    # an s3:// object is read with the files beside it sharing its name; an s3:// prefix as a directory
    if scheduler and jobs > 1:
        raise click.UsageError("--jobs sizes this machine's processes; a --scheduler's cluster has its own workers")
    with local_inputs(paths) as inputs, _cluster(scheduler) as cluster:
        with _files_progress(quiet) as bar:
            progress = None if bar is None else (lambda done, total: bar(done, total, "file(s) checked"))
            job = ValidationJob(strict=strict, jobs=jobs, labels_only=labels_only, dictionaries=dictionaries,
                                settings=settings, baseline=baseline, schemas=schemas,
                                skip_non_labels=skip_non_labels,
                                schema_cache=schema_cache or str(default_schema_cache()),
                                download_schemas=not offline, root=root, cluster=cluster)
            reports = iter_reports(inputs.paths, job, progress)
            if bar is not None:
                reports = _giving_way(reports, bar)
            if verbose:  # after iter_reports has checked the paths given with --dictionary
                _tell_choices(settings, baseline_path, tuple(dictionaries), jobs, labels_only)
                log.info("PDS4 schemas: %s; cache %s; %s", ", ".join(schemas) or "shipped",
                         schema_cache or str(default_schema_cache()), "offline" if offline else "downloads allowed")
            if write_baseline_path:
                kept = [f for report in reports for f in report.findings]
                count = configuration.write_baseline(write_baseline_path, kept)
                if not quiet:
                    click.echo(f"{count} finding(s) recorded in the baseline {write_baseline_path}")
                return
            tally = Tally(settings.fail_on, dictionary=dictionary_version(tuple(dictionaries)))
            counted = _counting_baseline(reports, baseline, tally)
            findings: list[dict[str, Any]] = []
            if as_json:
                counted = _keeping_findings(counted, findings)
            if as_json and not output:
                _tally_only(counted, tally)
            elif quiet and fmt == "text" and not output:
                _failing_findings(counted, tally)
            else:
                with _output(output) as out:
                    named = cast(IO[str], _Renaming(out, inputs.shown))
                    write_stream(counted, fmt, named, tally, writer_class=_html_writer() if fmt == "html" else None)
            elapsed = time.monotonic() - started
            log.info("checked %d file(s) in %.2f s (%.0f files/s): %d error(s), %d warning(s)", tally.files, elapsed,
                     tally.files / elapsed if elapsed > 0 else 0.0, tally.errors, tally.warnings)
            if output and not quiet:  # the report is in the file: the log still says why the run failed
                click.echo(f"{terminal_safe(output)}: {tally.summary_line()}", err=True)
            if as_json:
                from ..validate.run_result import ValidationRun  # only under --json: start-up

                echo_json(ValidationRun(tally, findings, output), inputs)
            sys.exit(tally.exit_code)


@contextmanager
def _cluster(scheduler: str | None) -> Iterator[Any]:
    """The Dask client of --scheduler (as `pdsgen batch` connects), or None: this machine's processes."""
    if scheduler is None:
        yield None
        return
    from .. import __version__
    from ..batch.cluster import check_version, open_client

    with open_client(scheduler, 1) as client:
        check_version(client, __version__)
        yield client


class _Renaming:
    """A report stream naming the local copies of objects by their URLs."""

    def __init__(self, out: TextIO, rename: Callable[[str], str]) -> None:
        self.out, self.rename = out, rename

    def write(self, text: str) -> int:
        return self.out.write(self.rename(text))

    def __getattr__(self, name: str) -> Any:
        return getattr(self.out, name)


def _html_writer():
    """The review page's writer (loaded only for --format html)."""
    from ..review import HtmlWriter

    return HtmlWriter


def _tell_choices(settings: configuration.RuleSettings, baseline_path: str | None, dictionaries: tuple[str, ...],
                  jobs: int, labels_only: bool) -> None:
    """--verbose: what the run reads and which rules it applies."""
    log.info("configuration: %s", settings.source or "none (defaults)")
    log.info("data dictionary: %s", dictionary_version(dictionaries))
    kept = [rule_id for rule_id in rules() if settings.keeps(rule_id)]
    log.info("rules: %d of %d; a run fails on %s", len(kept), len(rules()),
             "warnings too" if settings.fail_on == "warning" else "errors")
    log.info("baseline: %s", baseline_path or "none")
    log.info("%d process(es); %s", jobs, "labels only" if labels_only else "labels and their data")


def _failing_findings(reports, tally: Tally) -> None:
    """--quiet text report: one line per finding that fails the run, nothing else."""
    levels = failing_severities(tally.fail_on)
    for report in reports:
        tally.add(report)
        if fails(report, tally.fail_on):
            for finding in report.findings:
                if finding.severity in levels:
                    click.echo(terminal_safe(finding_line(finding)))


def _keeping_findings(reports: Iterable[FileReport], kept: list[dict[str, Any]]) -> Iterator[FileReport]:
    """Pass reports through, keeping each finding for --json."""
    for report in reports:
        kept.extend(finding.as_dict() for finding in report.findings)
        yield report


def _tally_only(reports: Iterable[FileReport], tally: Tally) -> None:
    """--json without a report file: the run counted, nothing written but the JSON document."""
    for report in reports:
        tally.add(report)


def _counting_baseline(reports, baseline: configuration.Baseline | None, tally: Tally):
    """Pass reports through, keeping the tally's count of findings the baseline suppressed."""
    for report in reports:
        yield report
        if baseline is not None:
            tally.baseline_suppressed = baseline.suppressed
