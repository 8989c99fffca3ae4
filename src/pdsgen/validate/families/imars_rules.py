"""IMARS family: an iMars metadata file (`*_ucl.pvl`) agrees with its GeoTIFF and footprint.

The PVL restates what the GeoTIFF holds (size, sample type, no-data DN, scaling,
geotransform, CRS, valid DN range) for readers that do not open GeoTIFF tags; these
rules read both and say where they differ, with the expected (GeoTIFF) and found
(PVL) values. The footprint `<hOOOO_NNNN>.geojson` is shared by a scene's DTM and
orthoimage, one feature per product, matched by `id` = ProductInfo.ProductId.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np

from ...missions.hrsc import parse_name as parse_hrsc_name
from ...missions.imars import METADATA_SUFFIX as IMARS_METADATA_SUFFIX
from ...missions.imars import MOSAIC_KEYWORD, metadata_name, mosaic_base
from ...missions.imars import footprint_name as imars_footprint_name
from ..imars_context import ImarsContext
from ..model import Hit
from ..registry import Rule, register

REQUIRED_OBJECTS = ("ProductInfo", "Image", "DataProduct", "MapProjection", "Algorithm")
REQUIRED_KEYWORDS = {
    "ProductInfo": ("ProductId",),
    "Image": ("Lines", "Samples", "Bands", "SampleType", "NoData", "ScalingFactor", "Offset",
              "ValidMinimum", "ValidMaximum"),
    "DataProduct": ("FileName",),
    "MapProjection": ("PixelResolution", "UpperLeftCornerX", "UpperLeftCornerY", "Proj4"),
}
TOLERANCE_PX = 1e-3
_GDAL_TYPES = {"byte": "uint8", "int8": "int8", "uint16": "uint16", "int16": "int16", "uint32": "uint32",
               "int32": "int32", "float32": "float32", "float64": "float64"}
_LENGTH_TO_M = {"m": 1.0, "meter": 1.0, "meters": 1.0, "metre": 1.0, "metres": 1.0, "km": 1000.0}


def _number(value: Any) -> float | None:
    """A PVL number (bare or a Quantity in m/km) in metres/plain units, else None."""
    units = None
    if hasattr(value, "value") and hasattr(value, "units"):
        value, units = value.value, value.units
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    factor = _LENGTH_TO_M.get(str(units).strip().lower(), 1.0) if units else 1.0
    return float(value) * factor


def _shown(value: Any) -> str:
    if hasattr(value, "value") and hasattr(value, "units"):
        return f"{value.value!r} <{value.units}>"
    return repr(value)


def _same(a: float, b: float) -> bool:
    return a == b or abs(a - b) <= 1e-9 * max(1.0, abs(a), abs(b))


def check_parses(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-001: the metadata file is PVL the pvl library can read."""
    if ctx.parse_error is not None:
        exc = ctx.parse_error
        line = getattr(exc, "lineno", None)
        text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        yield Hit(f"the metadata file does not parse as PVL: {text}", line if isinstance(line, int) else None)


