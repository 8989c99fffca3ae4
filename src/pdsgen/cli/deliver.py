"""`pdsgen deliver`: a PDS3 volume and/or a PDS4 bundle around a directory of products."""

from __future__ import annotations

import click

from ..archive.layout import publication_rank
from ..deliver import make_delivery
from ..dialect import Dialect
from ..storage import local_inputs, tree_area
from . import COMMANDS
from ._output import Outcome, output_options, told
from ._profile_options import output_option


@click.command(short_help=COMMANDS["deliver"])
@output_options
@click.argument("directory", type=click.Path(file_okay=False))
@click.option("--pds3", "dialect", flag_value=Dialect.PDS3, default=True,
              help="A PDS3 volume: DATA/, EXTRAS/, INDEX/INDEX.TAB + INDEX.LBL, VOLDESC.CAT, AAREADME.TXT [default].")
@click.option("--pds4", "dialect", flag_value=Dialect.PDS4,
              help="A PDS4 bundle: bundle, data/browse/document collections with inventories, browse "
                   "and document labels.")
@click.option("--both", "dialect", flag_value=Dialect.BOTH, help="The PDS3 volume and the PDS4 bundle in one tree.")
@output_option("out", "--out", type=click.Path(file_okay=False),
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
        return told(result, inputs, area)
