"""`write_mosaic`: many strips or tiles of one kind as one product of a profile.

The inputs are checked and placed (plan.py), presented to the profile's existing writer
as one virtual raster (vrt.py), and written by it: the PDS3 DTM (.IMG) or JP2
orthoimage of generic/HiRISE/HRSC/HRSC-AX (PDS4 too with `label="both"`), the iMars
GeoTIFF + PVL + footprint. The label or metadata names the source products and says
how they were put together.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
import os
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from ..errors import InputError, ParamsError, param
from ..missions import Mission, get_mission
from ..products.dispatch import call_mission_writer
from ..products.result import ProductResult
from .plan import MosaicInput, MosaicPlan, describe_input, plan_mosaic
from .vrt import mosaic_vrt

KINDS = ("dtm", "ortho")


def write_mosaic(
    inputs: Sequence[str | os.PathLike[str]],
    outdir: str | os.PathLike[str],
    *,
    profile: str = "generic",
    product_id: str,
    kind: str | None = None,
    order: str = "given",
    resampling: str | None = None,
    nodata: float | None = None,
    **options: Any,
) -> ProductResult:
    """Mosaic `inputs` (later on top; `order="reverse"` for the other way) into the product of
    `profile` named `product_id` in `outdir`; the writer's own `options` (label, params,
    version, overwrite ...) pass through. Equal to `gdal_merge.py -n ND -a_nodata ND -init ND`
    on the same inputs and order, ND being `nodata` (default: the first input's no-data value,
    0 for orthoimages). Refused in one line before anything is written: inputs of two kinds or
    CRSs, grids that are not aligned (unless `resampling` names a GDAL method), an unreadable
    input."""
    if not inputs:
        raise ParamsError(None, "a mosaic needs at least one input")
    if not product_id:
        raise ParamsError(None, f"a mosaic needs {param('product_id')}")
    if kind is not None and kind not in KINDS:
        raise ParamsError(None, f"{param('kind')} must be one of {', '.join(KINDS)}")
    get_mission(profile)  # an unknown profile is refused before any input is read
    _check_own_name(profile, product_id)
    with ExitStack() as stack:
        mission = get_mission(profile)
        if profile == "hrsc-ax":
            described, mission = _hrsc_ax_inputs(inputs, options, stack)
        else:
            described = [describe_input(path, kind) for path in inputs]
        plan = plan_mosaic(described, order, resampling)
        fill = _nodata(plan, nodata)
        statement = _statement(plan, order, bool(options.get("reproject_input")))
        # without --nodata, each input's own no-data value is no data in it (a no-data pixel never
        # covers data); a given ND is the one value for all inputs, as gdal_merge.py's -n ND
        vrt = stack.enter_context(mosaic_vrt(plan, fill, product_id, _presented_dtype(plan, profile),
                                             own_nodata=nodata is None))
        writer_options = {k: v for k, v in options.items()
                          if not (profile == "hrsc-ax" and k in _HRSC_AX_READER_OPTIONS)}
        return _write(plan, vrt, Path(outdir), mission, product_id, statement, writer_options)


# Options of the HRSC-AX tile reader (not of the writers the mosaic's VRT goes to).
_HRSC_AX_READER_OPTIONS = ("source_labels", "vicar_offsets")


def _check_own_name(profile: str, product_id: str) -> None:
    """An HRSC product is named by orbit and sequence; the HRSC writer would otherwise take
    them from the first source, naming the mosaic after (and as) one of its own strips."""
    from ..missions.hrsc import parse_name

    if profile == "hrsc" and parse_name(product_id) is None:
        raise ParamsError(None, f"an HRSC mosaic is named by orbit and sequence: give "
                                f"{param('product_id', 'h1234_0000')} (not its first source's name)")


# Sample types a float32 holds exactly: a mosaic of them read as float32 has gdal_merge.py's values.
_EXACT_IN_FLOAT32 = ("uint8", "int8", "uint16", "int16", "float32")


def _presented_dtype(plan: MosaicPlan, profile: str) -> str | None:
    """float32 for the float32 PDS3 DTM when every input converts exactly, else the inputs' own.

    The DTM writer stores float32 anyway; reading float32 lets it take its float32 path (fewer
    passes, strips of half the lines of int16 ones), so the mosaic is faster and smaller."""
    own_form = get_mission(profile).writer("dtm") is not None  # hrsc, imars: 16-bit forms of their own
    uniform = all(i.dtype == plan.dtype for i in plan.inputs)
    if plan.kind == "dtm" and (profile == "hrsc-ax" or not own_form) and uniform \
            and plan.dtype in _EXACT_IN_FLOAT32 and (plan.scale, plan.offset) == (1.0, 0.0):
        return "float32"
    return None


def _nodata(plan: MosaicPlan, nodata: float | None) -> float:
    """ND: given, else the first input's own, else 0 for an orthoimage; a DTM needs one."""
    if nodata is not None:
        return float(nodata)
    first = plan.inputs[0]
    if first.nodata is not None:
        return float(first.nodata)
    if plan.kind == "ortho":
        return 0.0
    raise InputError(first.name, f"has no no-data value; give the one its heights use as {param('nodata')}")


def _statement(plan: MosaicPlan, order: str, warped: bool = False) -> str:
    """How the sources were put together, for the label or metadata to say (`warped`: the
    profile's writer then warps the mosaic into its own projection, `reproject_input`)."""
    how = (f"resampled with GDAL's {plan.resampling} method onto the grid of the first" if plan.resampling
           else "placed on their common grid")
    how += ", then warped into the profile's map projection" if warped else \
        "" if plan.resampling else " without resampling"
    stacking = "listed order" if order == "given" else "reverse of the listed order"
    return (f"Mosaic of {len(plan.inputs)} products ({', '.join(i.product_id for i in plan.inputs)}), "
            f"{how}; later ones lie on top ({stacking}) and no-data never covers data.")


