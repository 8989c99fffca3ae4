"""Calling a mission's writer with the options a caller gave, refusing those it does not take."""

from __future__ import annotations

import inspect
import os
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from ..errors import ParamsError
from .result import ProductResult, checked_result


def call_mission_writer(
    writer: Callable[..., Any],
    profile: str,
    input_path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    outdir: str | os.PathLike[str],
    options: Mapping[str, Any],
) -> ProductResult:
    """`writer(input_path, outdir, **options)`, after checking each option is one it takes;
    its result must be a `ProductResult`.

    An option the profile does not use is refused rather than ignored, in Python
    as on the command line, so a misplaced keyword never drops a value silently.
    """
    accepted = inspect.signature(writer).parameters
    unused = sorted(name for name in options if name not in accepted)
    if unused:
        raise ParamsError(None, f"the {profile} profile does not use {', '.join(unused)}")
    return checked_result(writer(input_path, outdir, **options), writer)