def check_structure(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-002: required objects (ProductInfo with group Producer ...) and keywords are present."""
    if ctx.module is None:
        return
    missing = [name for name in REQUIRED_OBJECTS if ctx.obj(name) is None]
    if missing:
        yield Hit(f"missing object(s) {', '.join(missing)}; an iMars metadata file has "
                  f"{', '.join(REQUIRED_OBJECTS)}", 1, missing[0])
    if ctx.obj("ProductInfo") is not None and ctx.obj("ProductInfo", "Producer") is None:
        yield Hit("ProductInfo lacks its group Producer (Institution, Contact, Software)",
                  ctx.line("ProductInfo"), "Producer")
    for name, keys in REQUIRED_KEYWORDS.items():
        if ctx.obj(name) is None:
            continue
        absent = [k for k in keys if ctx.value(name, k) is None]
        if absent:
            yield Hit(f"{name} lacks {', '.join(absent)}", ctx.line(name), absent[0])


def product_id(ctx: ImarsContext) -> str | None:
    value = ctx.value("ProductInfo", "ProductId")
    return str(value).strip() if isinstance(value, str) and value.strip() else None


def check_product_id(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-003: the file is named `<ProductId>_ucl.pvl`."""
    pid = product_id(ctx)
    if pid is None:
        return
    expected = metadata_name(pid)
    if ctx.path.name.lower() != expected.lower():
        yield Hit(f"ProductInfo.ProductId = {pid} but the file is named {ctx.path.name}; expected "
                  f"{expected}", ctx.line("ProductInfo", "ProductId"), "ProductId")


def check_data_file(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-004: DataProduct.FileName names a file beside the metadata, in the same case."""
    name = ctx.data_name
    if name is None:
        return
    exact, other = ctx.resolve(name)
    line = ctx.line("DataProduct", "FileName")
    if exact is None and other is not None:
        yield Hit(f"DataProduct.FileName = {name} but the file beside it is {other.name} (case differs; "
                  "case-sensitive file systems will not find it)", line, "FileName")
    elif exact is None:
        yield Hit(f"DataProduct.FileName = {name}, which is not in {ctx.path.parent}", line, "FileName")


def check_opens(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-005: GDAL opens the data file, and it is a GeoTIFF."""
    if ctx.data_path is None:
        return
    dataset = ctx.dataset()
    line = ctx.line("DataProduct", "FileName")
    if dataset is None:
        yield Hit(f"GDAL cannot open {ctx.data_path.name}: {ctx.open_error}", line, "FileName")
    elif dataset.driver != "GTiff":
        yield Hit(f"{ctx.data_path.name} opens as {dataset.driver}, expected a GeoTIFF (GTiff)", line,
                  "FileName")


def _image_pairs(dataset) -> list[tuple[str, Any]]:
    return [("Lines", dataset.height), ("Samples", dataset.width), ("Bands", dataset.count),
            ("SampleType", dataset.dtypes[0]), ("NoData", dataset.nodata),
            ("ScalingFactor", dataset.scales[0]), ("Offset", dataset.offsets[0])]


def _sample_type(text: str) -> str:
    name = text.strip().lower()
    return _GDAL_TYPES.get(name, name)


def check_image(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-006: Image Lines/Samples/Bands/SampleType/NoData/ScalingFactor/Offset = the GeoTIFF's."""
    dataset = ctx.dataset()
    if dataset is None or ctx.obj("Image") is None:
        return
    for key, actual in _image_pairs(dataset):
        found = ctx.value("Image", key)
        if found is None:
            continue
        line = ctx.line("Image", key)
        if key == "SampleType":
            if not isinstance(found, str) or _sample_type(found) != _sample_type(str(actual)):
                yield Hit(f"Image SampleType = {found} but {dataset.name.rsplit('/', 1)[-1]} holds "
                          f"{actual}; expected SampleType = {actual}", line, key)
            continue
        number = _number(found)
        if actual is None:
            yield Hit(f"Image {key} = {_shown(found)} but the GeoTIFF has no {key} value", line, key)
        elif number is None or not _same(number, float(actual)):
            integral = key in ("Lines", "Samples", "Bands", "NoData") and float(actual).is_integer()
            shown = int(actual) if integral else actual
            yield Hit(f"Image {key} = {_shown(found)} but the GeoTIFF's is {shown!r}; expected "
                      f"{key} = {shown!r}", line, key)


def check_geotransform(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-007: PixelResolution and UpperLeftCornerX/Y = the GeoTIFF's geotransform (1e-3 px)."""
    dataset = ctx.dataset()
    if dataset is None or ctx.obj("MapProjection") is None:
        return
    t = dataset.transform
    line = ctx.line("MapProjection")
    if t.b != 0 or t.d != 0 or not _same(abs(t.a), abs(t.e)) or t.a <= 0 or t.e >= 0:
        yield Hit(f"the GeoTIFF's geotransform {tuple(t)[:6]} is not north-up with square pixels, "
                  "which PixelResolution/UpperLeftCorner cannot describe", line, "PixelResolution")
        return
    pixel = t.a
    size = max(dataset.width, dataset.height)
    checks = (("PixelResolution", pixel, size), ("UpperLeftCornerX", t.c, 1), ("UpperLeftCornerY", t.f, 1))
    for key, actual, reach in checks:
        found = ctx.value("MapProjection", key)
        value = _number(found)
        if found is None:
            continue
        if value is None:
            yield Hit(f"MapProjection {key} = {_shown(found)} is not a number; expected {actual!r} <m>",
                      ctx.line("MapProjection", key), key)
            continue
        off_px = abs(value - actual) * reach / pixel
        if off_px > TOLERANCE_PX:
            what = "at the far edge of the raster" if key == "PixelResolution" else ""
            yield Hit(f"MapProjection {key} = {_shown(found)} but the GeoTIFF's is {actual!r} m "
                      f"({off_px:.4g} px off{' ' + what if what else ''}); expected {key} = {actual!r} <m>",
                      ctx.line("MapProjection", key), key)


def _crs_params(crs) -> dict[str, Any]:
    return {k: v for k, v in crs.to_dict().items() if k not in ("no_defs", "type", "wktext")}


def _same_crs(a, b) -> bool:
    if a == b:
        return True
    pa, pb = _crs_params(a), _crs_params(b)
    if pa.keys() != pb.keys():
        return False
    for key, va in pa.items():
        vb = pb[key]
        if isinstance(va, (int, float)) and isinstance(vb, (int, float)):
            if not _same(float(va), float(vb)):
                return False
        elif va != vb:
            return False
    return True


def check_crs(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-008: MapProjection Proj4 is the GeoTIFF's coordinate reference system."""
    dataset = ctx.dataset()
    text = ctx.value("MapProjection", "Proj4")
    if dataset is None or not isinstance(text, str):
        return
    from rasterio.crs import CRS
    from rasterio.errors import CRSError

    line = ctx.line("MapProjection", "Proj4")
    actual = dataset.crs
    if actual is None:
        yield Hit(f"MapProjection Proj4 = \"{text}\" but the GeoTIFF has no CRS", line, "Proj4")
        return
    try:
        stated = CRS.from_proj4(text)
    except CRSError as exc:
        yield Hit(f"MapProjection Proj4 = \"{text}\" is not a PROJ string GDAL reads ({exc}); expected "
                  f"\"{actual.to_proj4()}\"", line, "Proj4")
        return
    if not _same_crs(stated, actual):
        yield Hit(f"MapProjection Proj4 = \"{text}\" but the GeoTIFF's CRS is \"{actual.to_proj4()}\"",
                  line, "Proj4")


def valid_range(dataset) -> tuple[float, float] | None:
    """(min, max) of band 1 without no-data (and NaN) samples, read block by block."""
    nodata = dataset.nodata
    low, high = math.inf, -math.inf
    for _, window in dataset.block_windows(1):
        block = dataset.read(1, window=window)
        valid = np.ones(block.shape, dtype=bool) if nodata is None else block != nodata
        if block.dtype.kind == "f":
            valid &= np.isfinite(block)
            if nodata is not None and math.isnan(nodata):
                valid = np.isfinite(block)
        if valid.any():
            values = block[valid]
            low, high = min(low, float(values.min())), max(high, float(values.max()))
    return None if low > high else (low, high)


def check_valid_range(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-009: ValidMinimum/ValidMaximum = the data's valid range (streamed by blocks)."""
    dataset = ctx.dataset()
    if dataset is None or ctx.obj("Image") is None:
        return
    stated = {k: ctx.value("Image", k) for k in ("ValidMinimum", "ValidMaximum")}
    if all(v is None for v in stated.values()):
        return
    found = valid_range(dataset)
    for key, actual in zip(stated, found or (None, None), strict=True):
        value = _number(stated[key])
        if stated[key] is None:
            continue
        line = ctx.line("Image", key)
        if actual is None:
            yield Hit(f"Image {key} = {_shown(stated[key])} but the data hold no valid samples", line, key)
        elif value is None or not _same(value, actual):
            shown = int(actual) if actual.is_integer() else actual
            yield Hit(f"Image {key} = {_shown(stated[key])} but the data's valid samples give {shown!r}; "
                      f"expected {key} = {shown!r}", line, key)


def footprint_name(ctx: ImarsContext) -> str | None:
    """`<hOOOO_NNNN>.geojson`: the scene part of the product id (or of the file name);
    a mosaic's: `<ID>.geojson` of its `<ID>_dtm` / `<ID>_ori`."""
    base = mosaic_base(product_id(ctx) or "") if is_mosaic(ctx) else None
    if base:
        return imars_footprint_name(base)
    for candidate in (product_id(ctx) or "", ctx.path.name):
        match = parse_hrsc_name(candidate)
        if match:
            return imars_footprint_name(candidate[: match.end("sequence")])
    return None


def _footprint(ctx: ImarsContext) -> tuple[dict | None, str | None]:
    """(parsed collection, problem) of the scene footprint."""
    cache = ctx.cache.get("_footprint")
    if cache is not None:
        return cache
    name = footprint_name(ctx)
    result: tuple[dict | None, str | None]
    if name is None:
        result = None, "no scene id (hOOOO_NNNN) in ProductInfo.ProductId or the file name to name it"
    else:
        exact, other = ctx.resolve(name)
        if exact is None:
            where = f" (found {other.name}: case differs)" if other is not None else ""
            result = None, f"footprint {name} is not in {ctx.path.parent}{where}"
        else:
            from ...bounded import load_json
            from ...errors import InputError

            try:
                data = load_json(exact, what="GeoJSON file")
            except InputError as exc:
                result = None, f"footprint {name} is not JSON: {exc.problem}"
            else:
                if not isinstance(data, dict) or data.get("type") != "FeatureCollection" \
                        or not isinstance(data.get("features"), list):
                    kind = data.get("type") if isinstance(data, dict) else type(data).__name__
                    result = None, (f"footprint {name} is not a GeoJSON FeatureCollection with a features "
                                    f"list (type {kind!r})")
                else:
                    result = data, None
    ctx.cache["_footprint"] = result
    return result


def check_footprint(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-010: the scene footprint `<hOOOO_NNNN>.geojson` exists and is a FeatureCollection."""
    if ctx.module is None:
        return
    _, problem = _footprint(ctx)
    if problem is not None:
        yield Hit(problem, ctx.line("ProductInfo", "ProductId"), "ProductId")


def is_mosaic(ctx: ImarsContext) -> bool:
    return ctx.value("Image", MOSAIC_KEYWORD) is not None


def check_footprint_feature(ctx: ImarsContext) -> Iterator[Hit]:
    """IMARS-011: the footprint has a feature whose id is ProductInfo.ProductId (a mosaic: one
    for each of its SourceProductId)."""
    pid = product_id(ctx)
    collection, _ = _footprint(ctx) if ctx.module is not None else (None, None)
    if pid is None or collection is None:
        return
    ids = [f.get("id") for f in collection["features"] if isinstance(f, dict)]
    if is_mosaic(ctx):
        sources = ctx.value("ProductInfo", "SourceProductId")
        missing = [s for s in (sources if isinstance(sources, list) else [sources]) if s not in ids]
        if missing:
            yield Hit(f"footprint {footprint_name(ctx)} has no feature for the mosaic's source(s) "
                      f"{', '.join(map(str, missing))}", ctx.line("ProductInfo", "SourceProductId"),
                      "SourceProductId")
        return
    if pid not in ids:
        yield Hit(f"footprint {footprint_name(ctx)} has no feature with id {pid} (ids found: "
                  f"{', '.join(map(str, ids)) or 'none'})", ctx.line("ProductInfo", "ProductId"), "ProductId")


register(
    Rule("IMARS-001", "error", "the iMars metadata file parses as PVL", check_parses, target="imars"),
    Rule("IMARS-002", "error", "ProductInfo (with Producer), Image, DataProduct, MapProjection, "
         "Algorithm and their keywords are present", check_structure, target="imars"),
    Rule("IMARS-003", "error", f"the file is named <ProductInfo.ProductId>{IMARS_METADATA_SUFFIX}",
         check_product_id,
         target="imars"),
    Rule("IMARS-004", "error", "DataProduct.FileName exists beside the metadata (exact case)",
         check_data_file, needs_data=True, target="imars"),
    Rule("IMARS-005", "error", "GDAL opens the data file as a GeoTIFF", check_opens, needs_data=True,
         target="imars"),
    Rule("IMARS-006", "error", "Image size, bands, sample type, NoData, scaling and offset = the GeoTIFF's",
         check_image, needs_data=True, target="imars"),
    Rule("IMARS-007", "error", "PixelResolution, UpperLeftCornerX/Y = the GeoTIFF geotransform (1e-3 px)",
         check_geotransform, needs_data=True, target="imars"),
    Rule("IMARS-008", "error", "MapProjection Proj4 = the GeoTIFF's CRS", check_crs, needs_data=True,
         target="imars"),
    Rule("IMARS-009", "error", "ValidMinimum/ValidMaximum = the data's valid range", check_valid_range,
         needs_data=True, target="imars"),
    Rule("IMARS-010", "error", "the footprint <hOOOO_NNNN>.geojson exists and is a FeatureCollection",
         check_footprint, needs_data=True, target="imars"),
    Rule("IMARS-011", "error", "the footprint has a feature whose id is ProductInfo.ProductId",
         check_footprint_feature, needs_data=True, target="imars"),
)
