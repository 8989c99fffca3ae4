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
import os
from collections.abc import Callable, Mapping, Sequence
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from ..errors import InputError, ParamsError, param
from ..missions import Mission, get_mission
from ..missions.base import resolve
from ..products.dispatch import NO_STATEMENT, ProductStatement, call_mission_writer
from ..products.options import ProductOptions
from ..products.result import ProductResult
from .plan import MosaicPlan, describe_input, plan_mosaic, source_ids
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
    mission = get_mission(profile)  # an unknown profile is refused before any input is read
    refusal = mission.mosaic_product_id(product_id) if mission.mosaic_product_id else None
    if refusal:
        raise ParamsError(None, refusal)
    with ExitStack() as stack:
        inputs_say = NO_STATEMENT
        if mission.mosaic_reader:  # the mission's own inputs (HRSC-AX tiles), read by its reader
            described, inputs_say = resolve(mission.mosaic_reader)(inputs, options, stack)
        else:
            described = [describe_input(path, kind) for path in inputs]
        plan = plan_mosaic(described, order, resampling)
        fill = _nodata(plan, nodata)
        statement = dataclasses.replace(inputs_say, mosaic=_statement(plan, order,
                                                                      bool(options.get("reproject_input"))))
        # without --nodata, each input's own no-data value is no data in it (a no-data pixel never
        # covers data); a given ND is the one value for all inputs, as gdal_merge.py's -n ND
        vrt = stack.enter_context(mosaic_vrt(plan, fill, product_id, _presented_dtype(plan, mission),
                                             own_nodata=nodata is None))
        writer_options = {k: v for k, v in options.items() if k not in mission.mosaic_reader_options}
        return _write(plan, vrt, Path(outdir), mission, product_id, statement, writer_options)




# Sample types a float32 holds exactly: a mosaic of them read as float32 has gdal_merge.py's values.
_EXACT_IN_FLOAT32 = ("uint8", "int8", "uint16", "int16", "float32")


def _presented_dtype(plan: MosaicPlan, mission: Mission) -> str | None:
    """float32 for the float32 PDS3 DTM when every input converts exactly, else the inputs' own.

    The DTM writer stores float32 anyway; reading float32 lets it take its float32 path (fewer
    passes, strips of half the lines of int16 ones), so the mosaic is faster and smaller."""
    uniform = all(i.dtype == plan.dtype for i in plan.inputs)
    if plan.kind == "dtm" and not _own_form(mission, "dtm") and uniform \
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


def _write(plan: MosaicPlan, vrt: Path, outdir: Path, mission: Mission, product_id: str, statement: ProductStatement,
           options: Mapping[str, Any]) -> ProductResult:
    """The profile's writer, reading the mosaic's VRT, given the `statement` its label makes: how
    the sources were put together (and, for HRSC-AX, what its tiles' labels say about their
    heights, images and offsets)."""
    profile = mission.name
    if mission.mosaic_writer:  # a mosaic form of its own (iMars)
        own_form: Callable[..., ProductResult] = resolve(mission.mosaic_writer)
        return own_form(plan, vrt, outdir, product_id, statement, options)
    options = {**options, "product_id": product_id, "params": _with_sources(plan, options.get("params"))}
    built = ProductOptions.build(plan.kind, mission, options)
    if plan.kind == "dtm":
        from ..products.dtm import dtm_writer, write_pds3_dtm

        if _own_form(mission, "dtm"):  # hrsc: its own DT4/DA4 form
            return call_mission_writer(dtm_writer(mission, statement), vrt, outdir, built)
        writer = functools.partial(write_pds3_dtm, mission=mission, statement=statement)
        return call_mission_writer(writer, vrt, outdir, built)
    from ..products.ortho import ortho_writer, write_jp2_ortho

    if _own_form(mission, "ortho"):
        return call_mission_writer(ortho_writer(mission, built, profile, statement), vrt, outdir, built)
    jp2_writer = functools.partial(write_jp2_ortho, mission=mission, statement=statement)
    return call_mission_writer(jp2_writer, vrt, outdir, built)


def _own_form(mission: Mission, kind: str) -> bool:
    """Whether the mission writes its `kind` ("dtm"/"ortho") in a form of its own (HRSC's 16-bit
    DT4/DA4, ND4): a mission whose own writer only reads its inputs (HRSC-AX tiles), and whose
    mosaic reader does that instead, is written in the standard forms."""
    return mission.writer(kind) is not None and mission.mosaic_reader is None


def _with_sources(plan: MosaicPlan, params: Any) -> dict[str, Any]:
    """The params keywords with the mosaic's sources first in SOURCE_PRODUCT_ID: the PDS3
    labels of DTMs and orthoimages take their sources from it, and a PDS4 label of the same
    product (`label="both"`/`"pds4"`) names the same ones in its Reference_List."""
    from ..params import resolve_params

    keywords = resolve_params(params)
    given = keywords.get("SOURCE_PRODUCT_ID") or []
    given = [given] if isinstance(given, str) else list(given)
    keywords["SOURCE_PRODUCT_ID"] = list(dict.fromkeys([*source_ids(plan), *map(str, given)]))
    return keywords







