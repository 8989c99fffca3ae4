"""Georeferencing from a label's map projection: label -> CRS and grid.

The one reader of a label's map projection for the Extras (products GDAL cannot place),
the review page's footprints, the PDS3 -> PDS4 migration (cart:) and the HRSC-AX tiles'
VICAR MAP groups (`vicar_map_georeferencing`; formats/vicar.py reads the group);
geometry.py is the other direction.

GDAL's PDS driver reads `IMAGE_MAP_PROJECTION` with the names current PDS3 labels
use. Older map products describe the same grid differently and GDAL then reports
no georeferencing at all: Magellan's F-MIDR framelets carry an
`IMAGE_MAP_PROJECTION_CATALOG` whose `X_AXIS_PROJECTION_OFFSET` counts lines and
`Y_AXIS_PROJECTION_OFFSET` samples (Magellan's axes: X down the image, Y across).
The Extras still need a CRS and a geotransform for the scale bar and the north
arrow, so this module builds them from the label:

- the CRS as a PROJ definition on a sphere or ellipsoid of the label's radii
  (sinusoidal and equirectangular from A_AXIS_RADIUS; polar stereographic from
  C_AXIS_RADIUS, as GDAL does; Transverse Mercator on the ellipsoid of A_AXIS_RADIUS
  and C_AXIS_RADIUS, scale factor 1, as a PDS3 label states it - see below), handed to
  rasterio's CRS (PROJ);
- the geotransform with the standard PDS3 offset convention
  (`ULX = -(SAMPLE_PROJECTION_OFFSET + 0.5) * MAP_SCALE`,
  `ULY = (LINE_PROJECTION_OFFSET + 0.5) * MAP_SCALE`; docs section 4), the
  convention GDAL itself applies to PDS3 labels.

Transverse Mercator: PDS3 has no keyword for a grid's scale factor or false
easting/northing, so a label (pdsgen's HRSC-AX products; geometry.py's module
docstring) folds them in - offsets from the natural origin, MAP_SCALE the grid spacing
divided by the scale factor - and read with scale factor 1 every pixel lands on its
ground position. pdsgen's writer states the true grid in the projection object's
comment, in the wording of transverse_mercator.py (the template renders it, this module
parses it); given the label's text,
`label_georeferencing` unfolds it (`transverse_mercator_grid`), so the CRS and
geotransform are the grid itself (scale factor, false origin, grid spacing) and the
pixels land on the same ground positions.

Magellan MIDR framelets are placed by their data set's own equations (a 6051.0 km sphere,
sample centres half a pixel out; magellan.py), not by their A_AXIS_RADIUS.

West-positive labels give their longitudes west; the projection's central
meridian is turned east-positive (conventions.py), as PROJ expects, and x still grows to
the east. A UTM grid's false origin is utm.py's.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from rasterio.crs import CRS
from rasterio.errors import CRSError
from rasterio.transform import Affine

from . import magellan, utm
from .conventions import east_positive, upper_left_corner, wrap_180
from .transverse_mercator import UNFOLDED, GridNoteError, TransverseMercatorGrid, read_grid_note

PROJECTION_OBJECTS = ("IMAGE_MAP_PROJECTION", "IMAGE_MAP_PROJECTION_CATALOG")
# (line offset, sample offset) keyword pairs: the PDS3 names, then Magellan's.
_OFFSET_KEYWORDS = (("LINE_PROJECTION_OFFSET", "SAMPLE_PROJECTION_OFFSET"),
                    ("X_AXIS_PROJECTION_OFFSET", "Y_AXIS_PROJECTION_OFFSET"))
_KM_UNITS = {"KM", "KILOMETER", "KILOMETERS", "KILOMETRE", "KILOMETRES"}
_EQUIRECTANGULAR = {"EQUIRECTANGULAR", "SIMPLE CYLINDRICAL", "SIMPLE_CYLINDRICAL",
                    "EQUIDISTANT", "CYLINDRICAL EQUAL DISTANCE"}
_SINUSOIDAL = {"SINUSOIDAL", "SINUSOIDAL EQUAL-AREA", "SINUSOIDAL_EQUAL-AREA"}
_POLAR = {"POLAR STEREOGRAPHIC", "POLAR_STEREOGRAPHIC"}
_TRANSVERSE_MERCATOR = {"TRANSVERSE MERCATOR", "TRANSVERSE_MERCATOR"}
_PLANETOCENTRIC = "PLANETOCENTRIC"


class LabelGeorefError(ValueError):
    """The label's map projection object cannot be turned into a CRS and geotransform."""


