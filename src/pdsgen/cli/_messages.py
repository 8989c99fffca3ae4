"""The library's messages in the command line's words.

Library messages name a parameter as Python code spells it (`product_id`,
`kind='dtm'`, `overwrite=True`: pdsgen.errors.param). On the command line the
same reference becomes the option a user types (--product-id, --kind dtm,
--overwrite). This table is the one place that knows which option sets which
library parameter where the names differ in more than '_' for '-'.
"""

from __future__ import annotations

import ast
import re

# library parameter -> command-line option, for every parameter a message may name
LIBRARY_TO_OPTION: dict[str, str] = {
    "product_id": "--product-id",
    "source_product_ids": "--source-product-id",
    "observation_id": "--observation-id",
    "source_dtm_id": "--source-dtm-id",
    "institution": "--institution",
    "params": "--params",
    "profile": "--profile",
    "kind": "--kind",
    "label": "--label",
    "bits": "--bits",
    "value_range": "--range",
    "vertical_datum": "--vertical-datum",
    "areoid": "--areoid",
    "precision": "--precision",
    "reproject_input": "--reproject",
    "source_labels": "--source-label",
    "offset_convention": "--offset-convention",
    "vicar_offsets": "--vicar-offsets",
    "allow_dictionary_deviations": "--allow-dictionary-deviations",
    "overwrite": "--overwrite",
    "schemas": "--schemas",
    "thumb_width": "--thumb-width",
    "azimuth": "--azimuth",
    "altitude": "--altitude",
    "exaggeration": "--exaggeration",
    "volume_id": "--volume-id",
    "bundle_lid": "--bundle-lid",
    "order": "--order",
    "resampling": "--resampling",
    "nodata": "--nodata",
}

_REFERENCE = re.compile(r"`([a-z][a-z0-9_]*)(?:=([^`]*))?`")


def in_cli_words(message: str) -> str:
    """`message` with each reference to a library parameter written as its option."""
    return _REFERENCE.sub(_as_option, message)


def _as_option(match: re.Match[str]) -> str:
    name, value = match.group(1), match.group(2)
    option = LIBRARY_TO_OPTION.get(name)
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
