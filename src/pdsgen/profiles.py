"""The registered profile names, as the CLI's --profile choices list them.

The profiles themselves are the missions (`pdsgen.missions`, one module per mission);
their naming helpers are imported from there.
"""

from __future__ import annotations

from .missions import mission_names


def profile_names() -> list[str]:
    """The registered profile names, sorted (the CLI's --profile choices)."""
    return sorted(mission_names())


__all__ = ["profile_names"]