def projection_object(label: Mapping[str, Any]) -> Mapping[str, Any] | None:
    """The label's map projection object, at the top or inside UNCOMPRESSED_FILE."""
    for holder in (label, label.get("UNCOMPRESSED_FILE") or {}):
        for name in PROJECTION_OBJECTS:
            if name in holder:
                return holder[name]
    return None


def transverse_mercator_grid(label_text: str) -> TransverseMercatorGrid | None:
    """The true grid pdsgen's writer states in a Transverse Mercator label's comment, or None."""
    try:
        return read_grid_note(label_text)
    except GridNoteError as exc:
        raise LabelGeorefError(str(exc)) from None


def label_georeferencing(label: Mapping[str, Any], label_text: str | None = None
                         ) -> tuple[CRS, Affine] | None:
    """(CRS, geotransform) stated by the label, or None when it has no map projection.

    `label_text`, the label as written: a Transverse Mercator label's comment stating its
    true grid (pdsgen's writer) is then unfolded (module docstring); without it, or without
    the comment, the grid is the label's as PDS3 states it (scale factor 1, no false origin),
    the same ground positions.
    LabelGeorefError when the projection object is there but unusable (an
    unsupported projection type, a missing radius, scale or offset).
    """
    block = projection_object(label)
    if block is None:
        return None
    grid = None
    if _projection_kind(block) in _TRANSVERSE_MERCATOR and label_text is not None:
        grid = transverse_mercator_grid(label_text)
    grid = grid or UNFOLDED
    midr = magellan.is_midr_grid(str(block.get("DATA_SET_ID", "")), _projection_kind(block))
    crs = _crs(block, grid, magellan.MIDR_PROJECTION_RADIUS_M if midr else None)
    scale = _map_scale_m(block)
    line_offset, sample_offset = _offsets(block)
    if midr:  # the data set's own equations (magellan.py), not the label's radius
        sample_offset -= magellan.MIDR_SAMPLE_SHIFT
    ulx, uly = upper_left_corner(sample_offset, line_offset, scale)
    k = grid.scale_factor
    transform = Affine(scale * k, 0.0, ulx * k + grid.false_easting,
                       0.0, -scale * k, uly * k + grid.false_northing)
    return crs, transform


def _projection_kind(block: Mapping[str, Any]) -> str:
    return str(block.get("MAP_PROJECTION_TYPE", "")).strip().upper()


def _crs(block: Mapping[str, Any], grid: TransverseMercatorGrid, sphere_radius: float | None = None) -> CRS:
    kind = _projection_kind(block)
    a = _length_m(block, "A_AXIS_RADIUS", default_km=True)
    c = _optional_length_m(block, "C_AXIS_RADIUS") or a
    if sphere_radius is not None:  # a data set whose grid is defined on another sphere
        a = c = sphere_radius
    lon0 = wrap_180(east_positive(_degrees(block, "CENTER_LONGITUDE", 0.0),
                                  block.get("POSITIVE_LONGITUDE_DIRECTION")))
    lat0 = _degrees(block, "CENTER_LATITUDE", 0.0)
    origin = "+x_0=0 +y_0=0"
    if kind in _TRANSVERSE_MERCATOR:
        return transverse_mercator_crs(_geodetic(block, lat0, a, c), lon0, grid, a, c)
    if kind in _SINUSOIDAL:
        definition = f"+proj=sinu +lon_0={lon0!r} +R={a!r}"
    elif kind in _EQUIRECTANGULAR:
        definition = f"+proj=eqc +lat_ts={lat0!r} +lat_0=0 +lon_0={lon0!r} +R={a!r}"
    elif kind in _POLAR:
        pole = 90.0 if lat0 >= 0 else -90.0
        definition = f"+proj=stere +lat_0={pole!r} +lon_0={lon0!r} +k=1 +R={c!r}"
    else:
        raise LabelGeorefError(f"map projection {kind or 'not named'} is not one pdsgen can place "
                               "from a label (sinusoidal, equirectangular, polar stereographic, "
                               "transverse Mercator)")
    return _proj_crs(f"{definition} {origin} +units=m +no_defs +type=crs")