def _source_ids(plan: MosaicPlan) -> tuple[str, ...]:
    return tuple(dict.fromkeys(i.product_id for i in plan.inputs))


def _write(plan: MosaicPlan, vrt: Path, outdir: Path, mission: Mission, product_id: str, statement: str,
           options: Mapping[str, Any]) -> ProductResult:
    """The profile's writer, reading the mosaic's VRT; `mission` the profile's (for HRSC-AX,
    with what its tiles' labels say about their heights, images and offsets)."""
    profile = mission.name
    if profile == "imars":
        return _write_imars(plan, vrt, outdir, product_id, statement, options)
    options = {**options, "product_id": product_id, "params": _with_sources(plan, options.get("params"))}
    if plan.kind == "dtm":
        from ..products.dtm import write_dtm, write_pds3_dtm

        if mission.writer("dtm") is not None and profile != "hrsc-ax":  # hrsc: its own DT4/DA4 form
            return write_dtm(vrt, outdir, profile=profile, **_stated(mission, "dtm", options, statement))
        note = f"{mission.dtm_note} {statement}".strip()
        writer = functools.partial(write_pds3_dtm, mission=dataclasses.replace(mission, dtm_note=note))
        return call_mission_writer(writer, profile, vrt, outdir, options)
    from ..products.ortho import write_jp2_ortho, write_ortho

    if mission.writer("ortho") is not None and profile != "hrsc-ax":
        return write_ortho(vrt, outdir, profile=profile, **_stated(mission, "ortho", options, statement))
    description = f"{mission.ortho_description} {statement}".strip()
    jp2_writer = functools.partial(write_jp2_ortho,
                                   mission=dataclasses.replace(mission, ortho_description=description))
    return call_mission_writer(jp2_writer, profile, vrt, outdir, options)


def _stated(mission: Mission, kind: str, options: Mapping[str, Any], statement: str) -> dict[str, Any]:
    """A profile's own writer that takes a `mosaic_statement` (HRSC's) gets the mosaic's, for its
    label to say what the standard writers' NOTE/DESCRIPTION say."""
    writer = mission.writer(kind)
    takes = writer is not None and "mosaic_statement" in inspect.signature(writer).parameters
    return {**options, "mosaic_statement": statement} if takes else dict(options)


def _with_sources(plan: MosaicPlan, params: Any) -> dict[str, Any]:
    """The params keywords with the mosaic's sources first in SOURCE_PRODUCT_ID: the PDS3
    labels of DTMs and orthoimages take their sources from it, and a PDS4 label of the same
    product (`label="both"`/`"pds4"`) names the same ones in its Reference_List."""
    from ..products.params import resolve_params

    keywords = resolve_params(params)
    given = keywords.get("SOURCE_PRODUCT_ID") or []
    given = [given] if isinstance(given, str) else list(given)
    keywords["SOURCE_PRODUCT_ID"] = list(dict.fromkeys([*_source_ids(plan), *map(str, given)]))
    return keywords


def _write_imars(plan: MosaicPlan, vrt: Path, outdir: Path, product_id: str, statement: str,
                 options: Mapping[str, Any]) -> ProductResult:
    """`<ID>_dtm.tif` / `<ID>_ori.tif` with the PVL naming the strips and their footprints."""
    from ..products.imars import ImarsMosaic, write_imars_dtm, write_imars_ori

    if plan.kind == "dtm" and plan.scale != 1.0:  # the strips' own precision unless told otherwise
        options = {"precision": plan.scale, **options}
    mosaic = ImarsMosaic(product_id, tuple(_outlines(plan)), statement)
    writer = functools.partial(write_imars_dtm if plan.kind == "dtm" else write_imars_ori, mosaic=mosaic)
    return call_mission_writer(writer, "imars", vrt, outdir, {"source_product_ids": _source_ids(plan), **options})


def _outlines(plan: MosaicPlan) -> Iterator[tuple[str, list[dict[str, Any]], dict[str, Any]]]:
    """Each source's valid data outlined (a decimated read of that source alone)."""
    import numpy as np

    from ..formats.footprint import valid_data_outline
    from ..formats.raster import open_raster

    for source in plan.inputs:
        nodata = source.nodata

        def valid(values: np.ndarray, nodata: float | None = nodata) -> np.ndarray:
            finite = np.isfinite(values) if values.dtype.kind == "f" else np.ones(values.shape, bool)
            return finite if nodata is None or math.isnan(nodata) else finite & (values != nodata)

        with open_raster(source.path) as dataset:
            polygons = valid_data_outline(dataset, valid)
        yield source.product_id, polygons, {"file": Path(source.name).name}


def _hrsc_ax_inputs(inputs: Sequence[str | os.PathLike[str]], options: Mapping[str, Any],
                    stack: ExitStack) -> tuple[list[MosaicInput], Mission]:
    """HRSC-AX tiles read by the HRSC-AX reader (its grid and height scaling), each as its VRT;
    and the HRSC-AX mission saying in the label what a single tile's product says: what the
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
    mission = dataclasses.replace(
        hrsc_ax.MISSION, map_projection_note=hrsc_ax.VICAR_OFFSET_NOTES[vicar_offsets],
        dtm_note=" ".join(dict.fromkeys(dtm_note(tile) for tile in dems)) or hrsc_ax.MISSION.dtm_note,
        ortho_description=" ".join(dict.fromkeys(ortho_description(tile) for tile in tiles if tile.kind != "DEM"))
        or hrsc_ax.MISSION.ortho_description)
    return described, mission


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
