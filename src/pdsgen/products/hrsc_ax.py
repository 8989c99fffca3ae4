"""HRSC-AX airborne tiles: the DEM (.dsm) as a float32 PDS3 .IMG, the panchromatic
(.pan), RGB (.re .gr .bl) and CIR (.cir_re .cir_gr .cir_bl) images as JP2 + .LBL.

The tiles are VICAR files. pdsgen reads their MAP and DIGITAL_TERRAIN_MODEL property
groups itself (formats/vicar.py) - GDAL's VICAR reader ignores SCALE_FACTOR and false
easting/northing and knows few projections - and hands the standard DTM and
orthoimage writers a GDAL virtual raster (VRT) that carries the label's grid: the
CRS (Transverse Mercator with its scale factor on the HRSC-AX ellipsoid), the
geotransform, the heights (DTM_OFFSET + stored * DTM_SCALING_FACTOR) and, for colour
products, the channel files side by side as bands in the order given. GDAL reads the
pixels through it by blocks, so memory stays flat; the writers, labels, PDS4 forms,
label checks and Extras are the standard ones.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING
from xml.sax.saxutils import escape

from affine import Affine
from rasterio.crs import CRS

from ..errors import InputError, ParamsError, PdsgenError, param
from ..formats.raster import temporary_vrt
from ..formats.vicar import VicarLabel, VicarValue, group_number, read_map_group, read_vicar_label
from ..geo.label_georef import LabelGeorefError, vicar_map_georeferencing
from ..missions import hrsc_ax
from .dispatch import ProductStatement
from .options import ProductOptions

if TYPE_CHECKING:  # the writers import them on first use
    from .dtm import DtmProduct
    from .ortho import OrthoProduct

_VRT_TYPES = {"BYTE": "Byte", "HALF": "Int16", "FULL": "Int32", "REAL": "Float32", "DOUB": "Float64",
              "WORD": "Int16", "LONG": "Int32"}
MAP_KEYS = (
    "TARGET_NAME", "A_AXIS_RADIUS", "B_AXIS_RADIUS", "C_AXIS_RADIUS", "CENTER_LATITUDE", "CENTER_LONGITUDE",
    "COORDINATE_SYSTEM_NAME", "LINE_PROJECTION_OFFSET", "SAMPLE_PROJECTION_OFFSET", "MAP_PROJECTION_TYPE",
    "MAP_SCALE", "POSITIVE_LONGITUDE_DIRECTION", "SCALE_FACTOR", "FALSE_EASTING", "FALSE_NORTHING",
)
DTM_KEYS = ("DTM_OFFSET", "DTM_SCALING_FACTOR", "DTM_DESC", "DTM_RANGE", "DTM_MISSING_DN")
DATE_KEYS = ("SURVEY_DATE", "ACQUISITION_DATE", "FLIGHT_DATE", "START_TIME", "IMAGE_TIME")


@dataclass(frozen=True)
class TileGrid:
    """The map grid a tile's label states: CRS, geotransform (grid metres) and size."""

    crs: CRS
    transform: Affine
    lines: int
    samples: int


@dataclass(frozen=True)
class Heights:
    """How a DEM's stored values become heights (metres above the ellipsoid)."""

    offset: float
    scaling_factor: float
    missing_stored: float
    cut_off: tuple[float, float] | None  # DTM_RANGE: the heights were cut to these bounds
    description: str


@dataclass(frozen=True)
class Tile:
    """One HRSC-AX product's inputs, read: channel files, their labels, grid and meaning."""

    paths: tuple[Path, ...]
    labels: tuple[VicarLabel, ...]
    kind: str  # DEM, PAN, RGB, CIR
    grid: TileGrid
    heights: Heights | None
    survey_date: str | None

    @property
    def channels(self) -> tuple[hrsc_ax.Channel, ...]:
        return tuple(hrsc_ax.channel_of(path) for path in self.paths)

    @property
    def stem(self) -> str:
        return hrsc_ax.tile_stem(self.paths[0])


