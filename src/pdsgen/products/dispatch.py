"""Calling a mission's writer with one options object, built from the keywords a caller gave."""

from __future__ import annotations

import functools
import inspect
import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from .options import ProductOptions
from .result import ProductResult, checked_result

if TYPE_CHECKING:
    from .statement import ProductStatement

# A mission's writer: `writer(input_path, outdir, options)` (its product's result); one whose label
# can say how a mosaic's sources were put together also takes `statement=` (products/statement.py).
MissionWriter = Callable[..., Any]


def stating(writer: MissionWriter, statement: ProductStatement | None) -> MissionWriter:
    """`writer` with the `statement` its label makes, the one way a statement reaches a writer
    (None: the writer as it is, its label in the mission's own words). A mission's writer without
    a `statement` parameter writes its label in its own words, as it did before writers took one."""
    if statement is None or "statement" not in inspect.signature(writer).parameters:
        return writer
    return functools.partial(writer, statement=statement)


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
