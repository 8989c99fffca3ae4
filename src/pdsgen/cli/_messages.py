"""The library's messages in the command line's words.

Library messages name a parameter as Python code spells it (`product_id`,
`kind='dtm'`, `overwrite=True`: pdsgen.errors.param). On the command line the
same reference becomes the option a user types (--product-id, --kind dtm,
--overwrite). The option vocabularies are the one place that knows which option sets which
library parameter; the table here is made from them.
"""

from __future__ import annotations

import ast
import re
from functools import cache
from typing import Any

# Library parameters that are no entry of an option vocabulary: the commands' own (--profile)
# and those of deliver and validate, whose options are written in their commands.
COMMAND_OWN_OPTIONS: dict[str, str] = {
    "profile": "--profile",
    "schemas": "--schemas",
    "volume_id": "--volume-id",
    "bundle_lid": "--bundle-lid",
    "root": "--root",
    "template": "--template",
}


@cache
def library_to_option() -> dict[str, str]:
    """Library parameter -> command-line option, for every parameter a message may name: each
    vocabulary entry's own flag (products/options.py, mosaic/options.py, extras/options.py), read
    when a message is first translated (a conversion that succeeds loads no other vocabulary)."""
    from ..extras.options import EXTRAS_OPTIONS
    from ..mosaic.options import MOSAIC_OPTIONS
    from ..products.options import DTM_OPTIONS, ORTHO_OPTIONS

    table = dict(COMMAND_OWN_OPTIONS)
    for spec in (*DTM_OPTIONS, *ORTHO_OPTIONS, *MOSAIC_OPTIONS, *EXTRAS_OPTIONS):
        table.setdefault(spec.library_keyword, f"--{spec.flag}")
    return table


def __getattr__(name: str) -> Any:
    """`LIBRARY_TO_OPTION`: the table of `library_to_option`, made when first asked for."""
    if name == "LIBRARY_TO_OPTION":
        return library_to_option()
    raise AttributeError(name)


_REFERENCE = re.compile(r"`([a-z][a-z0-9_]*)(?:=([^`]*))?`")


def in_cli_words(message: str) -> str:
    """`message` with each reference to a library parameter written as its option."""
    return _REFERENCE.sub(_as_option, message)


def _as_option(match: re.Match[str]) -> str:
    name, value = match.group(1), match.group(2)
    option = library_to_option().get(name)
    if option is None:
        return match.group(0)  # not a parameter the command line has: left as written
    if value is None:
        return option
    try:
        given = ast.literal_eval(value)
    except (ValueError, SyntaxError):
        given = value
    if given is True:
        return option  # a flag
    return f"{option} {given}"


# Control characters but the tab, line breaks included (see validate/report.py terminal_safe).


def one_line(text: str) -> str:
    """`text` as one line a terminal shows as written: control characters (a line break in a
    file name, an escape sequence), bidi controls (U+202E) and a non-UTF-8 name's bytes
    escaped (encode.shown, the one encoder of terminal text), so no name can forge a line."""
    from ..encode import shown

    return shown(text)
