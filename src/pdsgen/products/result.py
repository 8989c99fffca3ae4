"""The one shape every product result has, whichever mission wrote it."""

from __future__ import annotations

from pathlib import Path
from typing import Protocol, runtime_checkable

from ..geo.geometry import MapGeometry


@runtime_checkable
class ProductResult(Protocol):
    """What a writer returns: the product ID, the files it wrote, and the map geometry."""

    @property
    def product_id(self) -> str: ...

    @property
    def files(self) -> tuple[Path, ...]: ...

    @property
    def geometry(self) -> MapGeometry: ...
