"""Deliveries: a PDS3 volume (index, volume description) and/or a PDS4 bundle (collections,
inventories, browse and document labels) around pdsgen's products, with an MD5 manifest.

`make_delivery` is the API behind `pdsgen deliver`; `layout` holds the names and rules the
validator's delivery checks read."""

from __future__ import annotations

from .build import DIALECTS, Delivery, make_delivery

__all__ = ["DIALECTS", "Delivery", "make_delivery"]
