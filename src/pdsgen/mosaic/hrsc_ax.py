"""HRSC-AX tiles as mosaic inputs: each tile read by the HRSC-AX reader (its grid from the
VICAR MAP group, its heights' scaling), presented to the mosaic as its own VRT.

The HRSC-AX mission names this reader (`Mission.mosaic_reader`), so `write_mosaic` has no
HRSC-AX case of its own.
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
from collections.abc import Mapping, Sequence
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from ..errors import InputError, ParamsError, param
from ..products.dispatch import ProductStatement
from .plan import MosaicInput, describe_input


def tile_inputs(inputs: Sequence[str | os.PathLike[str]], options: Mapping[str, Any],
                stack: ExitStack) -> tuple[list[MosaicInput], ProductStatement]:
    """HRSC-AX tiles read by the HRSC-AX reader (its grid and height scaling), each as its VRT;
    and the statement the label makes of them, as a single tile's product does: what the
    heights or bands are (each distinct statement of the tiles once) and how the offsets were read."""
    from ..missions import hrsc_ax
    from ..products.hrsc_ax import dtm_note, ortho_description, read_tile, vrt_text

    labels = _labels_per_tile(inputs, options.get("source_labels", ()))
    folder = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="pdsgen-mosaic-tiles-")))
    vicar_offsets = options.get("vicar_offsets", "standard")
    described, tiles = [], []
    for path, own_labels in zip(inputs, labels, strict=True):
        if hrsc_ax.channel_of(Path(path)).extension not in hrsc_ax.PRODUCT_KINDS:
            raise InputError(path, "is one channel of an HRSC-AX colour tile; a mosaic takes tiles of one "
                                   f"file each: {', '.join('.' + c for c in hrsc_ax.PRODUCT_KINDS)}")
        tile = read_tile(path, own_labels, vicar_offsets)
        name = hrsc_ax.tile_product_id(tile.stem, tile.kind)
        tile_vrt = folder / f"{name}.vrt"
        tile_vrt.write_text(vrt_text(tile), encoding="utf-8")
        described.append(dataclasses.replace(describe_input(tile_vrt, "dtm" if tile.kind == "DEM" else "ortho"),
                                             shown=str(path)))
        tiles.append(tile)
    dems = [tile for tile in tiles if tile.kind == "DEM"]
    statement = ProductStatement(
        map_projection_note=hrsc_ax.VICAR_OFFSET_NOTES[vicar_offsets],
        dtm_note=" ".join(dict.fromkeys(dtm_note(tile) for tile in dems)) or None,
        ortho_description=" ".join(dict.fromkeys(ortho_description(tile) for tile in tiles if tile.kind != "DEM"))
        or None)
    return described, statement


def _labels_per_tile(inputs: Sequence[str | os.PathLike[str]],
                     source_labels: Sequence[str | os.PathLike[str]]) -> list[tuple[str | os.PathLike[str], ...]]:
    """Each tile's own XML image label: one per tile, in the tiles' order (or none at all).

    The HRSC-AX reader takes a keyword from the first label that gives it, so labels given to
    every tile would scale all tiles' heights by the first tile's keywords."""
    if not source_labels:
        return [()] * len(inputs)
    if len(source_labels) != len(inputs):
        raise ParamsError(None, f"give one {param('source_labels')} per tile, in the tiles' order: "
                                f"{len(inputs)} tiles, {len(source_labels)} label(s)")
    return [(label,) for label in source_labels]
