"""`pdsgen deliver`: a PDS3 volume and/or a PDS4 bundle around a directory of products."""

from __future__ import annotations

import click

from ..archive.layout import REVIEW_PAGE, publication_rank
from ..deliver import make_delivery
from ..deliver.build import Delivery
from ..dialect import Dialect
from ..storage import local_inputs, tree_area
from . import COMMANDS
from ._output import Outcome, output_options


@click.command(short_help=COMMANDS["deliver"])
@output_options
@click.argument("directory", type=click.Path(file_okay=False))
@click.option("--pds3", "dialect", flag_value=Dialect.PDS3, default=True,
              help="A PDS3 volume: DATA/, EXTRAS/, INDEX/INDEX.TAB + INDEX.LBL, VOLDESC.CAT, AAREADME.TXT [default].")
@click.option("--pds4", "dialect", flag_value=Dialect.PDS4,
              help="A PDS4 bundle: bundle, data/browse/document collections with inventories, browse "
                   "and document labels.")
@click.option("--both", "dialect", flag_value=Dialect.BOTH, help="The PDS3 volume and the PDS4 bundle in one tree.")
@click.option("-o", "--out", type=click.Path(file_okay=False),
              help="Delivery directory [default: DIRECTORY itself, its products moved into the layout].")
@click.option("--volume-id", help="PDS3 VOLUME_ID (up to 11 characters) [default: the previous delivery's].")
@click.option("--bundle-lid", help="PDS4 bundle LID, urn:nasa:pds:NAME [default: the previous delivery's].")
def deliver(directory, dialect, out, volume_id, bundle_lid) -> Outcome:
    """Make DIRECTORY's products (with their Extras, README.TXT and JP2INFO.TXT) a delivery.

    Run it again after adding or replacing products: the index, inventories, versions and
    the MD5SUMS.TXT manifest are brought up to date, and nothing stale stays.
    Then check the whole delivery with `pdsgen validate OUT`.
    """
    # s3:// DIRECTORY and OUT: built from local copies; published changed files first, the index and MD5SUMS.TXT last
    with local_inputs([directory] if out is not None else []) as inputs, \
            tree_area(out if out is not None else directory, publication_rank) as area:
        source = inputs.paths[0] if out is not None else area.directory
        result = make_delivery(source, area.directory, dialect=dialect, volume_id=volume_id, bundle_lid=bundle_lid,
                               shown_as=area.shown(str(area.directory)))
        outcome = _outcome(result)
    return Outcome(area.shown([inputs.shown(line) for line in outcome.lines]), area.shown(outcome.summary),
                   tuple(area.shown(inputs.shown(line)) for line in outcome.warnings))


def _outcome(result: Delivery) -> Outcome:
    lines = [f"DELIVERY {result.path}: {result.products} data product(s), {result.previews} preview(s), "
             f"{result.documents} document(s), {result.files} file(s) in {result.path / 'MD5SUMS.TXT'}"]
    if result.volume_id:
        lines.append(f"PDS3     volume {result.volume_id}: INDEX/INDEX.TAB + INDEX.LBL, VOLDESC.CAT, AAREADME.TXT "
                     "(fill in their [TO BE WRITTEN: ...] text)")
    if result.bundle_lid:
        lines.append(f"PDS4     bundle {result.bundle_lid}::{result.bundle_version}, "
                     f"{len(result.changed)} product(s) new or with a new version")
    lines.append(f"CHECK    pdsgen validate {result.path}")
    lines.append(f"REVIEW   {result.path / REVIEW_PAGE} (open it in a browser; not in the manifest)")
    summary = {"command": "deliver", "path": str(result.path), "dialect": str(result.dialect),
               "products": result.products, "previews": result.previews, "documents": result.documents,
               "files": result.files, "volume_id": result.volume_id, "bundle_lid": result.bundle_lid,
               "bundle_version": result.bundle_version, "changed": result.changed,
               "skipped": [str(p) for p in result.skipped]}
    where = "left where it is, outside the layout" if result.in_place else "not delivered"
    unclaimed = tuple(f"{path}: no label names it and no Extras rule claims it; {where}"
                      for path in result.skipped)
    return Outcome(lines, summary, unclaimed)
