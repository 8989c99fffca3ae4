"""`pdsgen batch`: run a manifest of product jobs on Dask (local processes or a cluster)."""

from __future__ import annotations

import logging
import os
import sys
from importlib.resources import files

import click

from ..batch import ManifestError, Settings, load_manifest, plan, run
from ..batch.cluster import local_workers
from ..batch.manifest import parse_size
from ..batch.resident import DEFAULT_MAX_GROWTH_MB, DEFAULT_MAX_JOBS
from ..progress import wanted as progress_wanted
from ..storage import display
from . import COMMANDS
from ._messages import one_line
from ._output import log_to_stderr
from ._profile_options import output_option

log = logging.getLogger("pdsgen.batch")


@click.command(short_help=COMMANDS["batch"])
@click.argument("manifest", required=False, type=click.Path(dir_okay=False))
@output_option("outdir", "--outdir", type=click.Path(file_okay=False),
              help="Batch output directory [default: the manifest's [batch] outdir].")
@click.option("--scheduler", metavar="ADDRESS",
              help="Run on this Dask scheduler (e.g. tcp://10.0.0.5:8786) [default: a local cluster].")
@click.option("--workers", type=click.IntRange(min=1),
              help="Local worker processes [default: one per core / --threads-per-job].")
@click.option("--threads-per-job", type=click.IntRange(min=1),
              help="Threads each job's GDAL and JPEG 2000 encoder use [default: [batch] threads, else 1].")
@click.option("--dry-run", is_flag=True, help="Print the plan (to do / done / blocked) and run nothing.")
@click.option("--retries", type=click.IntRange(min=0),
              help="Re-runs of a job that crashed or timed out [default: [batch] retries, else 0].")
@click.option("--log-dir", type=click.Path(file_okay=False),
              help="One log per job and summary.json [default: OUTDIR/.pdsgen-batch/logs].")
@click.option("--child-jobs", type=click.IntRange(min=1), default=DEFAULT_MAX_JOBS, show_default=True,
              help="Jobs a worker slot's resident job process runs before it is replaced (1: a new process "
                   "per job).")
@click.option("--child-growth", metavar="SIZE", default=f"{DEFAULT_MAX_GROWTH_MB:g} MB", show_default=True,
              help="Replace a resident job process once its memory has grown by SIZE over its size at start.")
@click.option("--example", is_flag=True, help="Print a commented example manifest and exit.")
@click.option("-q", "--quiet", is_flag=True,
              help="Print only failed and blocked jobs (and errors); no progress, no summary line.")
@click.option("-v", "--verbose", is_flag=True,
              help="Print the plan first and one line per finished job, with timings, even on a terminal.")
def batch(manifest, outdir, scheduler, workers, threads_per_job, dry_run, retries, log_dir, child_jobs, child_growth,
          example, quiet, verbose) -> None:
    """Run the jobs of MANIFEST (TOML: [[dtm]], [[ortho]], [[mosaic]], [[extras]], [[validate]] tables
    whose keys are those commands' options) on Dask, each job in its own process.
    Finished jobs are skipped on a re-run. Exit status: 0 all jobs succeeded,
    1 some failed (each named), 2 bad manifest or cluster."""
    if example:
        click.echo(files("pdsgen.batch").joinpath("example.toml").read_text(encoding="utf-8"), nl=False)
        return
    if manifest is None:
        raise click.UsageError("give a MANIFEST (see pdsgen batch --example)")
    if scheduler and workers:
        raise click.UsageError("--workers sizes the local cluster; a --scheduler's cluster has its own workers")
    if quiet and verbose:
        raise click.UsageError("--quiet and --verbose exclude each other")
    growth = parse_size(child_growth)
    if growth is None:
        raise click.BadParameter(f"{child_growth!r} is not a size such as '512 MB'", param_hint="'--child-growth'")
    if verbose:
        log_to_stderr()
    overrides = {k: v for k, v in (("threads", threads_per_job), ("retries", retries)) if v is not None}
    try:
        checked = load_manifest(manifest, outdir, overrides)
    except ManifestError as exc:
        for line in exc.lines():
            click.echo(f"pdsgen: error: {one_line(line)}", err=True)
        sys.exit(2)
    threads = max(j.threads for j in checked.jobs)
    settings = Settings(scheduler=scheduler, workers=workers or local_workers(threads), log_dir=log_dir,
                        child_jobs=child_jobs, child_growth_mb=growth / 1e6)
    if dry_run:
        plan(checked, settings, sys.stdout)
        return
    if verbose:
        log.info("%d job(s) on %s", len(checked.jobs), scheduler or f"a local cluster of {settings.workers} worker(s)")
        plan(checked, settings, sys.stderr)
    summary = _run(checked, settings, quiet, verbose)
    counts = summary.data["counts"]
    if not quiet:
        click.echo(f"{len(summary.data['jobs'])} jobs in {summary.data['seconds']:.1f} s: {counts['done']} done, "
                   f"{counts['skipped']} already done, {counts['failed']} failed, {counts['blocked']} blocked; "
                   f"summary {display(summary.path)}", err=True)
    for job in summary.failed:
        click.echo(one_line(f"pdsgen: {job['status']}: {job['kind']} {job['id']}: {job['error']}"), err=True)
    sys.exit(summary.exit_code)


def _run(checked, settings: Settings, quiet: bool, verbose: bool):
    """Run with the progress the output mode asks for: none (--quiet; failures are printed
    after the run), one line per job (--verbose, or not a terminal), else a bar."""
    if quiet:
        with open(os.devnull, "w") as nowhere:
            return run(checked, settings, progress_stream=nowhere, bar=False)
    return run(checked, settings, bar=False if verbose else progress_wanted())

