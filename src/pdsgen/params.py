"""Producer and data-set keywords from a `--params` file (PVL or TOML).

The allowed keywords and their kinds are listed in `schemas/params.toml`; an
unknown keyword is refused so that a typo never silently drops a value from a
delivery's labels.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from functools import cache
from pathlib import Path
from typing import Any

from .encode import check_pvl_keyword, check_pvl_string
from .errors import PdsgenError, param
from .resources import schemas_dir

ParamValue = str | list[str] | dict[str, str | int | float]

# Label lines hold 78 characters and wrap between words only; after the aligned
# `KEYWORD = "` (about 30 columns) this is the longest word sure to fit on a line.
LONGEST_WORD = 45

# The keywords that say whose product it is and where it comes from: what a params file states and a
# profile may leave "UNK" (a product made without one warns; a delivery's DLV-007 reports each).
IDENTIFICATION_KEYWORDS = ("DATA_SET_ID", "DATA_SET_NAME", "PRODUCER_INSTITUTION_NAME", "PRODUCER_ID",
                           "PRODUCER_FULL_NAME", "INSTRUMENT_HOST_NAME", "INSTRUMENT_HOST_ID", "INSTRUMENT_NAME",
                           "INSTRUMENT_ID", "RATIONALE_DESC")

_VERSION_RE = re.compile(r"^\d+(\.\d+)*$")
_IDENTIFIER_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.\-]*$")


@cache
def params_schema() -> dict[str, dict[str, Any]]:
    """The keyword table of schemas/params.toml."""
    from .bounded import load_toml

    return load_toml(schemas_dir() / "params.toml")


def check_version(version: str) -> str:
    """PRODUCT_VERSION_ID: digits separated by dots, e.g. 1.0 (never empty)."""
    text = str(version).strip()
    if not _VERSION_RE.match(text):
        raise PdsgenError(None, f"product version must look like 1.0, got {version!r}")
    return text


def check_source_id(value: object, option: str = "source_product_ids") -> str:
    """A source product ID given by the caller: ASCII letters, digits, '_', '.', '-' only.

    Refused rather than quoted, so a space, quote, newline or non-ASCII character
    from a shell mistake never reaches a label. `option`: the parameter it was given as.
    """
    if not isinstance(value, str) or not _IDENTIFIER_RE.fullmatch(value):
        raise PdsgenError(None, f"{param(option)} {value!r} is not a product ID "
                                "(ASCII letters, digits, '_', '.' and '-' only)")
    return value


def source_ids(given: Sequence[str], keywords: Mapping[str, ParamValue]) -> list[str]:
    """SOURCE_PRODUCT_ID values: those given (checked), else the params file's (checked on load)."""
    checked = [check_source_id(item) for item in given]
    listed = keywords.get("SOURCE_PRODUCT_ID", [])
    return checked or ([str(s) for s in listed] if isinstance(listed, list) else [str(listed)])


def resolve_params(params: str | os.PathLike[str] | Mapping[str, ParamValue] | None) -> dict[str, ParamValue]:
    """Keywords given as a mapping (Python callers) or as a params file path (the CLI)."""
    return dict(params) if isinstance(params, Mapping) else load_params(params)


def load_params(path: str | os.PathLike[str] | None) -> dict[str, ParamValue]:
    """Read and check a params file; None gives an empty set."""
    if path is None:
        return {}
    path = Path(path)
    if not path.exists():
        raise PdsgenError(path, "params file not found")
    raw = _read_toml(path) if path.suffix.lower() == ".toml" else _read_pvl(path)
    return {key: _check_value(path, key, value) for key, value in raw.items()}


def _read_toml(path: Path) -> dict[str, Any]:
    from .bounded import load_toml

    data = load_toml(path, what="params file")
    return {key.upper(): value for key, value in data.items()}


def _read_pvl(path: Path) -> dict[str, Any]:
    from .bounded import load_pvl

    module = load_pvl(path, what="params file")
    return {str(key).upper(): value for key, value in module.items()}


def _check_value(path: Path, key: str, value: Any) -> ParamValue:
    schema = params_schema()
    if key not in schema:
        known = ", ".join(sorted(schema))
        raise PdsgenError(path, f"unknown keyword {key}; known keywords: {known}")
    kind = schema[key]["kind"]
    if kind == "table":
        if not isinstance(value, Mapping) or not value:
            raise PdsgenError(path, f"{key} must be a group (PVL) or table (TOML) of name = value pairs")
        table: dict[str, str | int | float] = {}
        for name, item in value.items():
            if isinstance(item, bool) or not isinstance(item, (str, int, float)):
                raise PdsgenError(path, f"{key}.{name} must be a single text or number value")
            check_pvl_keyword(str(name), key, path)  # it becomes a keyword of the product's metadata
            if isinstance(item, str):
                check_pvl_string(item, f"{key}.{name}", path)
            table[str(name)] = item
        return table
    if kind == "list":
        items = list(value) if isinstance(value, (list, tuple)) else [value]
        bad = [item for item in items if not isinstance(item, str) or not _IDENTIFIER_RE.fullmatch(item)]
        if bad or not items:
            raise PdsgenError(path, f"{key} must be product identifiers, got {bad or value!r}")
        return items
    if kind == "flag":
        flag = str(value).strip().lower()
        if flag not in ("true", "false"):
            raise PdsgenError(path, f"{key} must be true or false, got {value!r}")
        return flag
    if isinstance(value, (dict, list, tuple)):
        raise PdsgenError(path, f"{key} must be a single value")
    text = check_pvl_string(str(value), key, path)  # a label value: refused here, naming the file
    if kind == "version" and not _VERSION_RE.match(text):
        raise PdsgenError(path, f"{key} must look like 1.0, got {text!r}")
    longest = max(text.split(), key=len, default="")
    if len(longest) > LONGEST_WORD:
        raise PdsgenError(path, f"{key} has a word of {len(longest)} characters ({longest[:20]}...); label lines "
                                f"wrap only between words, so keep words to {LONGEST_WORD} characters")
    return " ".join(text.split())
