"""Options that only some profiles use: giving one to another profile is an error.

A command's --help lists every option of every profile; silently ignoring one a
profile has no use for would let a user believe it took effect.
"""

from __future__ import annotations

import click
from click.core import ParameterSource

from ..errors import PdsgenError
from ._output import OUTPUT_OPTIONS


def refuse_unused_options(ctx: click.Context, profile: str, used: set[str]) -> None:
    """PdsgenError naming the first option given on the command line that `profile` does not use."""
    for param in ctx.command.params:
        if param.name in used or param.name in OUTPUT_OPTIONS or param.name == "profile" \
                or not isinstance(param, click.Option):
            continue
        if ctx.get_parameter_source(param.name) not in (ParameterSource.DEFAULT, None):
            flag = max(param.opts, key=len)
            raise PdsgenError(None, f"{flag} does not apply to --profile {profile}")


# Library keyword -> click parameter name, where they differ.
_CLI_NAMES = {"source_product_ids": "source_ids", "params": "params_file", "version": "product_version",
              "reproject_input": "reproject", "allow_dictionary_deviations": "allow_deviations"}


def profile_options(given: dict[str, object], used: set[str]) -> dict[str, object]:
    """The library keywords (with their values) of the options `used` by a profile."""
    return {name: value for name, value in given.items() if _CLI_NAMES.get(name, name) in used}


# Options `pdsgen mosaic` shares with `pdsgen dtm` and `pdsgen ortho`.
vicar_offsets_option = click.option(
    "--vicar-offsets", type=click.Choice(["standard", "dlr"]), default="standard", show_default=True,
    help="hrsc-ax: how the tile's VICAR MAP offsets count: from the centre of pixel 1,1 as the HRSC-AX "
         "image description defines them (GDAL reads them so), or DLR's HRSC Mars counting, one pixel further.")
allow_deviations_option = click.option(
    "--allow-dictionary-deviations", "allow_deviations", is_flag=True, default=None,
    help="Keep label values that break the PDS3 data dictionary (warned once) instead of refusing the product.")


def label_fidelity_options(command):
    """The options of `pdsgen dtm` and `pdsgen ortho` about what their labels carry:
    HRSC source labels and offset convention, HRSC-AX tile offsets, and keeping dictionary deviations."""
    options = [
        click.option("--source-label", "source_labels", multiple=True, type=click.Path(dir_okay=False),
                     help="hrsc: level-2/3 label whose identification, time and orbit keywords the "
                          "product carries; hrsc-ax: XML image label of the tile's MAP/DTM keywords "
                          "and survey date; repeat for each source."),
        click.option("--offset-convention", type=click.Choice(["standard", "dlr"]), default="standard",
                     show_default=True, help="hrsc: PDS3 standard projection offsets (GDAL reads them "
                                             "exactly) or DLR's own, one pixel apart."),
        vicar_offsets_option,
        allow_deviations_option,
    ]
    for option in reversed(options):
        command = option(command)
    return command
