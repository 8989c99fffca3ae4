"""Options that only some profiles use: giving one to another profile is an error.

A command's --help lists every option of every profile; silently ignoring one a
profile has no use for would let a user believe it took effect.
"""

from __future__ import annotations

import click
from click.core import ParameterSource

from ..errors import PdsgenError


def refuse_unused_options(ctx: click.Context, profile: str, used: set[str]) -> None:
    """PdsgenError naming the first option given on the command line that `profile` does not use."""
    for param in ctx.command.params:
        if param.name in used or param.name == "profile" or not isinstance(param, click.Option):
            continue
        if ctx.get_parameter_source(param.name) not in (ParameterSource.DEFAULT, None):
            flag = max(param.opts, key=len)
            raise PdsgenError(None, f"{flag} does not apply to --profile {profile}")


# Library keyword -> click parameter name, where they differ.
_CLI_NAMES = {"source_product_ids": "source_ids", "params": "params_file", "version": "product_version",
              "reproject_input": "reproject"}


def profile_options(given: dict[str, object], used: set[str]) -> dict[str, object]:
    """The library keywords (with their values) of the options `used` by a profile."""
    return {name: value for name, value in given.items() if _CLI_NAMES.get(name, name) in used}
