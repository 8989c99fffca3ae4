"""Mosaics: strips or tiles of one kind, placed as gdal_merge.py places them, written as one product.

plan.py decides the grid and where each input lies; vrt.py presents the result as a
virtual raster; write.py hands it to the profile's existing writer.
"""

from __future__ import annotations

from .plan import ORDERS, RESAMPLING_METHODS
from .write import KINDS, write_mosaic

__all__ = ["KINDS", "ORDERS", "RESAMPLING_METHODS", "write_mosaic"]