def read_tile(inputs: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
              source_labels: Sequence[str | os.PathLike[str]] = (), vicar_offsets: str = "standard") -> Tile:
    """Read the channel files of one product and the XML image labels given; refuse what does not fit.

    `vicar_offsets`: how the MAP group's offsets count (missions/hrsc_ax.py VICAR_OFFSETS).
    """
    check_vicar_offsets(vicar_offsets)
    paths = [Path(inputs)] if isinstance(inputs, (str, os.PathLike)) else [Path(p) for p in inputs]
    if not paths:
        raise PdsgenError(None, "no input file given")
    for path in paths:
        if not path.is_file():
            raise InputError(path, "no such file" if not path.exists() else "is not a file")
    kind = hrsc_ax.product_kind(paths)
    labels = [read_vicar_label(path) for path in paths]
    xml = read_xml_labels(source_labels)
    _check_same_grid(labels)
    first = labels[0]
    map_group = {**_xml_group(xml, MAP_KEYS), **(first.group("MAP") or {})}
    grid = tile_grid(map_group, first, vicar_offsets)
    heights = None
    if kind == "DEM":
        if first.bands != 1:
            raise InputError(first.path, f"has {first.bands} bands; an HRSC-AX DEM has one")
        dtm_group = {**_xml_group(xml, DTM_KEYS), **(first.group("DIGITAL_TERRAIN_MODEL") or {})}
        heights = _heights(dtm_group, first)
    elif first.format != "BYTE":
        raise InputError(first.path, f"is a {first.format} image; HRSC-AX images are 8-bit (BYTE)")
    date = next((str(v) for key in DATE_KEYS for v in [xml.get(key), first.system.get(key)] if v), None)
    return Tile(tuple(paths), tuple(labels), kind, grid, heights, date)


def _check_same_grid(labels: Sequence[VicarLabel]) -> None:
    """Channels of one composite share size, sample type and map grid (one line names the odd file)."""
    first = labels[0]
    for label in labels[1:]:
        if (label.lines, label.samples) != (first.lines, first.samples):
            raise InputError(label.path, f"is {label.lines} x {label.samples} pixels, {first.path.name} is "
                                         f"{first.lines} x {first.samples}: not channels of one tile")
        if label.format != first.format or label.bands != first.bands:
            raise InputError(label.path, f"holds {label.bands} band(s) of {label.format}, {first.path.name} "
                                         f"{first.bands} of {first.format}: not channels of one tile")
        if (label.group("MAP") or {}) != (first.group("MAP") or {}):
            raise InputError(label.path, f"has another map grid (MAP group) than {first.path.name}: "
                                         "not channels of one tile")


def check_vicar_offsets(convention: str) -> None:
    if convention not in hrsc_ax.VICAR_OFFSETS:
        raise ParamsError(None, f"{param('vicar_offsets')} must be one of "
                                f"{', '.join(hrsc_ax.VICAR_OFFSETS)}, not {convention!r}")


def tile_grid(group: Mapping[str, VicarValue], label: VicarLabel, vicar_offsets: str = "standard") -> TileGrid:
    """CRS and geotransform from a MAP group (the label's, not GDAL's reading of it).

    formats/vicar.py reads the group, geo/label_georef.py places its grid (Transverse Mercator
    with the label's SCALE_FACTOR and false origin, or the UTM grid's); the offsets count as
    `vicar_offsets` says (missions/hrsc_ax.py VICAR_OFFSETS).
    """
    projection = read_map_group(group, label.path, f" (give the XML image label with {param('source_labels')})")
    if projection.projection_type not in ("TRANSVERSE_MERCATOR", "UNIVERSAL_TRANSVERSE_MERCATOR"):
        raise InputError(label.path, f"MAP_PROJECTION_TYPE {projection.projection_type} is not read for "
                                     "HRSC-AX tiles (TRANSVERSE_MERCATOR is)")
    try:
        crs, transform = vicar_map_georeferencing(projection, hrsc_ax.VICAR_OFFSETS[vicar_offsets])
    except LabelGeorefError as exc:
        raise InputError(label.path, f"MAP group: {exc}") from None
    return TileGrid(crs, transform, label.lines, label.samples)


