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
@click.option("--label", "label", type=click.Choice([d.value for d in Dialect]), default=None,
              help="pds3: a PDS3 volume (DATA/, EXTRAS/, INDEX/INDEX.TAB + INDEX.LBL, VOLDESC.CAT, AAREADME.TXT); "
                   "pds4: a PDS4 bundle (bundle, data/browse/document collections with inventories, browse and "
                   "document labels); both: the two in one tree.  [default: pds3]")
@click.option("--pds3", "old_dialect", flag_value=Dialect.PDS3.value, hidden=True)
@click.option("--pds4", "old_dialect", flag_value=Dialect.PDS4.value, hidden=True)
@click.option("--both", "old_dialect", flag_value=Dialect.BOTH.value, hidden=True)
@output_option("out", "--out", type=click.Path(file_okay=False),
              help="Delivery directory [default: DIRECTORY itself, its products moved into the layout].")
@click.option("--volume-id", help="PDS3 VOLUME_ID (up to 11 characters) [default: the previous delivery's].")
@click.option("--bundle-lid", help="PDS4 bundle LID, urn:nasa:pds:NAME [default: the previous delivery's].")
@click.option("--text", "text", type=click.Path(dir_okay=False),
              help="TOML file whose [delivery] table gives the title, description (multi-line), authors "
                   "(list of \"Last, F.\"), readme (AAREADME.TXT's own text) and optional keywords; what it "
                   "does not give is kept from the previous delivery where a person wrote it.")
@click.option("--new-version", is_flag=True,
              help="Give the volume, the bundle and what changed the next version (otherwise versions "
                   "advance only once the delivery is released: a .released file at its root).")
def deliver(directory, label, old_dialect, out, volume_id, bundle_lid, text, new_version) -> Outcome:
    """Make DIRECTORY's products (with their Extras, README.TXT and JP2INFO.TXT) a delivery.

    Run it again after adding or replacing products: the index, inventories, versions and
    the MD5SUMS.TXT manifest are brought up to date, and nothing stale stays.
    Then check the whole delivery with `pdsgen validate OUT`.
    """
    dialect = _dialect(label, old_dialect)
    # s3:// DIRECTORY and OUT: built from local copies; published changed files first, the index and MD5SUMS.TXT last
    with local_inputs([directory] if out is not None else []) as inputs, \
            tree_area(out if out is not None else directory, publication_rank) as area:
        source = inputs.paths[0] if out is not None else area.directory
        result = make_delivery(source, area.directory, dialect=dialect, volume_id=volume_id, bundle_lid=bundle_lid,
                               shown_as=area.shown(str(area.directory)), text=text, new_version=new_version)
        return told(result, inputs, area)


def _dialect(label: str | None, old_dialect: str | None) -> str:
    """--label, or the older --pds3/--pds4/--both it replaces (still accepted); both given must agree."""
    if label is not None and old_dialect is not None and label != old_dialect:
        raise click.UsageError(f"--label {label} and --{old_dialect} disagree; give --label only")
    return label or old_dialect or Dialect.PDS3.value
