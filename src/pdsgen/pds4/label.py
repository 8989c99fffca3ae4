"""PDS4 label text from the same geometry and statistics the PDS3 labels use.

The label is rendered from jinja2 templates (`templates/pds4/`), UTF-8 XML with
two-space indentation. Values are XML-escaped by the template environment;
numbers pass through `format_number`, the PDS3 writer's noise-free formatting
(3396190.0000000005 -> 3396190.0), so labels are reproducible and readable.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Any

from affine import Affine
from rasterio.crs import CRS

from ..encode import EncodeError, xml_finalize
from ..geo.geometry import EQUIRECTANGULAR, POLAR_STEREOGRAPHIC, SINUSOIDAL, TRANSVERSE_MERCATOR, MapGeometry
from ..label.render import named_refusal, template_environment
from ..label.values import format_real
from ..resources import templates_dir
from .model import CURRENT_IM, InformationModel

if TYPE_CHECKING:
    import jinja2

# PDS3 projection type -> (cart:map_projection_name, element holding its parameters).
PROJECTION_NAMES = {
    EQUIRECTANGULAR: ("Equirectangular", "Equirectangular"),
    POLAR_STEREOGRAPHIC: ("Polar Stereographic", "Polar_Stereographic"),
    SINUSOIDAL: ("Sinusoidal", "Sinusoidal"),
    TRANSVERSE_MERCATOR: ("Transverse Mercator", "Transverse_Mercator"),
}
# The reverse, for reading labels back: cart:map_projection_name -> PDS3 projection type.
PDS3_PROJECTION = {name: pds3 for pds3, (name, _) in PROJECTION_NAMES.items()}


def format_number(value: Any) -> str:
    """Integers as they are; reals as in PDS3 labels (no float noise, round-trip exact)."""
    if isinstance(value, bool):
        raise TypeError("a boolean is not a number")
    if isinstance(value, int):
        return str(value)
    return format_real(value)


@cache
def _environment() -> jinja2.Environment:
    """The PDS3 template environment's settings, over `templates/pds4/`, escaping XML."""
    import jinja2  # on first use, as in label.render

    env = template_environment().overlay(loader=jinja2.FileSystemLoader(str(templates_dir() / "pds4")),
                                         autoescape=True, finalize=xml_finalize)
    env.filters = {**env.filters, "num": format_number}
    return env


def render_pds4(template_name: str, context: Mapping[str, Any], im: InformationModel = CURRENT_IM,
                source: str | os.PathLike[str] | None = None) -> str:
    """Render one PDS4 label template (UTF-8 XML text, LF line ends). A value XML cannot carry
    is refused (EncodeError) naming where in `context` it was and `source`, what it came from."""
    try:
        return _environment().get_template(template_name).render(im=im, **context)
    except EncodeError as exc:
        raise named_refusal(exc, context).naming(source=source) from None


@dataclass(frozen=True)
class Cartography:
    """What cart:Cartography states about a map-projected array."""

    projection_name: str
    projection_element: str
    projection_parameters: tuple[tuple[str, float], ...]
    resolution: float  # metres per pixel
    pixel_scale: float  # pixels per degree
    upper_left_x: float  # metres, GDAL geotransform origin (natural origin, no false easting)
    upper_left_y: float
    a_axis: float  # metres
    b_axis: float
    c_axis: float
    spheroid_name: str
    west: float
    east: float
    north: float
    south: float
    latitude_type: str = "Planetocentric"


def cartography(geometry: MapGeometry, crs: CRS, transform: Affine, target_name: str) -> Cartography:
    """cart: values of a north-up raster whose geometry `describe_geometry` accepted."""
    name, element = PROJECTION_NAMES[geometry.projection_type]
    params = crs.to_dict()
    # cart: states a Transverse Mercator grid as it is (its scale factor is a cart: field), so
    # its resolution is the grid spacing; PDS3 labels fold the scale factor into MAP_SCALE.
    k = geometry.scale_factor
    return Cartography(
        projection_name=name,
        projection_element=element,
        projection_parameters=_projection_parameters(geometry, params),
        resolution=geometry.map_scale * k,
        pixel_scale=geometry.map_resolution / k,
        upper_left_x=transform.c - geometry.false_easting,
        upper_left_y=transform.f - geometry.false_northing,
        a_axis=geometry.a_axis_km * 1000.0,
        b_axis=geometry.b_axis_km * 1000.0,
        c_axis=geometry.c_axis_km * 1000.0,
        spheroid_name=target_name,
        west=geometry.westernmost_longitude,
        east=geometry.easternmost_longitude,
        north=geometry.maximum_latitude,
        south=geometry.minimum_latitude,
        latitude_type=geometry.latitude_type.capitalize(),
    )


def _projection_parameters(geometry: MapGeometry, params: Mapping[str, Any]) -> tuple[tuple[str, float], ...]:
    """Each projection's required fields, in the cart schema's order."""
    lon0 = geometry.center_longitude
    if geometry.projection_type == EQUIRECTANGULAR:
        return (("latitude_of_projection_origin", float(params.get("lat_0", 0.0))),
                ("standard_parallel_1", geometry.center_latitude),
                ("longitude_of_central_meridian", lon0))
    if geometry.projection_type == POLAR_STEREOGRAPHIC:
        return (("longitude_of_central_meridian", lon0),
                ("latitude_of_projection_origin", geometry.center_latitude),
                ("scale_factor_at_projection_origin", 1.0))
    if geometry.projection_type == TRANSVERSE_MERCATOR:
        return (("scale_factor_at_central_meridian", geometry.scale_factor),
                ("longitude_of_central_meridian", lon0),
                ("latitude_of_projection_origin", geometry.center_latitude))
    return (("longitude_of_central_meridian", lon0),)