def _heights(group: Mapping[str, VicarValue], label: VicarLabel) -> Heights:
    path = label.path
    offset = group_number(group, "DTM_OFFSET", path, 0.0)
    factor = group_number(group, "DTM_SCALING_FACTOR", path, 1.0)
    if factor == 0:
        raise InputError(path, "DTM_SCALING_FACTOR is 0: the stored values cannot be heights")
    missing = group_number(group, "DTM_MISSING_DN", path, hrsc_ax.MISSING_STORED)
    cut = group.get("DTM_RANGE")
    cut_off = None
    if isinstance(cut, tuple) and len(cut) == 2:
        try:
            cut_off = (float(cut[0]), float(cut[1]))
        except ValueError:
            raise InputError(path, f"DTM_RANGE {cut!r} is not two numbers") from None
    elif cut is not None:
        raise InputError(path, f"DTM_RANGE {cut!r} is not (minimum, maximum)")
    return Heights(offset, factor, missing, cut_off, str(group.get("DTM_DESC", "")))


def read_xml_labels(paths: Sequence[str | os.PathLike[str]]) -> dict[str, str]:
    """Keywords of the XML image labels: every element holding text, by its upper-case name.

    The first label giving a keyword wins; the VICAR label's own groups win over all of them.
    """
    from lxml import etree

    found: dict[str, str] = {}
    for path in paths:
        path = Path(path)
        try:
            tree = etree.parse(str(path), etree.XMLParser(resolve_entities=False, no_network=True))
        except OSError as exc:
            raise InputError(path, f"cannot read ({exc})") from None
        except etree.XMLSyntaxError as exc:
            raise InputError(path, f"is not an XML image label ({exc.msg})") from None
        for element in tree.iter():
            if not isinstance(element.tag, str) or len(element) or not (element.text or "").strip():
                continue
            name = etree.QName(element).localname.upper()
            found.setdefault(name, element.text.strip())
    return found


def _xml_group(xml: Mapping[str, str], keys: Sequence[str]) -> dict[str, VicarValue]:
    group: dict[str, VicarValue] = {}
    for key in keys:
        if key in xml:
            text = xml[key]
            if key == "DTM_RANGE":
                parts = text.strip("()").replace(",", " ").split()
                group[key] = tuple(parts)
            else:
                group[key] = text
    return group


# -- the virtual raster the standard writers read --------------------------------------
def vrt_text(tile: Tile) -> str:
    """A GDAL VRT of the tile: the label's grid, heights or channels as bands in the given order."""
    grid = tile.grid
    t = grid.transform
    bands = []
    for number, (path, label) in enumerate(zip(tile.paths, tile.labels, strict=True), start=1):
        source_type = _VRT_TYPES[label.format]
        rect = f'xOff="0" yOff="0" xSize="{grid.samples}" ySize="{grid.lines}"'
        props = (f'<SourceProperties RasterXSize="{grid.samples}" RasterYSize="{grid.lines}" '
                 f'DataType="{source_type}" BlockXSize="{grid.samples}" BlockYSize="1"/>')
        source = f"<SourceFilename relativeToVRT=\"0\">{escape(str(path.resolve()))}</SourceFilename>"
        if tile.heights is not None:
            h = tile.heights
            bands.append(
                f'<VRTRasterBand dataType="Float32" band="{number}"><NoDataValue>nan</NoDataValue>'
                f"<ComplexSource>{source}<SourceBand>1</SourceBand>{props}<SrcRect {rect}/><DstRect {rect}/>"
                f"<NODATA>{h.missing_stored!r}</NODATA><ScaleOffset>{h.offset!r}</ScaleOffset>"
                f"<ScaleRatio>{h.scaling_factor!r}</ScaleRatio></ComplexSource></VRTRasterBand>")
        else:
            bands.append(
                f'<VRTRasterBand dataType="{source_type}" band="{number}"><NoDataValue>0</NoDataValue>'
                f"<SimpleSource>{source}<SourceBand>1</SourceBand>{props}<SrcRect {rect}/><DstRect {rect}/>"
                f"</SimpleSource></VRTRasterBand>")
    return (f'<VRTDataset rasterXSize="{grid.samples}" rasterYSize="{grid.lines}">'
            f"<SRS>{escape(grid.crs.to_wkt())}</SRS>"
            f"<GeoTransform>{t.c!r}, {t.a!r}, 0.0, {t.f!r}, 0.0, {t.e!r}</GeoTransform>"
            + "".join(bands) + "</VRTDataset>")


