"""Mars Express HRSC level-4 DTMs: DT4 (heights above the 3396.0 km sphere) and DA4
(heights above the areoid), as signed 16-bit samples with the MEX:DTM group.

HRSC's archive conventions (docs section 7): file names `hOOOO_NNNN_dt4.img`,
map reference body a sphere of 3396.0 km, sinusoidal for centre latitudes within
+-85 degrees and polar stereographic poleward. Inputs in other projections are
refused, or warped on the fly (`reproject=True`) through a GDAL warped VRT that
is read strip by strip like any other input.
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from affine import Affine
from rasterio.crs import CRS
from rasterio.enums import Resampling
from rasterio.io import DatasetReader
from rasterio.vrt import WarpedVRT
from rasterio.warp import calculate_default_transform
from rasterio.warp import transform as warp_transform

from .. import __version__
from ..dialect import Dialect
from ..errors import ParamsError, PdsgenError, param
from ..formats.img import BandStatistics, stream_band, write_attached_product
from ..formats.scale_dn import SPECIAL_DNS, dn_encoder, null_zero_byte_mapping
from ..formats.vicar import vicar_label
from ..geo.geometry import POLAR_STEREOGRAPHIC, SINUSOIDAL, MapGeometry
from ..label.grammar import sample_type
from ..label.render import RecordLayout, render_label
from ..label.values import Based, Symbol
from ..missions import hrsc as hrsc_mission
from ..missions.hrsc import DTM_KINDS, MISSING_DN, NOT_APPLICABLE, POLAR_LIMIT_DEG
from ..missions.hrsc import base_name as hrsc_base_name
from ..params import ParamValue, check_version, resolve_params, source_ids
from ..pds4.model import DATA_TYPES
from ..pds4.products import FileHeader, ProductDescription, StoredArray, pds3_label_header, write_image_pds4_label
from ..storage.staging import StagedOutputs
from .agreement import allows_deviations, check_label
from .dispatch import NO_STATEMENT, ProductStatement
from .hrsc_label import (
    VICAR_DESCRIPTION,
    VICAR_DESCRIPTION_NAME,
    DnMoments,
    carried_context,
    offset_context,
    pds_label_part,
    with_header,
)
from .identification import source_id_values
from .int16_heights import (
    Int16Encoding,
    areoid_adjustment,
    chain_adjustments,
    check_datum_conversion,
    choose_encoding,
    source_body,
    sphere_change,
)
from .opening import Opening, ProductInput, map_geometry, open_product_input, require_valid, single_band
from .options import ProductOptions
from .result import ProductResult

HRSC_SPHERE_M = hrsc_mission.SPHERE_M


@dataclass(frozen=True, kw_only=True)
class HrscProduct(ProductResult):
    """What both HRSC level-4 products have: one file (VICAR header + PDS3 label + data)."""

    product_id: str
    path: Path
    geometry: MapGeometry
    valid_minimum: int
    valid_maximum: int
    label_text: str
    warnings: tuple[str, ...] = ()  # dictionary deviations kept (--allow-dictionary-deviations)
    pds4_label_path: Path | None = None  # label "both": the PDS4 label of the same .img

    @property
    def files(self) -> tuple[Path, ...]:
        """Every file this product wrote."""
        return (self.path,) + ((self.pds4_label_path,) if self.pds4_label_path else ())


@dataclass(frozen=True, kw_only=True)
class HrscDtmProduct(HrscProduct):
    kind: str
    encoding: Int16Encoding

    @property
    def summary_facts(self) -> tuple[str, ...]:
        return (f"DN {self.valid_minimum} .. {self.valid_maximum} "
                f"(x {self.encoding.scaling_factor:g} + {self.encoding.offset:g} m)",)


def hrsc_target_crs(dataset: DatasetReader) -> CRS:
    """The HRSC projection for this input: sinusoidal or polar stereographic on 3396.0 km."""
    lon, lat = _centre_lonlat(dataset.crs, dataset.transform, dataset.width, dataset.height)
    if abs(lat) > POLAR_LIMIT_DEG:
        return CRS.from_proj4(
            f"+proj=stere +lat_0={math.copysign(90, lat):.0f} +lon_0=0 +k=1 +R={HRSC_SPHERE_M:.0f} "
            "+units=m +no_defs"
        )
    return CRS.from_proj4(f"+proj=sinu +lon_0={round(lon):d} +R={HRSC_SPHERE_M:.0f} +units=m +no_defs")


def check_hrsc_geometry(geometry: MapGeometry, centre_latitude: float, source: str) -> None:
    """HRSC level-4 products are on the 3396.0 km sphere, in the projection their latitude calls for."""
    expected = POLAR_STEREOGRAPHIC if abs(centre_latitude) > POLAR_LIMIT_DEG else SINUSOIDAL
    if geometry.projection_type != expected:
        raise PdsgenError(
            source,
            f"HRSC products at centre latitude {centre_latitude:.1f} are {expected.lower()}, "
            f"the input is {geometry.projection_type.lower()}; rerun with {param('reproject_input', True)}",
        )
    if not (geometry.is_sphere and math.isclose(geometry.a_axis_km, hrsc_mission.SPHERE_KM, abs_tol=1e-9)):
        raise PdsgenError(
            source,
            f"HRSC products use the 3396.0 km sphere, the input uses {geometry.a_axis_km:g} x "
            f"{geometry.c_axis_km:g} km; rerun with {param('reproject_input', True)}",
        )


@contextmanager
def hrsc_grid(dataset: DatasetReader, reproject_input: bool) -> Iterator[DatasetReader]:
    """The input as is, or warped into the HRSC projection at its own pixel size."""
    if not reproject_input:
        yield dataset
        return
    if dataset.crs is None:
        raise PdsgenError(dataset.name, "raster has no coordinate reference system (map projection)")
    target = hrsc_target_crs(dataset)
    resolution = abs(dataset.transform.a)
    transform, width, height = calculate_default_transform(
        dataset.crs, target, dataset.width, dataset.height, *dataset.bounds, resolution=resolution
    )
    transform, width, height = _snap_to_pixels(transform, width, height, resolution)
    floating = np.dtype(dataset.dtypes[0]).kind == "f"
    nodata = dataset.nodata if dataset.nodata is not None else (math.nan if floating else None)
    with WarpedVRT(
        dataset, crs=target, transform=transform, width=width, height=height,
        resampling=Resampling.bilinear, src_nodata=dataset.nodata, nodata=nodata,
        warp_mem_limit=64, dtype="float32",
    ) as vrt:
        yield vrt


def write_hrsc_dtm(
    input_path: str | os.PathLike[str],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
    *,
    statement: ProductStatement = NO_STATEMENT,
) -> HrscDtmProduct:
    """Write `OUTDIR/hOOOO_NNNN_<kind>.img` from a single-band height raster.

    `source_labels`: level-2/3 labels whose identification, time and orbit keywords
    the product carries (left out without them). `offset_convention`: "standard"
    (PDS3, GDAL reads the grid exactly) or "dlr" (DLR's pipeline, one pixel apart).
    With `reproject_input`, heights above the input's own reference surface are
    converted to the 3396.0 km sphere (radius = R_in + h, h' = radius - 3396.0 km).
    label "both" adds `hOOOO_NNNN_<kind>.xml`, a PDS4 label of the same .img (see
    `_pds4_beside`). `statement`: how a mosaic's sources were put together, for NOTE.
    """
    kind, vertical_datum, areoid, precision = options.kind, options.vertical_datum, options.areoid, options.precision
    product_id, source_product_ids, params, byte_order = (options.product_id, options.source_product_ids,
                                                          options.params, options.byte_order)
    version, overwrite, source_labels, offset_convention, allow_dictionary_deviations, label = (
        options.version, options.overwrite, options.source_labels, options.offset_convention,
        options.allow_dictionary_deviations, options.label)
    reproject_input = options.reproject_input
    _check_hrsc_label(label)
    output_datum, description = DTM_KINDS[kind]
    vertical_datum = vertical_datum or output_datum  # unset: the kind's (HRSC's declaration says "sphere")
    check_datum_conversion(kind, output_datum, vertical_datum, areoid)
    version = check_version(version)
    keywords = resolve_params(params)
    input_path = Path(input_path)
    with hrsc_input(input_path, reproject_input) as (opened, source_body):
        grid, geometry = opened.dataset, opened.geometry
        adjusts = []
        if vertical_datum == "sphere" and source_body is not None:
            adjusts.append(sphere_change(source_body, grid))
        if output_datum != vertical_datum:
            adjusts.append(areoid_adjustment(areoid, grid, +1.0 if output_datum == "sphere" else -1.0))
        adjust = chain_adjustments(adjusts)
        encoding = choose_encoding(opened.scan(adjust), precision, str(input_path))
        context = hrsc_identification(hrsc_mission.KEYWORDS, keywords, product_id, source_product_ids, kind, version)
        file_name, final_id = context["file_name"], context["product_id"]
        context |= carried_context(source_labels, context["orbit"], Path(outdir))
        context |= offset_context(geometry, offset_convention)
        moments = DnMoments()
        context |= {
            "geometry": geometry,
            "sample_type": Symbol(sample_type(byte_order == "msb", "i")),
            "bit_mask": Based(0xFFFF, 2, 16),
            "offset": encoding.offset,
            "scaling_factor": encoding.scaling_factor,
            "missing_dn": MISSING_DN,
            "dtm_radius_km": hrsc_mission.SPHERE_KM if kind == "dt4" else NOT_APPLICABLE,
            "dtm_desc": description,
            "note": statement.after(
                f"Heights in meters {hrsc_mission.DTM_NOTE_DATUMS[kind]} = DN * SCALING_FACTOR "
                f"+ OFFSET, quantised to {encoding.scaling_factor:g} m. DN {MISSING_DN} marks missing data."),
        }

        big_endian = byte_order == "msb"
        header = vicar_label(np.dtype(np.int16), grid.height, grid.width, 1, grid.width * 2, big_endian)

        def render(records: RecordLayout, stats: BandStatistics) -> str:
            return with_header(lambda view: render_label("hrsc_dtm.lbl.j2", {
                **context, "records": view, "stats": moments.summary(stats),
                "vicar_description": VICAR_DESCRIPTION_NAME,
            }), header, grid.width * 2)(records)

        def write_data(handle) -> BandStatistics:
            return stream_band(grid, handle, big_endian, moments.counting(encoding.encode), adjust)

        final = opened.output_dir(outdir) / file_name
        xml_final = final.with_suffix(".xml") if Dialect.of(label).pds4 else None
        with opened.stage([final, *_vicar_description(final), *([xml_final] if xml_final else [])],
                          overwrite) as staged:
            records, text, stats = write_attached_product(
                staged.path(final), render, grid.width * 2, grid.height, write_data
            )
            _write_vicar_description(staged, final)
            warnings = check_label(pds_label_part(text), final.name,
                                   allow_deviations=allows_deviations(allow_dictionary_deviations, keywords))
            if xml_final is not None:
                stored = StoredArray(
                    DATA_TYPES[("i2", big_endian)], (("missing_constant", float(MISSING_DN)),),
                    f"{description.capitalize()} in metres = DN * scaling_factor + value_offset; "
                    "DNs equal to missing_constant hold no data.",
                    scaling=(encoding.scaling_factor, encoding.offset))
                _pds4_beside(staged, final, xml_final, ProductDescription(
                    final_id, hrsc_mission.MISSION, version, context["ident"], geometry, grid, context["sources"]
                ), stored, records.label_bytes, len(header))
    return HrscDtmProduct(product_id=final_id, path=final, geometry=geometry, kind=kind, encoding=encoding,
                          valid_minimum=_as_int(stats.minimum), valid_maximum=_as_int(stats.maximum),
                          label_text=pds_label_part(text), warnings=warnings, pds4_label_path=xml_final)


@contextmanager
def hrsc_input(
    input_path: Path, reproject_input: bool, what: str = "a DTM"
) -> Iterator[tuple[ProductInput, tuple[float, float] | None]]:
    """Open a single-band input on the HRSC grid (as is, or warped) and check its geometry:
    HRSC's hooks of the writers' common opening.

    Also yields the input's reference body (a, c in metres) when the grid was warped
    from another body, so heights above it can be converted (None otherwise).
    """
    opening = Opening(check=single_band(what), grid=functools.partial(hrsc_grid, reproject_input=reproject_input),
                      describe=_checked_hrsc_geometry)
    with open_product_input(input_path, opening) as opened:
        yield opened, source_body(opened.source) if reproject_input else None


def _checked_hrsc_geometry(grid: DatasetReader, input_path: Path) -> MapGeometry:
    """The grid's geometry, refused unless it is HRSC's projection and sphere."""
    geometry = map_geometry(grid, input_path)
    _, centre_lat = _centre_lonlat(grid.crs, grid.transform, grid.width, grid.height)
    check_hrsc_geometry(geometry, centre_lat, str(input_path))
    return geometry


def hrsc_identification(
    defaults: Mapping[str, str], keywords: Mapping[str, ParamValue], product_id: str | None,
    source_product_ids: Sequence[str], kind: str, version: str,
) -> dict:
    """File name, PRODUCT_ID, orbit and identification keywords of one HRSC product."""
    sources = source_ids(source_product_ids, keywords)
    base, orbit = hrsc_base_name(product_id, sources)
    ident: dict[str, ParamValue] = {
        **defaults, "MISSION_NAME": hrsc_mission.MISSION_NAME, "PRODUCT_VERSION_ID": version,
        "SOFTWARE_NAME": f"pdsgen {__version__}",
    }
    ident.update({k: v for k, v in keywords.items() if k in ident})
    return {
        "file_name": f"{base}_{kind}.img",
        "product_id": f"{base}_{kind}".upper(),
        "orbit": orbit,
        "processing_level": hrsc_mission.PROCESSING_LEVEL,
        "ident": ident,
        "source_product_id": source_id_values(sources),
        "sources": sources,  # the same, for the PDS4 label's Reference_List
    }


@dataclass(frozen=True, kw_only=True)
class HrscImageProduct(HrscProduct):
    scaling_factor: float
    offset: float

    @property
    def summary_facts(self) -> tuple[str, ...]:
        return (f"DN {self.valid_minimum} .. {self.valid_maximum}",)


def write_hrsc_nd4(
    input_path: str | os.PathLike[str],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
    *,
    statement: ProductStatement = NO_STATEMENT,
) -> HrscImageProduct:
    """Write the nadir orthoimage `OUTDIR/hOOOO_NNNN_nd4.img`: 8-bit DNs, 0 = no data.

    Byte input keeps its DNs (0 is HRSC's no-data DN already); anything else is
    mapped linearly from its valid range (or `value_range`) onto DNs 1..254,
    with SCALING_FACTOR and OFFSET giving the input values back. label "both" adds
    `hOOOO_NNNN_nd4.xml`, a PDS4 label of the same .img (see `_pds4_beside`).
    `statement`: how a mosaic's sources were put together, for NOTE.
    """
    value_range, reproject_input, product_id, source_product_ids = (options.value_range, options.reproject_input,
                                                                    options.product_id, options.source_product_ids)
    version, overwrite, source_labels, offset_convention, allow_dictionary_deviations, label = (
        options.version, options.overwrite, options.source_labels, options.offset_convention,
        options.allow_dictionary_deviations, options.label)
    _check_hrsc_label(label)
    keywords = resolve_params(options.params)
    input_path = Path(input_path)
    special = SPECIAL_DNS[8]
    with hrsc_input(input_path, reproject_input, "an HRSC nadir image") as (opened, _):
        grid, geometry = opened.dataset, opened.geometry
        mapping = null_zero_byte_mapping(grid, value_range, str(input_path))
        context = hrsc_identification(
            hrsc_mission.ND4_KEYWORDS, keywords, product_id, source_product_ids, "nd4", version
        )
        context |= carried_context(source_labels, context["orbit"], Path(outdir))
        context |= offset_context(geometry, offset_convention)
        moments = DnMoments()
        context |= {
            "geometry": geometry,
            "bit_mask": Based(0xFF, 2, 8),
            "offset": mapping.offset,
            "scaling_factor": mapping.scaling_factor,
            "missing_dn": special.null,
            "note": statement.after("Nadir orthoimage. Value = DN * SCALING_FACTOR + OFFSET; DN 0 marks "
                                    "missing data."),
        }

        encode = moments.counting(dn_encoder(mapping, str(input_path)))

        header = vicar_label(np.dtype(np.uint8), grid.height, grid.width, 1, grid.width, True)

        def render(records: RecordLayout, stats: BandStatistics) -> str:
            return with_header(lambda view: render_label("hrsc_nd4.lbl.j2", {
                **context, "records": view, "stats": moments.summary(stats),
                "vicar_description": VICAR_DESCRIPTION_NAME,
            }), header, grid.width)(records)

        def write_data(handle) -> BandStatistics:
            return require_valid(stream_band(grid, handle, True, encode), input_path)

        final = opened.output_dir(outdir) / context["file_name"]
        xml_final = final.with_suffix(".xml") if Dialect.of(label).pds4 else None
        with opened.stage([final, *_vicar_description(final), *([xml_final] if xml_final else [])],
                          overwrite) as staged:
            records, text, stats = write_attached_product(
                staged.path(final), render, grid.width, grid.height, write_data)
            _write_vicar_description(staged, final)
            warnings = check_label(pds_label_part(text), final.name,
                                   allow_deviations=allows_deviations(allow_dictionary_deviations, keywords))
            if xml_final is not None:
                identity = mapping.scaling_factor == 1.0 and mapping.offset == 0.0
                stored = StoredArray(
                    DATA_TYPES[("u1", True)], (("missing_constant", float(special.null)),),
                    "Nadir orthoimage DNs" + ("" if identity else "; value = DN * scaling_factor + value_offset")
                    + f"; DN {special.null} marks missing data.",
                    unit=None, scaling=None if identity else (mapping.scaling_factor, mapping.offset),
                    collection="data_ortho", kind="nadir orthoimage")
                _pds4_beside(staged, final, xml_final, ProductDescription(
                    context["product_id"], hrsc_mission.MISSION, version, context["ident"], geometry, grid,
                    context["sources"]
                ), stored, records.label_bytes, len(header))
    return HrscImageProduct(product_id=context["product_id"], path=final, geometry=geometry,
                            scaling_factor=mapping.scaling_factor, offset=mapping.offset,
                            valid_minimum=_as_int(stats.minimum), valid_maximum=_as_int(stats.maximum),
                            label_text=pds_label_part(text), warnings=warnings, pds4_label_path=xml_final)


def _check_hrsc_label(label: str) -> None:
    """HRSC products are DLR's PDS3 .img; a PDS4 label can describe that file, not replace it."""
    if not Dialect.of(label).pds3:
        raise ParamsError(None, f"HRSC products keep their PDS3 .img; use {param('label', 'both')} "
                                "to add a PDS4 label of it")


def _pds4_beside(staged: StagedOutputs, final: Path, xml_final: Path, product: ProductDescription,
                 stored: StoredArray, headers_bytes: int, vicar_bytes: int) -> None:
    """The PDS4 label of a written HRSC .img: its attached PDS3 label and the VICAR label
    after it are two Headers (in file order), the DNs with their scaling the array."""
    vicar = FileHeader("vicar_label", vicar_bytes, "VICAR2",
                       f"The VICAR label of the same product, as DLR writes it "
                       f"({VICAR_DESCRIPTION_NAME} describes it).")
    write_image_pds4_label(product, staged.path(xml_final), staged.path(final), final.name, stored,
                           [pds3_label_header(headers_bytes - vicar_bytes), vicar])


def _vicar_description(product: Path) -> list[Path]:
    """VICAR2.TXT beside the product, when the directory does not hold it yet."""
    path = product.parent / VICAR_DESCRIPTION_NAME
    return [] if path.exists() else [path]


def _write_vicar_description(staged: StagedOutputs, product: Path) -> None:
    for path in _vicar_description(product):
        staged.path(path).write_bytes(VICAR_DESCRIPTION.replace("\n", "\r\n").encode("ascii"))


def _as_int(value: float) -> int:
    """DN statistics are integers; write_attached_product's label-size reservation passes
    a non-integer placeholder, which must stay at least as wide as any int16 when written."""
    return int(value) if float(value).is_integer() else -(10**23)


def _centre_lonlat(crs: CRS, transform: Affine, width: int, height: int) -> tuple[float, float]:
    x, y = transform @ (width / 2.0, height / 2.0)
    lons, lats = warp_transform(crs, CRS.from_proj4(f"+proj=longlat +R={HRSC_SPHERE_M:.0f} +no_defs"), [x], [y])
    return float(lons[0]), float(lats[0])


def _snap_to_pixels(transform: Affine, width: int, height: int, resolution: float):
    """Put the warped grid's corners on whole multiples of the pixel size."""
    left = math.floor(transform.c / resolution) * resolution
    top = math.ceil(transform.f / resolution) * resolution
    right = transform.c + width * transform.a
    bottom = transform.f + height * transform.e
    width = math.ceil((right - left) / resolution)
    height = math.ceil((top - bottom) / resolution)
    return Affine(resolution, 0.0, left, 0.0, -resolution, top), width, height


__all__ = ["write_hrsc_dtm", "write_hrsc_nd4", "HrscDtmProduct", "HrscImageProduct"]
