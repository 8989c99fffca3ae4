"""PDS4 cartography checks: cart: values against each other and against the georeferencing.

Pixel scale against resolution and the body radius; bounding coordinates against
Geo_Transformation within half a pixel (with the validator's own closed-form sphere
projections, not the writer's PROJ computation); a JP2's GeoJP2 box against cart:.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from lxml import etree

from ..geojp2 import Jp2Error, grid_terms, read_jp2
from ..projection import Sphere, boundary
from .label_tree import C, P, Pds4Hits, data_path, file_areas, number

_SPHERE_NAMES = {"Equirectangular": "EQUIRECTANGULAR", "Polar Stereographic": "POLAR_STEREOGRAPHIC",
                 "Sinusoidal": "SINUSOIDAL"}


@dataclass
class _Cart:
    element: etree._Element
    projection: str
    parameters: etree._Element | None
    resolution_x: float
    resolution_y: float
    scale: float | None
    ulx: float
    uly: float
    a: float
    c: float
    bounds: dict[str, float]
    bound_lines: dict[str, int | None]
    encoding: str
    lines: int
    samples: int


def _read_cart(tree: etree._ElementTree) -> _Cart | None:
    cart = tree.find(f".//{C}Cartography")
    if cart is None:
        return None
    horizontal = f"{C}Spatial_Reference_Information/{C}Horizontal_Coordinate_System_Definition"
    planar = cart.find(f"{horizontal}/{C}Planar")
    model = cart.find(f"{horizontal}/{C}Geodetic_Model")
    if planar is None or model is None:
        return None
    projection = planar.findtext(f"{C}Map_Projection/{C}map_projection_name") or ""
    parameters = planar.find(f"{C}Map_Projection/{C}{projection.replace(' ', '_')}")
    rep = f"{C}Planar_Coordinate_Information/{C}Coordinate_Representation"
    values = {
        "rx": number(planar, f"{rep}/{C}pixel_resolution_x"),
        "ry": number(planar, f"{rep}/{C}pixel_resolution_y"),
        "ulx": number(planar, f"{C}Geo_Transformation/{C}upperleft_corner_x"),
        "uly": number(planar, f"{C}Geo_Transformation/{C}upperleft_corner_y"),
        "a": number(model, f"{C}a_axis_radius"),
        "c": number(model, f"{C}c_axis_radius"),
    }
    if any(v is None for v in values.values()):
        return None
    box = cart.find(f"{C}Spatial_Domain/{C}Bounding_Coordinates")
    bounds, bound_lines = {}, {}
    for side in ("west", "east", "north", "south"):
        value = number(box, f"{C}{side}_bounding_coordinate")
        if value is not None:
            bounds[side] = value
            bound_lines[side] = box.find(f"{C}{side}_bounding_coordinate").sourceline
    encoding = planar.findtext(f"{C}Planar_Coordinate_Information/{C}planar_coordinate_encoding_method") or ""
    ref = cart.findtext(f"{P}Local_Internal_Reference/{P}local_identifier_reference")
    array = next((a for a in tree.iter() if isinstance(a.tag, str) and a.tag.startswith(f"{P}Array")
                  and a.findtext(f"{P}local_identifier") == ref), None)
    if array is None:
        return None
    axes = {a.findtext(f"{P}axis_name"): int(number(a, f"{P}elements") or 0)
            for a in array.findall(f"{P}Axis_Array")}
    return _Cart(cart, projection, parameters, values["rx"], values["ry"],  # type: ignore[arg-type]
                 number(planar, f"{rep}/{C}pixel_scale_x"), values["ulx"], values["uly"],  # type: ignore[arg-type]
                 values["a"], values["c"], bounds, bound_lines, encoding,  # type: ignore[arg-type]
                 axes.get("Line", 0), axes.get("Sample", 0))


def _angle(parameters: etree._Element | None, name: str, default: float = 0.0) -> float:
    value = number(parameters, f"{C}{name}") if parameters is not None else None
    return default if value is None else value


def check_cartography(report: Pds4Hits, tree: etree._ElementTree) -> None:
    cart = _read_cart(tree)
    if cart is None:
        return
    if cart.parameters is None:
        report.add("PDS4-032", f"map_projection_name {cart.projection!r} but no cart:"
                               f"{cart.projection.replace(' ', '_')} block holds its parameters",
                   cart.element.sourceline, "map_projection_name")
        return
    sphere_name = _SPHERE_NAMES.get(cart.projection)
    if sphere_name is None:  # a projection pdsgen does not write: its arithmetic is not checked
        return
    radius = cart.c if sphere_name == "POLAR_STEREOGRAPHIC" else cart.a
    if cart.scale is not None and radius > 0 and cart.resolution_x > 0:
        expected = math.pi * radius / 180.0 / cart.resolution_x
        if not math.isclose(cart.scale, expected, rel_tol=1e-6):
            report.add("PDS4-030", f"pixel_scale_x = {cart.scale:.10g} pixel/deg but pixel_resolution_x = "
                                   f"{cart.resolution_x:.10g} m on a {radius:.10g} m radius gives {expected:.10g}",
                       cart.element.sourceline, "pixel_scale_x")
    _check_bounds(report, cart, sphere_name, radius)


def _check_bounds(report: Pds4Hits, cart: _Cart, sphere_name: str, radius: float) -> None:
    """Only "Coordinate Pair" encodings give Geo_Transformation in projection metres
    (as GDAL reads them); other encodings are not checked."""
    if len(cart.bounds) != 4 or not cart.lines or not cart.samples or cart.encoding != "Coordinate Pair":
        return
    centre_lat = _angle(cart.parameters, "standard_parallel_1",
                        _angle(cart.parameters, "latitude_of_projection_origin"))
    if sphere_name != "EQUIRECTANGULAR":
        centre_lat = _angle(cart.parameters, "latitude_of_projection_origin")
    sphere = Sphere(sphere_name, radius, centre_lat, _angle(cart.parameters, "longitude_of_central_meridian"))
    y_shift = 0.0
    if sphere_name == "EQUIRECTANGULAR":  # a latitude of origin shifts northings
        y_shift = radius * math.radians(_angle(cart.parameters, "latitude_of_projection_origin"))
    x0, x1 = cart.ulx, cart.ulx + cart.samples * cart.resolution_x
    y1, y0 = cart.uly + y_shift, cart.uly + y_shift - cart.lines * cart.resolution_y
    lats, lons = sphere.inverse(*boundary(x0, x1, y0, y1))
    extremes = {"north": int(np.nanargmax(lats)), "south": int(np.nanargmin(lats))}
    if not sphere.contains_pole(x0, x1, y0, y1):
        extremes.update(west=int(np.nanargmin(lons)), east=int(np.nanargmax(lons)))
    for side, index in extremes.items():
        lat, lon = float(lats[index]), float(lons[index])
        found = lon if side in ("west", "east") else lat
        stated = cart.bounds[side]
        difference = (stated - found + 180.0) % 360.0 - 180.0 if side in ("west", "east") else stated - found
        pixels = abs(difference) * _metres_per_degree(sphere, lat, lon, side in ("west", "east")) / cart.resolution_x
        if pixels > 0.5:
            report.add("PDS4-031", f"{side}_bounding_coordinate = {stated:.10g} but Geo_Transformation "
                                   f"({cart.ulx:.10g}, {cart.uly:.10g}) gives {_wrap_bound(found, side):.10g} "
                                   f"({pixels:.2f} px off)",
                       cart.bound_lines.get(side), f"{side}_bounding_coordinate")
    if sphere.contains_pole(x0, x1, y0, y1):
        pole = "north" if sphere.north else "south"
        if abs(cart.bounds[pole]) != 90.0:
            report.add("PDS4-031", f"{pole}_bounding_coordinate = {cart.bounds[pole]:.10g} but the raster "
                                   "contains the pole", cart.bound_lines.get(pole), f"{pole}_bounding_coordinate")


def _metres_per_degree(sphere: Sphere, lat: float, lon: float, along_longitude: bool) -> float:
    """Projected metres per degree at a point, in longitude or latitude (numerically)."""
    step = 1e-4
    lat = max(-90.0 + step, min(90.0 - step, lat))
    x0, y0 = sphere.forward(lat, lon)
    x1, y1 = sphere.forward(lat, lon + step) if along_longitude else sphere.forward(lat - step, lon)
    return float(math.hypot(x1 - x0, y1 - y0)) / step


def _wrap_bound(value: float, side: str) -> float:
    return value % 360.0 if side in ("west", "east") else value


def check_encoded_jp2(report: Pds4Hits, tree: etree._ElementTree) -> None:
    cart = _read_cart(tree)
    for area in file_areas(tree):
        encoded = area.find(f"{P}Encoded_Image")
        if encoded is None or encoded.findtext(f"{P}encoding_standard_id") not in ("JP2", "J2C"):
            continue
        path = data_path(report, area, report_missing=False)
        if path is None or cart is None:
            continue
        try:
            info = read_jp2(path)
        except Jp2Error as exc:
            report.add("PDS4-040", f"{path.name} is not a readable JP2: {exc}", encoded.sourceline)
            continue
        georef = next((g for g in info.georefs if g.source == "GeoJP2"), None)
        if georef is None:
            why = info.unreadable("GeoJP2")
            report.add("PDS4-040", f"{path.name}: {why}" if why else f"{path.name} has no GeoJP2 box",
                       encoded.sourceline)
            continue
        # cart: corners count from the projection's natural origin (no false easting or
        # northing in its projection classes); the GeoJP2 grid's may carry one (UTM)
        _, east, north = grid_terms(georef.keys)
        for name, stated, found in (("upperleft_corner_x", cart.ulx, georef.ulx - east),
                                    ("upperleft_corner_y", cart.uly, georef.uly - north),
                                    ("pixel_resolution_x", cart.resolution_x, georef.xres)):
            if not math.isclose(stated, found, rel_tol=1e-9, abs_tol=1e-6 * cart.resolution_x):
                report.add("PDS4-040", f"cart:{name} = {stated:.10g} but the GeoJP2 box of {path.name} "
                                       f"gives {found:.10g}", encoded.sourceline, name)
