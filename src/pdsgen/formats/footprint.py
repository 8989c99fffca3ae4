"""GIS footprints: the outline of a product's valid data as GeoJSON in longitude/latitude.

The outline is traced on a decimated validity mask (at most FOOTPRINT_SIZE pixels a
side), so it costs one small read whatever the raster's size. Coordinates are
degrees (planetocentric on a sphere), longitudes in -180..180 as GeoJSON readers expect; the
body is named in the collection's properties since GeoJSON itself assumes Earth.
"""

from __future__ import annotations

import datetime
import json
import os
from pathlib import Path
from typing import Any

import numpy as np
from rasterio.crs import CRS
from rasterio.enums import Resampling
from rasterio.features import shapes
from rasterio.io import DatasetReader
from rasterio.warp import transform_geom

from ..errors import PdsgenError
from ..geo.geometry import ellipsoid_axes, geographic_crs

FOOTPRINT_SIZE = 1024


def valid_data_outline(dataset: DatasetReader, valid_fn) -> list[dict[str, Any]]:
    """Polygons (GeoJSON geometries, lon/lat) around the pixels `valid_fn` accepts."""
    scale = max(1.0, max(dataset.width, dataset.height) / FOOTPRINT_SIZE)
    shape = (max(1, round(dataset.height / scale)), max(1, round(dataset.width / scale)))
    sample = dataset.read(1, out_shape=shape, resampling=Resampling.nearest)
    valid = valid_fn(sample).astype(np.uint8)
    transform = dataset.transform @ dataset.transform.scale(dataset.width / shape[1], dataset.height / shape[0])
    lonlat = geographic_crs(*ellipsoid_axes(dataset.crs, dataset.name))
    polygons = []
    for geometry, value in shapes(valid, mask=valid.astype(bool), transform=transform, connectivity=8):
        if value:
            polygons.append(transform_geom(dataset.crs, lonlat, geometry, antimeridian_cutting=True, precision=7))
    return polygons


def write_footprint(
    path: str | os.PathLike[str], staged_path: str | os.PathLike[str], feature_id: str,
    polygons: list[dict[str, Any]], properties: dict[str, Any], body: str,
) -> dict[str, Any]:
    """Add or replace one product's feature in the scene's footprint collection.

    One footprint file serves a scene: the DTM and the orthoimage of an iMars
    delivery each contribute their own feature, matched by `feature_id`. The
    merged collection is written to `staged_path` (published with the product);
    an existing file that is not a FeatureCollection is never replaced.
    """
    return write_footprints(path, staged_path, [(feature_id, polygons, properties)], body)


def write_footprints(
    path: str | os.PathLike[str], staged_path: str | os.PathLike[str],
    features: list[tuple[str, list[dict[str, Any]], dict[str, Any]]], body: str,
) -> dict[str, Any]:
    """write_footprint for several features at once (a mosaic: one per source product)."""
    path = Path(path)
    collection: dict[str, Any] = {"type": "FeatureCollection", "properties": {"body": body}, "features": []}
    ids = {feature_id for feature_id, _, _ in features}
    if path.exists():
        collection["features"] = [f for f in _existing_features(path) if f.get("id") not in ids]
    for feature_id, polygons, properties in features:
        geometry = (
            {"type": "MultiPolygon", "coordinates": [poly["coordinates"] for poly in polygons
                                                     if poly["type"] == "Polygon"]}
            if len(polygons) != 1 else polygons[0]
        )
        collection["features"].append(
            {"type": "Feature", "id": feature_id, "properties": {"product_id": feature_id, **properties},
             "geometry": geometry}
        )
    collection["features"].sort(key=lambda feature: str(feature.get("id")))
    with open(staged_path, "w") as handle:  # streamed: a mosaic's many outlines never held as one text
        json.dump(collection, handle, indent=1)
        handle.write("\n")
    return collection


SHAPEFILE_PARTS = (".shp", ".shx", ".dbf", ".prj", ".qpj")


def footprint_wkt(crs: CRS) -> str:
    """The longitude/latitude CRS of a footprint (on the product's body), in ESRI's WKT
    dialect as .prj files hold it."""
    return geographic_crs(*ellipsoid_axes(crs)).to_wkt(version="WKT1_ESRI")
_FIELDS = (("PRODUCT_ID", 40), ("TYPE", 8), ("FILE", 80))


def write_shapefile(collection: dict[str, Any], staged: dict[str, Path], wkt: str, updated: datetime.date) -> None:
    """The footprint collection as an ESRI Shapefile: one polygon record per product.

    `staged` maps each of SHAPEFILE_PARTS to the path to write it to; `wkt` is the
    longitude/latitude CRS of the coordinates (the .prj in ESRI's WKT dialect, the
    .qpj, QGIS's copy of it, likewise). pyshp writes .shp/.shx/.dbf; rings are
    wound as the format requires (outer rings clockwise, holes counter-clockwise).
    `updated` is the .dbf header's date of last update: pyshp writes the wall clock's day
    there, which would make the same input give other bytes on another day, so the
    product's own day of making replaces it (dbf_updated).
    """
    import shapefile  # pyshp: a small pure-Python writer for exactly this format

    with open(staged[".shp"], "wb") as shp, open(staged[".shx"], "wb") as shx, open(staged[".dbf"], "wb") as dbf:
        writer = shapefile.Writer(shp=shp, shx=shx, dbf=dbf, shapeType=shapefile.POLYGON)
        for name, size in _FIELDS:
            writer.field(name, "C", size=size)
        for feature in collection["features"]:
            writer.poly(_shapefile_rings(feature["geometry"]))
            properties = feature.get("properties", {})
            writer.record(str(feature.get("id", "")), str(properties.get("type", "")),
                          str(properties.get("file", "")))
        writer.close()
    dbf_updated(staged[".dbf"], updated)
    for part in (".prj", ".qpj"):
        Path(staged[part]).write_text(wkt + "\n")


def dbf_updated(path: Path, day: datetime.date) -> None:
    """Set a dBASE III table's date of last update: header bytes 1-3 are the year - 1900, the
    month and the day (dBASE III file structure; the year byte holds 1900-2155)."""
    if not 1900 <= day.year <= 2155:
        raise PdsgenError(path, f"a .dbf header cannot hold the year {day.year} (the day of making)")
    with open(path, "r+b") as table:
        table.seek(1)
        table.write(bytes((day.year - 1900, day.month, day.day)))


def _shapefile_rings(geometry: dict[str, Any]) -> list[list[list[float]]]:
    polygons = [geometry["coordinates"]] if geometry["type"] == "Polygon" else geometry["coordinates"]
    rings = []
    for polygon in polygons:
        for index, ring in enumerate(polygon):
            clockwise = _signed_area(ring) < 0
            outer = index == 0
            rings.append([list(point) for point in (ring if clockwise == outer else ring[::-1])])
    return rings


def _signed_area(ring: list[list[float]]) -> float:
    """Shoelace area: positive for counter-clockwise rings (x east, y north)."""
    return 0.5 * sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(ring, ring[1:] + ring[:1], strict=True))


def _existing_features(path: Path) -> list[dict[str, Any]]:
    from ..bounded import load_json
    from ..errors import InputError

    try:
        existing = load_json(path, what="GeoJSON file")
    except InputError:
        existing = None
    if not isinstance(existing, dict) or existing.get("type") != "FeatureCollection" or not isinstance(
        existing.get("features"), list
    ):
        raise PdsgenError(path, "exists and is not a GeoJSON FeatureCollection; move it away to write the footprint")
    return [f for f in existing["features"] if isinstance(f, dict)]
