"""Calling a mission's writer with one options object, built from the keywords a caller gave."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Any

from .options import ProductOptions
from .result import ProductResult, checked_result

# A mission's writer: `writer(input_path, outdir, options)` (its product's result).
MissionWriter = Callable[..., Any]


def call_mission_writer(
    writer: MissionWriter,
    input_path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
) -> ProductResult:
    """`writer(input_path, outdir, options)`, whose result must be a `ProductResult`.

    The options were built by `ProductOptions.build`, which refused any keyword the profile
    does not use, in Python as on the command line, so a misplaced keyword never drops a value
    silently."""
    return checked_result(writer(input_path, outdir, options), writer)
