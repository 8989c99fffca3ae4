"""What a product's label says of its making beyond its mission's fixed wording.

A mosaic says how its sources were put together; an HRSC-AX tile what its heights or bands
are and how its map offsets were read. Both reach the writer as one `ProductStatement` argument,
so the mission object a writer is given is always the registered one, never a rewritten copy.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..missions import Mission


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

__all__ = ["NO_STATEMENT", "ProductStatement"]
