"""Calling a mission's writer with one options object, built from the keywords a caller gave,
and the statement its label makes.

A product's label says some things beyond its mission's fixed wording: a mosaic how its sources
were put together, an HRSC-AX tile what its heights or bands are and how its map offsets were
read. Both reach the writer as one `ProductStatement` argument, so the mission object a writer
is given is always the registered one, never a rewritten copy.
"""

from __future__ import annotations

import functools
import inspect
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .options import ProductOptions
from .result import ProductResult, checked_result

if TYPE_CHECKING:
    from ..missions import Mission

# A mission's writer: `writer(input_path, outdir, options)` (its product's result); one whose label
# can say how a mosaic's sources were put together also takes `statement=` (a ProductStatement).
MissionWriter = Callable[..., Any]


@dataclass(frozen=True)
class ProductStatement:
    """The words a writer puts in the label in place of, or after, its mission's own.

    `dtm_note`, `ortho_description`, `map_projection_note`: said instead of the mission's
    (None: the mission's). `mosaic`: how a mosaic's sources were put together, said after
    the NOTE or DESCRIPTION ("" for a product of one input).
    """

    mosaic: str = ""
    dtm_note: str | None = None
    ortho_description: str | None = None
    map_projection_note: tuple[str, ...] | None = None

    def after(self, text: str) -> str:
        """`text` followed by the mosaic's statement (unchanged when there is none)."""
        return f"{text} {self.mosaic}".strip() if self.mosaic else text

    def note(self, mission: Mission) -> str:
        """The DTM's NOTE: the tile's or the mission's, then the mosaic's statement."""
        return self.after(mission.dtm_note if self.dtm_note is None else self.dtm_note)

    def description(self, mission: Mission) -> str:
        """The orthoimage's DESCRIPTION: the tile's or the mission's, then the mosaic's statement."""
        return self.after(mission.ortho_description if self.ortho_description is None else self.ortho_description)

    def projection_note(self, mission: Mission) -> tuple[str, ...]:
        """The MAP_PROJECTION comment lines: the tile's (its offsets' reading) or the mission's."""
        return mission.map_projection_note if self.map_projection_note is None else self.map_projection_note


NO_STATEMENT = ProductStatement()  # a product of one input, described by its mission's own words


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
