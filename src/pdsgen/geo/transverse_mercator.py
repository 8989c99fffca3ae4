"""A Transverse Mercator grid in a PDS3 label: folded into the keywords, stated in a comment.

PDS3 has no keyword for a grid's scale factor or false easting/northing, and GDAL's PDS
reader applies scale factor 1 and no false origin. pdsgen's writer therefore folds them
in (geometry.py's module docstring: offsets from the natural origin, MAP_SCALE the grid
spacing divided by the scale factor) and states the true grid in the projection object's
comment; label_georef.py reads that statement back to unfold the label into the grid.
Writer and reader take the wording from here, so they cannot drift apart.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

# The note in the label's IMAGE_MAP_PROJECTION object, one comment per line. GRID_STATEMENT
# is the part read back: {k}, {east} and {north} are the grid's scale factor and its false
# easting and northing in metres.
_NOTE_BEFORE = (
    "NOTE: TRANSVERSE MERCATOR on the ellipsoid of A_AXIS_RADIUS and",
    "C_AXIS_RADIUS; latitudes are geodetic (PLANETOGRAPHIC). The map",
)
GRID_STATEMENT = (
    "grid has scale factor {k} on the central meridian,",
    "false easting {east:.3f} m, false northing {north:.3f} m.",
)
_NOTE_AFTER = (
    "PDS3 has no keywords for these; they are folded in: the offsets",
    "count from the natural origin (CENTER_LATITUDE, CENTER_LONGITUDE)",
    "and MAP_SCALE is the grid spacing divided by the scale factor",
    "(ground metres per pixel on the central meridian), so grid metres",
    "= (pixels * MAP_SCALE) * scale factor + false easting/northing.",
    "A reader applying TRANSVERSE MERCATOR with scale factor 1 (GDAL)",
    "thus places every pixel on its ground position.",
)
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_COMMENT_BREAK = r"(?:\s|\*/|/\*)*"  # between words: spaces, line ends, comment delimiters
_PLACEHOLDER = re.compile(r"\{(?P<name>\w+)(?::[^}]*)?\}")


@dataclass(frozen=True)
class TransverseMercatorGrid:
    """The grid a folded Transverse Mercator label stands for: what PDS3 cannot say."""

    scale_factor: float
    false_easting: float  # metres
    false_northing: float


UNFOLDED = TransverseMercatorGrid(1.0, 0.0, 0.0)  # the grid as PDS3 (and GDAL) read the keywords


def grid_note(scale_factor: float, false_easting: float, false_northing: float) -> tuple[str, ...]:
    """The label comment lines stating a folded Transverse Mercator grid."""
    statement = tuple(line.format(k=scale_factor, east=false_easting, north=false_northing)
                      for line in GRID_STATEMENT)
    return tuple(f"/* {line} */" for line in (*_NOTE_BEFORE, *statement, *_NOTE_AFTER))


def _statement_pattern() -> re.Pattern[str]:
    """GRID_STATEMENT as a pattern: its words in order, any comment break between them."""
    words = " ".join(GRID_STATEMENT).split()
    parts = []
    for word in words:
        placeholder = _PLACEHOLDER.fullmatch(word)
        parts.append(f"(?P<{placeholder['name']}>{_NUMBER})" if placeholder else re.escape(word))
    return re.compile(_COMMENT_BREAK.join(parts))


_GRID_STATEMENT_RE = _statement_pattern()


class GridNoteError(ValueError):
    """The label states a Transverse Mercator grid that cannot be a grid."""


def read_grid_note(label_text: str) -> TransverseMercatorGrid | None:
    """The true grid a label's comment states (pdsgen's writer), or None without the statement."""
    match = _GRID_STATEMENT_RE.search(label_text)
    if match is None:
        return None
    grid = TransverseMercatorGrid(float(match["k"]), float(match["east"]), float(match["north"]))
    if not (math.isfinite(grid.scale_factor) and grid.scale_factor > 0
            and math.isfinite(grid.false_easting) and math.isfinite(grid.false_northing)):
        raise GridNoteError(f"the label's Transverse Mercator grid note is unusable ({match[0]!r})")
    return grid