@contextmanager
def tile_vrt(tile: Tile, name: str) -> Iterator[Path]:
    """The tile's VRT as a file `name`.vrt in a private temporary directory, removed afterwards.

    A problem the standard writers report about the VRT (no valid pixels, unreadable data) is
    the user's files' problem: it is reported naming them, never the temporary file.
    """
    names = str(tile.paths[0]) if len(tile.paths) == 1 else ", ".join(str(p) for p in tile.paths)
    with temporary_vrt(vrt_text(tile), name, names, prefix="pdsgen-hrsc-ax-") as path:
        yield path


# -- what the labels say (the wording is missions/hrsc_ax.py's) ---------------------------
def dtm_note(tile: Tile) -> str:
    """The DEM's NOTE: what the numbers are, the datum, the cut-off, the survey."""
    h = tile.heights
    assert h is not None
    return hrsc_ax.dtm_note(h.offset, h.scaling_factor, h.cut_off, tile.survey_date)


def ortho_description(tile: Tile) -> str:
    """The orthoimage's DESCRIPTION: which band is which channel and wavelength, the survey."""
    return hrsc_ax.ortho_description(tile.kind, tile.channels, tile.survey_date)


# -- the writers ---------------------------------------------------------------------------
def write_hrsc_ax_dtm(
    input_path: str | os.PathLike[str],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
) -> DtmProduct:
    """The DEM of an HRSC-AX tile (`TILE.dsm`) as `<PRODUCT_ID>.IMG`: float32 ellipsoid heights.

    `vicar_offsets`: "standard" (the HRSC-AX image description's definition, default) or
    "dlr" (tiles whose offsets count one pixel further); the label's comment says which.
    """
    from .dtm import write_pds3_dtm

    tile = read_tile(input_path, options.source_labels, options.vicar_offsets)
    product_id = options.product_id or hrsc_ax.tile_product_id(tile.stem, tile.kind)
    statement = ProductStatement(dtm_note=dtm_note(tile),
                          map_projection_note=hrsc_ax.VICAR_OFFSET_NOTES[options.vicar_offsets])
    with tile_vrt(tile, product_id) as vrt:
        return write_pds3_dtm(vrt, outdir, options.replace(product_id=product_id), mission=hrsc_ax.MISSION,
                              statement=statement)


def write_hrsc_ax_ortho(
    input_path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
) -> OrthoProduct:
    """The panchromatic, RGB or CIR image of an HRSC-AX tile as `<PRODUCT_ID>.JP2` + `.LBL`.

    `input_path` is one `.pan` file, or the three channel files of a composite in band
    order (`.re .gr .bl`, `.cir_re .cir_gr .cir_bl`); they must share one grid.
    `vicar_offsets`: how the tiles' MAP offsets count, as for write_hrsc_ax_dtm.
    """
    from .ortho import write_jp2_ortho

    tile = read_tile(input_path, options.source_labels, options.vicar_offsets)
    if tile.kind == "DEM":
        raise PdsgenError(tile.paths[0], "is an HRSC-AX DEM; make it with `pdsgen dtm`")
    product_id = options.product_id or hrsc_ax.tile_product_id(tile.stem, tile.kind)
    statement = ProductStatement(ortho_description=ortho_description(tile),
                          map_projection_note=hrsc_ax.VICAR_OFFSET_NOTES[options.vicar_offsets])
    with tile_vrt(tile, product_id) as vrt:
        return write_jp2_ortho(vrt, outdir, options.replace(product_id=product_id), mission=hrsc_ax.MISSION,
                               filter_names=tuple(c.band_name for c in tile.channels), statement=statement)
