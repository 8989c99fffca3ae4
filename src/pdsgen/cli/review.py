"""`pdsgen review`: the review page of a delivery (or any directory of products)."""

from __future__ import annotations

import click

from . import COMMANDS
from ._output import Outcome, output_options, told
from ._profile_options import output_option


@click.command(short_help=COMMANDS["review"])
@output_options
@click.argument("directory", type=click.Path(file_okay=False))
@output_option("page", "--out", type=click.Path(dir_okay=False),
              help="The page to write [default: DIRECTORY/REVIEW.html].")
@click.option("--labels-only", is_flag=True, help="Check label text only; do not open the data files.")
@click.option("--jobs", "-j", type=click.IntRange(min=1), default=1, show_default=True,
              help="Files checked in parallel (processes).")
def review(directory, page, labels_only, jobs) -> Outcome:
    """Check DIRECTORY's products as `pdsgen validate` does and write one self-contained HTML page
    to look at them: summary, footprints on a map of the body, and per product its previews,
    label facts, index row, files and findings (filterable). The page opens offline, from the
    delivery, in any browser. A delivery of more than 500 products is reviewed in pages
    (REVIEW.html with the summary and the map, then REVIEW-2.html ...), each quick to open.
    """
    from ..review import write_review

    return told(write_review(directory, page, labels_only=labels_only, jobs=jobs))
