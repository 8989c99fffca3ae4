"""The size of a preview image made of a product: one home for the arithmetic.

The Extras (extras/decimate.py, extras/renderings.py) make a browse of a product `max_width`
wide, never wider than the product nor than a JPEG can hold with the annotated browse's margins,
its aspect kept, and a thumbnail of the browse, never enlarged. The validator asks the same
question the other way round (validate/delivery: is a delivered browse the size the Extras would
make of the delivered product, or one of an earlier version of it?), so both take it from here.
"""

from __future__ import annotations

JPEG_MAX_SIDE = 65500
ANNOTATION_ROOM = 2000  # the annotated browse adds margins; it must still fit in a JPEG


def browse_size(width: int, height: int, max_width: int) -> tuple[int, int]:
    """(width, height) of the browse of a `width` x `height` product made `max_width` wide."""
    side = JPEG_MAX_SIDE - ANNOTATION_ROOM
    browse_width = max(1, min(int(max_width), width, side))
    browse_height = max(1, round(height * browse_width / width))
    if browse_height > side:
        browse_height = side
        browse_width = max(1, round(width * browse_height / height))
    return browse_width, browse_height


def thumbnail_size(browse_width: int, browse_height: int, thumb_width: int) -> tuple[int, int]:
    """(width, height) of the thumbnail of a browse, `thumb_width` wide (never enlarged)."""
    width = max(1, min(thumb_width, browse_width))
    return width, max(1, round(browse_height * width / browse_width))
