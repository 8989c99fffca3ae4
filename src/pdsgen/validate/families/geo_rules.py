"""GEO family: a JPEG 2000 product and its detached label tell the same story.

The JP2 is the file COMPRESSED_FILE's FILE_NAME names. Its header must match the
label's image (LINES, LINE_SAMPLES, BANDS, bits), and its GeoJP2/GMLJP2 boxes must carry
the label's geotransform (within 1e-3 px) and projection parameters. For equirectangular
the standard parallel belongs in ProjStdParallel1GeoKey (3078); HiRISE's writer once put
it in ProjCenterLatGeoKey (3089), GDAL ticket 2706.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

from ...label.tree import Block
from ..context import FileContext
from ..geojp2 import (
    CT_NAMES,
    GEOG_SEMI_MAJOR,
    PROJ_CENTER_LAT,
    PROJ_CENTER_LONG,
    PROJ_COORD_TRANS,
    PROJ_NAT_ORIGIN_LONG,
    PROJ_STD_PARALLEL1,
    PROJ_STRAIGHT_VERT_POLE_LONG,
    Jp2Error,
    Jp2Info,
    grid_terms,
    read_jp2,
)
from ..model import Hit
from ..projection import normalise, projection_radius_key
from ..quantities import is_image
from ..quantities import kilometres as _km
from ..quantities import metres_per_pixel as _scale_m
from ..quantities import number as _num
from ..registry import Rule, register

GEOTRANSFORM_TOLERANCE_PX = 1e-3


def _compressed(ctx: FileContext) -> tuple[Block, str] | None:
    for block in ctx.root.find("COMPRESSED_FILE"):
        name = block.text("FILE_NAME")
        encoding = (block.text("ENCODING_TYPE") or "").upper()
        if name and (encoding.startswith("JP2") or name.upper().endswith((".JP2", ".J2K"))):
            return block, name
    return None


def _jp2(ctx: FileContext) -> tuple[Block, Path | None, Jp2Info | None, str | None] | None:
    """(COMPRESSED_FILE block, path, header, problem) computed once per file."""
    if ctx.labels_only:
        return None
    if "_jp2" in ctx.cache:
        return ctx.cache["_jp2"]
    found = _compressed(ctx)
    result: tuple[Block, Path | None, Jp2Info | None, str | None] | None = None
    if found is not None:
        block, name = found
        exact, other = ctx.resolve(name)
        path = exact or other
        if path is None:
            result = (block, None, None, f"FILE_NAME {name} names a JP2 that is not in {ctx.path.parent}")
        else:
            try:
                result = (block, path, read_jp2(path), None)
            except Jp2Error as exc:
                result = (block, path, None, f"{path.name} is not a readable JPEG 2000 file ({exc})")
    ctx.cache["_jp2"] = result
    return result


def _image(ctx: FileContext) -> Block | None:
    return next((b for b in ctx.root.walk() if is_image(b)), None)


def _map(ctx: FileContext) -> Block | None:
    return next(ctx.root.find("IMAGE_MAP_PROJECTION"), None)


def check_readable(ctx: FileContext) -> Iterator[Hit]:
    found = _jp2(ctx)
    if found is not None and found[3] is not None:
        line = found[0].get("FILE_NAME")
        yield Hit(found[3], line.line if line else found[0].line, "FILE_NAME")


def check_header(ctx: FileContext) -> Iterator[Hit]:
    found = _jp2(ctx)
    image = _image(ctx)
    if found is None or found[2] is None or image is None:
        return
    info, name = found[2], found[1].name  # type: ignore[union-attr]
    bits = image.number("SAMPLE_BITS")
    mask = image.value("SAMPLE_BIT_MASK")
    if mask is not None and mask.is_number and int(mask.number) > 0:
        bits = int(mask.number).bit_length()
    signed = "UNSIGNED" not in (image.text("SAMPLE_TYPE") or "UNSIGNED")
    for key, label_value, jp2_value in (
        ("LINES", image.number("LINES"), info.height),
        ("LINE_SAMPLES", image.number("LINE_SAMPLES"), info.width),
        ("BANDS", image.number("BANDS") or 1, info.bands),
        ("SAMPLE_BITS", bits, info.bits),
    ):
        if label_value is not None and label_value != jp2_value:
            stmt = image.get(key)
            what = "precision" if key == "SAMPLE_BITS" else key.lower()
            yield Hit(f"{key} gives {label_value} but {name} has {what} {jp2_value}",
                      stmt.line if stmt else image.line, key)
    if image.get("SAMPLE_TYPE") is not None and signed != info.signed:
        stmt = image.get("SAMPLE_TYPE")
        yield Hit(f"SAMPLE_TYPE {image.text('SAMPLE_TYPE')} but {name} samples are "
                  f"{'signed' if info.signed else 'unsigned'}", stmt.line if stmt else None, "SAMPLE_TYPE")


def check_has_georef(ctx: FileContext) -> Iterator[Hit]:
    found = _jp2(ctx)
    if found is not None and found[2] is not None and not found[2].georefs and not found[2].unreadable_georefs \
            and _map(ctx) is not None:
        yield Hit(f"{found[1].name} has no GeoJP2 or GMLJP2 box: GIS readers cannot place it",  # type: ignore[union-attr]
                  found[0].line, "FILE_NAME")


def check_georef_readable(ctx: FileContext) -> Iterator[Hit]:
    """A GeoJP2 or GMLJP2 box that is there but malformed: a reader misreads or ignores it,
    which is not the same as a JP2 that carries none (GEO-003)."""
    found = _jp2(ctx)
    if found is None or found[2] is None:
        return
    for why in found[2].unreadable_georefs:
        yield Hit(f"{found[1].name}: {why}", found[0].line, "FILE_NAME")  # type: ignore[union-attr]


def _label_transform(ctx: FileContext) -> tuple[float, float, float] | None:
    block = _map(ctx)
    if block is None:
        return None
    scale, spo, lpo = _scale_m(block), _num(block, "SAMPLE_PROJECTION_OFFSET"), _num(block, "LINE_PROJECTION_OFFSET")
    if scale is None or spo is None or lpo is None:
        return None
    return -(spo + 0.5) * scale, (lpo + 0.5) * scale, scale


def check_geotransform(ctx: FileContext) -> Iterator[Hit]:
    found = _jp2(ctx)
    label = _label_transform(ctx)
    if found is None or found[2] is None or label is None:
        return
    ulx, uly, scale = label
    info = found[2]
    map_block = _map(ctx)
    spo = map_block.get("SAMPLE_PROJECTION_OFFSET") if map_block is not None else None
    line = spo.line if spo is not None else None
    folds = normalise(map_block.text("MAP_PROJECTION_TYPE") or "") == "TRANSVERSE_MERCATOR" \
        if map_block is not None else False
    for ref in info.georefs:
        k, east, north = grid_terms(ref.keys) if folds else (1.0, 0.0, 0.0)
        # A TM label carries the grid's scale factor and false origin folded into MAP_SCALE and
        # the offsets (PDS3 has no keywords for them): compare the JP2's grid in those terms.
        ref_ulx, ref_uly = (ref.ulx - east) / k, (ref.uly - north) / k
        ref_xres, ref_yres = ref.xres / k, ref.yres / k
        dx, dy = (ref_ulx - ulx) / scale, (uly - ref_uly) / scale
        dsx = (ref_xres - scale) * info.width / scale
        dsy = (ref_yres - scale) * info.height / scale
        worst = max(abs(dx), abs(dy), abs(dsx), abs(dsy))
        if worst > GEOTRANSFORM_TOLERANCE_PX:
            yield Hit(
                f"{ref.source} geotransform of {found[1].name} differs from the label: upper-left "  # type: ignore[union-attr]
                f"corner {dx:+.4f} px (x), {dy:+.4f} px (y); pixel size {ref_xres!r} x {ref_yres!r} m vs "
                f"MAP_SCALE {scale!r} m ({dsx:+.4f} / {dsy:+.4f} px across the image); expected "
                f"upper-left ({ulx!r}, {uly!r})",
                line,
                "SAMPLE_PROJECTION_OFFSET",
            )


def _center_longitude(keys: dict[int, object]) -> float | None:
    for key in (PROJ_CENTER_LONG, PROJ_NAT_ORIGIN_LONG, PROJ_STRAIGHT_VERT_POLE_LONG):
        value = keys.get(key)
        if isinstance(value, (int, float)):
            return float(value)
    return None


def check_projection(ctx: FileContext) -> Iterator[Hit]:
    found = _jp2(ctx)
    block = _map(ctx)
    if found is None or found[2] is None or block is None:
        return
    name = normalise(block.text("MAP_PROJECTION_TYPE") or "")
    for ref in found[2].georefs:
        keys = ref.keys
        if not keys:
            continue
        problems = []
        ct = keys.get(PROJ_COORD_TRANS)
        ct_name = CT_NAMES.get(ct, "") if isinstance(ct, int) else ""
        ct_name = ct_name or f"coordinate transformation {ct}"
        label_name = "EQUIRECTANGULAR" if name in ("SIMPLE_CYLINDRICAL", "EQUIDISTANT") else name
        if ct is not None and ct_name != label_name and not (
            label_name == "POLAR_STEREOGRAPHIC" and ct_name == "STEREOGRAPHIC"
        ):
            problems.append(f"projection {ct_name}, label {block.text('MAP_PROJECTION_TYPE')}")
        lon = _center_longitude(keys)
        label_lon = _num(block, "CENTER_LONGITUDE")
        if lon is not None and label_lon is not None:
            if (block.text("POSITIVE_LONGITUDE_DIRECTION") or "EAST").upper() == "WEST":
                label_lon = -label_lon
            if abs((lon - label_lon + 180) % 360 - 180) > 1e-9:
                problems.append(f"central meridian {lon!r}, label CENTER_LONGITUDE {label_lon!r}")
        radius = _km(block, projection_radius_key(name))
        semi_major = keys.get(GEOG_SEMI_MAJOR)
        if radius is not None and isinstance(semi_major, float) and not math.isclose(
            semi_major, radius * 1000.0, rel_tol=1e-9
        ):
            problems.append(f"sphere radius {semi_major!r} m, label {projection_radius_key(name)} "
                            f"{radius * 1000.0!r} m")
        if name in ("EQUIRECTANGULAR",) and PROJ_STD_PARALLEL1 in keys:
            lat = _num(block, "CENTER_LATITUDE")
            if lat is not None and abs(float(keys[PROJ_STD_PARALLEL1]) - lat) > 1e-9:  # type: ignore[arg-type]
                problems.append(f"standard parallel {keys[PROJ_STD_PARALLEL1]!r}, label CENTER_LATITUDE {lat!r}")
        for problem in problems:
            yield Hit(f"{ref.source} of {found[1].name}: {problem}", block.line,  # type: ignore[union-attr]
                      "MAP_PROJECTION_TYPE")


def check_std_parallel_key(ctx: FileContext) -> Iterator[Hit]:
    found = _jp2(ctx)
    block = _map(ctx)
    if found is None or found[2] is None or block is None:
        return
    if normalise(block.text("MAP_PROJECTION_TYPE") or "") != "EQUIRECTANGULAR":
        return
    lat = _num(block, "CENTER_LATITUDE")
    for ref in found[2].georefs:
        keys = ref.keys
        if ref.source != "GeoJP2" or keys.get(PROJ_COORD_TRANS) != 17 or not lat:
            continue
        if PROJ_STD_PARALLEL1 not in keys and float(keys.get(PROJ_CENTER_LAT, 0.0)) == lat:  # type: ignore[arg-type]
            yield Hit(f"GeoJP2 of {found[1].name} puts the standard parallel {lat!r} in "  # type: ignore[union-attr]
                      "ProjCenterLatGeoKey (3089) instead of ProjStdParallel1GeoKey (3078) "
                      "(GDAL ticket 2706)", block.line, "CENTER_LATITUDE")
        elif PROJ_STD_PARALLEL1 not in keys:
            yield Hit(f"GeoJP2 of {found[1].name} has no ProjStdParallel1GeoKey (3078) for the "  # type: ignore[union-attr]
                      f"standard parallel {lat!r}", block.line, "CENTER_LATITUDE")


register(
    Rule("GEO-001", "error", "the JP2 file opens and is a JPEG 2000 file", check_readable,
         needs_data=True),
    Rule("GEO-002", "error", "JP2 size, bands and precision agree with the label", check_header,
         needs_data=True),
    Rule("GEO-003", "warning", "the JP2 carries a GeoJP2 or GMLJP2 box", check_has_georef,
         needs_data=True),
    Rule("GEO-004", "error", "GeoJP2/GMLJP2 geotransform agrees with the label within 1e-3 px",
         check_geotransform, needs_data=True),
    Rule("GEO-005", "error", "GeoJP2 projection parameters agree with the label",
         check_projection, needs_data=True),
    Rule("GEO-006", "error", "equirectangular standard parallel in key 3078, not 3089",
         check_std_parallel_key, needs_data=True),
    Rule("GEO-007", "error", "a GeoJP2 or GMLJP2 box the JP2 carries can be read (a GeoTIFF of finite grid "
         "tags and GeoKeys of their types; a GML grid of numbers)", check_georef_readable, needs_data=True),
)