@functools.lru_cache(maxsize=256)
def _proj_crs(definition: str) -> CRS:
    """The CRS of a PROJ definition, made once per definition (a delivery's labels share a few)."""
    try:
        return CRS.from_proj4(definition)
    except CRSError as exc:
        raise LabelGeorefError(f"PROJ refuses the label's projection ({exc})") from None


def transverse_mercator_crs(geodetic_lat0: float, lon0: float, grid: TransverseMercatorGrid,
                            a: float, c: float) -> CRS:
    """Transverse Mercator on the ellipsoid of semi-axes a, c (metres), origin (geodetic latitude,
    east longitude in degrees), with the grid's scale factor and false origin."""
    return _proj_crs(f"+proj=tmerc +lat_0={geodetic_lat0!r} +lon_0={lon0!r} +k={grid.scale_factor!r} "
                     f"+a={a!r} +b={c!r} +x_0={grid.false_easting!r} +y_0={grid.false_northing!r} "
                     "+units=m +no_defs +type=crs")


def geodetic_latitude(planetocentric: float, a: float, c: float) -> float:
    """The geodetic (planetographic) latitude of a planetocentric one on the ellipsoid a, c."""
    if a == c or abs(planetocentric) >= 90.0:
        return planetocentric
    return math.degrees(math.atan(math.tan(math.radians(planetocentric)) * (a / c) ** 2))


def _geodetic(block: Mapping[str, Any], latitude: float, a: float, c: float) -> float:
    """A latitude of the label as PROJ takes it on an ellipsoid: geodetic (planetographic)."""
    kind = str(block.get("PROJECTION_LATITUDE_TYPE", block.get("COORDINATE_SYSTEM_NAME", ""))).strip().upper()
    return geodetic_latitude(latitude, a, c) if kind == _PLANETOCENTRIC else latitude


# -- a VICAR MAP group (formats/vicar.py reads it) ----------------------------------------------
@dataclass(frozen=True)
class VicarMap:
    """A VICAR MAP group's map projection as the label states it: its units, its counting
    (formats/vicar.py's read_map_group fills it in; here so that geo imports nothing of formats)."""

    projection_type: str  # upper case, words joined by "_" (TRANSVERSE_MERCATOR)
    a_axis_km: float
    c_axis_km: float
    center_latitude: float  # degrees, of the latitude type below
    center_longitude: float  # degrees, in the positive direction below
    latitude_type: str  # COORDINATE_SYSTEM_NAME: PLANETOGRAPHIC when absent
    positive_longitude_direction: str  # EAST when absent
    map_scale_km: float  # MAP_SCALE, kilometres of the grid per pixel
    line_projection_offset: float  # pixels, as the label counts them
    sample_projection_offset: float
    scale_factor: float  # SCALE_FACTOR, 1 when absent
    false_easting_m: float | None  # FALSE_EASTING / FALSE_NORTHING (metres) when the label gives either
    false_northing_m: float | None


