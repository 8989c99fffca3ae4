"""Georeferencing from a PDS3 label's map projection object, for products GDAL cannot place.

GDAL's PDS driver reads `IMAGE_MAP_PROJECTION` with the names current PDS3 labels
use. Older map products describe the same grid differently and GDAL then reports
no georeferencing at all: Magellan's F-MIDR framelets carry an
`IMAGE_MAP_PROJECTION_CATALOG` whose `X_AXIS_PROJECTION_OFFSET` counts lines and
`Y_AXIS_PROJECTION_OFFSET` samples (Magellan's axes: X down the image, Y across).
The Extras still need a CRS and a geotransform for the scale bar and the north
arrow, so this module builds them from the label:

- the CRS as a PROJ definition on a sphere or ellipsoid of the label's radii
  (sinusoidal and equirectangular from A_AXIS_RADIUS; polar stereographic from
  C_AXIS_RADIUS, as GDAL does), handed to rasterio's CRS (PROJ);
- the geotransform with the standard PDS3 offset convention
  (`ULX = -(SAMPLE_PROJECTION_OFFSET + 0.5) * MAP_SCALE`,
  `ULY = (LINE_PROJECTION_OFFSET + 0.5) * MAP_SCALE`; docs section 4), the
  convention GDAL itself applies to PDS3 labels.

West-positive labels give their longitudes west; the projection's central
meridian is turned east-positive, as PROJ expects, and x still grows to the east.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from typing import Any

from rasterio.crs import CRS
from rasterio.errors import CRSError
from rasterio.transform import Affine

PROJECTION_OBJECTS = ("IMAGE_MAP_PROJECTION", "IMAGE_MAP_PROJECTION_CATALOG")
# (line offset, sample offset) keyword pairs: the PDS3 names, then Magellan's.
_OFFSET_KEYWORDS = (("LINE_PROJECTION_OFFSET", "SAMPLE_PROJECTION_OFFSET"),
                    ("X_AXIS_PROJECTION_OFFSET", "Y_AXIS_PROJECTION_OFFSET"))
_KM_UNITS = {"KM", "KILOMETER", "KILOMETERS", "KILOMETRE", "KILOMETRES"}
_EQUIRECTANGULAR = {"EQUIRECTANGULAR", "SIMPLE CYLINDRICAL", "SIMPLE_CYLINDRICAL",
                    "EQUIDISTANT", "CYLINDRICAL EQUAL DISTANCE"}
_SINUSOIDAL = {"SINUSOIDAL", "SINUSOIDAL EQUAL-AREA", "SINUSOIDAL_EQUAL-AREA"}
_POLAR = {"POLAR STEREOGRAPHIC", "POLAR_STEREOGRAPHIC"}


class LabelGeorefError(ValueError):
    """The label's map projection object cannot be turned into a CRS and geotransform."""


def projection_object(label: Mapping[str, Any]) -> Mapping[str, Any] | None:
    """The label's map projection object, at the top or inside UNCOMPRESSED_FILE."""
    for holder in (label, label.get("UNCOMPRESSED_FILE") or {}):
        for name in PROJECTION_OBJECTS:
            if name in holder:
                return holder[name]
    return None


def label_georeferencing(label: Mapping[str, Any]) -> tuple[CRS, Affine] | None:
    """(CRS, geotransform) stated by the label, or None when it has no map projection.

    LabelGeorefError when the projection object is there but unusable (an
    unsupported projection type, a missing radius, scale or offset).
    """
    block = projection_object(label)
    if block is None:
        return None
    crs = _crs(block)
    scale = _map_scale_m(block)
    line_offset, sample_offset = _offsets(block)
    transform = Affine(scale, 0.0, -(sample_offset + 0.5) * scale,
                       0.0, -scale, (line_offset + 0.5) * scale)
    return crs, transform


def _crs(block: Mapping[str, Any]) -> CRS:
    kind = str(block.get("MAP_PROJECTION_TYPE", "")).strip().upper()
    a = _length_m(block, "A_AXIS_RADIUS", default_km=True)
    c = _optional_length_m(block, "C_AXIS_RADIUS") or a
    lon0 = _degrees(block, "CENTER_LONGITUDE", 0.0)
    if str(block.get("POSITIVE_LONGITUDE_DIRECTION", "EAST")).strip().upper() == "WEST":
        lon0 = -lon0
    lon0 = (lon0 + 180.0) % 360.0 - 180.0
    lat0 = _degrees(block, "CENTER_LATITUDE", 0.0)
    if kind in _SINUSOIDAL:
        definition = f"+proj=sinu +lon_0={lon0!r} +R={a!r}"
    elif kind in _EQUIRECTANGULAR:
        definition = f"+proj=eqc +lat_ts={lat0!r} +lat_0=0 +lon_0={lon0!r} +R={a!r}"
    elif kind in _POLAR:
        pole = 90.0 if lat0 >= 0 else -90.0
        definition = f"+proj=stere +lat_0={pole!r} +lon_0={lon0!r} +k=1 +R={c!r}"
    else:
        raise LabelGeorefError(f"map projection {kind or 'not named'} is not one the Extras "
                               "can place (sinusoidal, equirectangular, polar stereographic)")
    return _proj_crs(f"{definition} +x_0=0 +y_0=0 +units=m +no_defs +type=crs")


@functools.lru_cache(maxsize=256)
def _proj_crs(definition: str) -> CRS:
    """The CRS of a PROJ definition, made once per definition (a delivery's labels share a few)."""
    try:
        return CRS.from_proj4(definition)
    except CRSError as exc:
        raise LabelGeorefError(f"PROJ refuses the label's projection ({exc})") from None


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
