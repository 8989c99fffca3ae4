"""`pdsgen extras`: preview JPEGs and README.TXT for DTM and orthoimage products."""

from __future__ import annotations

import click

from ..extras import DEFAULT_CREDIT, KINDS, make_extras
from ..missions.hrsc import CREDIT as HRSC_CREDIT
from ..profiles import profile_names


@click.command(short_help="Make browse, annotated browse and thumbnail JPEGs and README.TXT.")
@click.argument("products", metavar="PRODUCT...", nargs=-1, required=True,
                type=click.Path(dir_okay=False))
@click.option("-o", "--outdir", required=True, type=click.Path(file_okay=False),
              help="Output directory.")
@click.option("--credit", help=f"Credit line on annotated images [default: params CREDIT, else the "
                               f"profile's (hrsc: {HRSC_CREDIT!r}), else {DEFAULT_CREDIT!r}].")
@click.option("--params", "params_file", type=click.Path(dir_okay=False),
              help="PVL or TOML file of producer keywords (contact, known artifacts ...).")
@click.option("--browse-width", type=int,
              help="Browse width in pixels [default: 1024 for DTMs, 2048 for orthoimages].")
@click.option("--thumb-width", type=int, default=128, show_default=True,
              help="Thumbnail width in pixels.")
@click.option("--azimuth", type=float, default=315.0, show_default=True,
              help="Light direction for shaded relief, degrees clockwise from image up.")
@click.option("--altitude", type=float, default=45.0, show_default=True,
              help="Light elevation above the horizon for shaded relief, degrees.")
@click.option("--exaggeration", type=float,
              help="Vertical exaggeration of the shaded relief [default: 1, raised "
                   "automatically when the relief is too faint at preview scale].")
@click.option("--kind", type=click.Choice(KINDS),
              help="Treat every PRODUCT as this kind [default: from the label or data type].")
@click.option("--profile", type=click.Choice(profile_names()),
              help="Mission conventions (credit line) [default: from each product's label].")
@click.option("--overwrite", is_flag=True, help="Replace existing Extras files.")
def extras(products, outdir, credit, params_file, browse_width, thumb_width, azimuth, altitude,
           exaggeration, kind, profile, overwrite) -> None:
    """Write the Extras of each PRODUCT (a PDS3 .IMG/.LBL/.JP2 or a GeoTIFF) into OUTDIR."""
    written = make_extras(products, outdir, credit=credit, params=params_file,
                          browse_width=browse_width, thumb_width=thumb_width, azimuth=azimuth,
                          altitude=altitude, exaggeration=exaggeration, kind=kind,
                          profile=profile, overwrite=overwrite)
    for path in written:
        click.echo(str(path))