def vicar_map_georeferencing(projection: VicarMap, offset_shift: float = 0.0) -> tuple[CRS, Affine]:
    """(CRS, geotransform in grid metres) of a Transverse Mercator VICAR MAP group.

    Transverse Mercator on the label's ellipsoid with its SCALE_FACTOR; false easting/northing
    from FALSE_EASTING/FALSE_NORTHING when given, else those of the UTM grid when the projection
    is a UTM zone (southern grid when the upper-left corner is not north of the equator), else
    none. The offsets count in the PDS3 standard convention once `offset_shift` pixels are taken
    from both (a producer's other counting: missions/hrsc_ax.py VICAR_OFFSETS).
    """
    a = projection.a_axis_km * 1000.0
    c = projection.c_axis_km * 1000.0
    k = projection.scale_factor
    lat0 = projection.center_latitude
    if projection.latitude_type == _PLANETOCENTRIC:
        lat0 = geodetic_latitude(lat0, a, c)
    lon0 = wrap_180(east_positive(projection.center_longitude, projection.positive_longitude_direction))
    scale = projection.map_scale_km * 1000.0  # grid metres per pixel
    x_left, y_top = upper_left_corner(projection.sample_projection_offset - offset_shift,
                                      projection.line_projection_offset - offset_shift, scale)
    if projection.false_easting_m is not None and projection.false_northing_m is not None:
        x0, y0 = projection.false_easting_m, projection.false_northing_m
    elif utm.is_utm(k, lat0, lon0):
        x0, y0 = utm.FALSE_EASTING, utm.false_northing(south=y_top <= 0)
    else:
        x0 = y0 = 0.0
    crs = transverse_mercator_crs(lat0, lon0, TransverseMercatorGrid(k, x0, y0), a, c)
    return crs, Affine(scale, 0.0, x0 + x_left, 0.0, -scale, y0 + y_top)


def _map_scale_m(block: Mapping[str, Any]) -> float:
    if "MAP_SCALE" not in block:
        raise LabelGeorefError("the map projection object has no MAP_SCALE")
    value, unit = _value_and_unit(block["MAP_SCALE"])
    # PDS3's standard unit is KM/PIXEL; archives also write M/PIXEL or METERS/PIXEL.
    per_pixel = unit.split("/")[0].strip() if unit else "KM"
    metres = value * (1000.0 if per_pixel in _KM_UNITS else 1.0)
    if not (math.isfinite(metres) and metres > 0):
        raise LabelGeorefError(f"MAP_SCALE {value!r} is not a positive pixel size")
    return metres


def _offsets(block: Mapping[str, Any]) -> tuple[float, float]:
    for line_key, sample_key in _OFFSET_KEYWORDS:
        if line_key in block and sample_key in block:
            line, _ = _value_and_unit(block[line_key])
            sample, _ = _value_and_unit(block[sample_key])
            if math.isfinite(line) and math.isfinite(sample):
                return line, sample
    raise LabelGeorefError("the map projection object gives no line and sample "
                           "projection offsets")


def _length_m(block: Mapping[str, Any], key: str, default_km: bool) -> float:
    metres = _optional_length_m(block, key, default_km)
    if metres is None:
        raise LabelGeorefError(f"the map projection object has no usable {key}")
    return metres


def _optional_length_m(block: Mapping[str, Any], key: str, default_km: bool = True
                       ) -> float | None:
    if key not in block:
        return None
    try:
        value, unit = _value_and_unit(block[key])
    except LabelGeorefError:
        return None
    km = unit in _KM_UNITS if unit else default_km
    metres = value * (1000.0 if km else 1.0)
    return metres if math.isfinite(metres) and metres > 0 else None


def _degrees(block: Mapping[str, Any], key: str, default: float) -> float:
    if key not in block:
        return default
    try:
        return _value_and_unit(block[key])[0]
    except LabelGeorefError:
        return default


def _value_and_unit(item: Any) -> tuple[float, str]:
    """A number and its upper-case unit (pvl Quantity or a plain number)."""
    value = getattr(item, "value", item)
    unit = str(getattr(item, "units", "") or "").strip().upper()
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise LabelGeorefError(f"{item!r} is not a number")
    return float(value), unit
