"""`pdsgen migrate`: PDS4 labels that describe existing PDS3 products, their files unchanged."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import click

from ..migrate import migrate_products, product_labels
from . import COMMANDS
from ._output import Outcome, output_options, told
from ._profile_options import output_option


@click.command(short_help=COMMANDS["migrate"])
@output_options
@click.argument("products", nargs=-1, required=True, type=click.Path())
@output_option("outdir", "--outdir", type=click.Path(file_okay=False),
              help="Directory for the PDS4 labels and unchanged copies of the products' files.")
@click.option("--in-place", is_flag=True, help="Write each PDS4 label beside its PDS3 product; copy nothing.")
@click.option("--bundle-lid", help="Bundle LID the products' LIDs start with, urn:nasa:pds:NAME "
                                   "[default: from each product's DATA_SET_ID].")
@click.option("--collection", default="data", show_default=True, help="Collection part of the products' LIDs.")
@click.option("--overwrite", is_flag=True, help="Replace labels and copies the output already holds.")
@click.option("--root", type=click.Path(file_okay=False, exists=True),
              help="Trusted tree: files labels name may lie anywhere inside it (default: each label's directory).")
def migrate(products, outdir, in_place, bundle_lid, collection, overwrite, root) -> Outcome:
    """Describe each PDS3 product (a label, an attached-label file, or a data file beside its
    .LBL) in a PDS4 label (IM 1.24): Header for the PDS3 label, arrays and tables at their
    byte offsets, scaling, special constants, cart: for map products, the PDS3 PRODUCT_ID
    and DATA_SET_ID as aliases. Data bytes are never changed. A product PDS4 cannot describe
    exactly is refused in one line and the others go on; the exit status is then 2.

    A directory or s3:// prefix (one, alone) is a PDS3 volume: it becomes a PDS4 bundle (--bundle-lid needed)
    with data, document, browse and miscellaneous collections, the bundle label from the
    volume's catalog and a crosswalk of PDS3 PRODUCT_IDs to PDS4 LIDVIDs; the index table is
    the manifest the products are checked against.
    """
    if bool(outdir) == in_place:
        raise click.UsageError("give either -o/--output or --in-place")
    directories = [p for p in products if _is_volume(p)]
    if directories:
        if len(products) != 1:
            raise click.UsageError(f"{directories[0]} is a directory: give one PDS3 volume alone, or product labels")
        if not bundle_lid:
            raise click.UsageError("a volume becomes a bundle: give --bundle-lid urn:nasa:pds:NAME")
        if root or collection != "data":  # a volume is its own tree; its collections follow its data sets
            raise click.UsageError("--root and --collection are for product labels, not a volume")
        from ..migrate.volume import migrate_volume  # on first use: single products never load it

        with _volume_areas(products[0], outdir, in_place) as (source, inputs, area):
            result = migrate_volume(source, None if in_place else area.directory, bundle_lid=bundle_lid,
                                    in_place=in_place, overwrite=overwrite)
            return told(result, inputs, area)
    run = migrate_products(product_labels(products), outdir, bundle_lid=bundle_lid, collection=collection,
                           in_place=in_place, overwrite=overwrite, root=root)
    return told(run)  # a refused product: one error line each, the others migrated, exit status 2


def _is_volume(path: str) -> bool:
    """A local directory, or an s3:// prefix (a trailing '/', or a last name without an extension)."""
    if path.startswith("s3://"):
        return path.endswith("/") or "." not in path.rstrip("/").rsplit("/", 1)[-1]
    return Path(path).is_dir()


@contextmanager
def _volume_areas(volume: str, outdir: str | None, in_place: bool) -> Iterator[tuple[Path, Any, Any]]:
    """The volume as a local directory and the bundle's output area; s3:// VOLUME_DIR and OUTDIR
    as `pdsgen deliver` treats its trees: built from local copies, the changed files published
    with the index and manifest last."""
    from ..archive.layout import publication_rank
    from ..storage import local_inputs, tree_area

    with local_inputs([] if in_place else [volume]) as inputs, \
            tree_area(volume if in_place else outdir, publication_rank) as area:  # type: ignore[arg-type]
        yield (area.directory if in_place else Path(inputs.paths[0])), inputs, area
