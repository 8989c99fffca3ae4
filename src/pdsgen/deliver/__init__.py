"""Deliveries: a PDS3 volume (index, volume description) and/or a PDS4 bundle (collections,
inventories, browse and document labels) around pdsgen's products, with an MD5 manifest.

`make_delivery` is the API behind `pdsgen deliver` (the builder is loaded on first use); the
names and rules of a delivery's layout, which the validator's delivery checks and the review
page read too, are archive/layout.py."""

from __future__ import annotations

from typing import Any

__all__ = ["DIALECTS", "Delivery", "make_delivery"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        from . import build

        return getattr(build, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
