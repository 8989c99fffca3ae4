"""Read what a JP2 says about itself: header (size, bands, precision) and georeferencing.

The GeoJP2 box is a UUID box holding a degenerate 1 x 1 GeoTIFF; its TIFF tags
(ModelPixelScale 33550, ModelTiepoint 33922, GeoKeyDirectory 34735, GeoDoubleParams
34736) are parsed here directly, so the GeoKey numbers themselves (3078 vs 3089) can
be checked. A GMLJP2 box (an `asoc` with GML XML) is read with lxml.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass, field
from pathlib import Path

from ..formats.geojp2 import (
    GEOJP2_UUID,
    MODEL_PIXEL_SCALE_TAG,
    MODEL_TIEPOINT_TAG,
    MODEL_TRANSFORMATION_TAG,
    geokeys_of,
)
from ..formats.geojp2 import tiff_tags as _tiff_tags

# GeoKey ids used by the checks
GT_RASTER_TYPE = 1025
PROJ_COORD_TRANS = 3075
PROJ_STD_PARALLEL1 = 3078
PROJ_NAT_ORIGIN_LONG = 3080
PROJ_NAT_ORIGIN_LAT = 3081
PROJ_CENTER_LONG = 3088
PROJ_CENTER_LAT = 3089
PROJ_STRAIGHT_VERT_POLE_LONG = 3095
PROJECTION_CODE = 3074  # ProjectionGeoKey: an EPSG projection (e.g. 16033 UTM zone 33N)
PROJ_FALSE_EASTING = 3082
PROJ_FALSE_NORTHING = 3083
PROJ_SCALE_AT_NAT_ORIGIN = 3092
GEOG_SEMI_MAJOR = 2057
GEOG_SEMI_MINOR = 2058
# GeoTIFF 1.0 (section 6.3) gives each GeoKey one type: these the checks read are DOUBLE (a
# SHORT is taken as its number) and these SHORT codes. A key of another type is a malformed box.
_DOUBLE_KEYS = frozenset({GEOG_SEMI_MAJOR, GEOG_SEMI_MINOR, PROJ_STD_PARALLEL1, PROJ_NAT_ORIGIN_LONG,
                          PROJ_NAT_ORIGIN_LAT, PROJ_FALSE_EASTING, PROJ_FALSE_NORTHING, PROJ_CENTER_LONG,
                          PROJ_CENTER_LAT, PROJ_SCALE_AT_NAT_ORIGIN, PROJ_STRAIGHT_VERT_POLE_LONG})
_SHORT_KEYS = frozenset({GT_RASTER_TYPE, PROJECTION_CODE, PROJ_COORD_TRANS})
CT_NAMES = {17: "EQUIRECTANGULAR", 24: "SINUSOIDAL", 15: "POLAR_STEREOGRAPHIC", 14: "STEREOGRAPHIC",
            7: "MERCATOR", 1: "TRANSVERSE_MERCATOR"}


@dataclass
class Georef:
    """Geotransform and GeoKeys from one georeferencing box."""

    source: str  # "GeoJP2" or "GMLJP2"
    ulx: float
    uly: float
    xres: float
    yres: float
    keys: dict[int, object] = field(default_factory=dict)


@dataclass
class Jp2Info:
    height: int
    width: int
    bands: int
    bits: int
    signed: bool
    georefs: list[Georef]
    # the georeferencing boxes that are there but cannot be read, each as "GeoJP2 box: why"
    unreadable_georefs: list[str] = field(default_factory=list)

    def unreadable(self, source: str) -> str | None:
        """Why the SOURCE ("GeoJP2", "GMLJP2") box cannot be read, if there is one that cannot."""
        return next((why for why in self.unreadable_georefs if why.startswith(f"{source} box")), None)


def grid_terms(keys: dict[int, object]) -> tuple[float, float, float]:
    """(scale factor, false easting, false northing) of a Transverse Mercator GeoKey set: its
    own parameters, or those of the UTM zone its ProjectionGeoKey (3074) names (EPSG 16001-16060
    north, 16101-16160 south: scale 0.9996, false easting 500 km, false northing 0 or 10,000 km)."""
    code = keys.get(PROJECTION_CODE)
    if isinstance(code, int) and (16001 <= code <= 16060 or 16101 <= code <= 16160):
        from ..geo import utm  # UTM's definition; imported only for a UTM GeoJP2
        return utm.SCALE_FACTOR, utm.FALSE_EASTING, utm.false_northing(south=code > 16060)

    def value(key: int, default: float) -> float:
        found = keys.get(key)
        return float(found) if isinstance(found, (int, float)) else default

    return (value(PROJ_SCALE_AT_NAT_ORIGIN, 1.0), value(PROJ_FALSE_EASTING, 0.0),
            value(PROJ_FALSE_NORTHING, 0.0))


class Jp2Error(Exception):
    """The file is not a JP2 that can be read."""


class GeorefError(ValueError):
    """A georeferencing box that is there but does not hold what its standard lays out."""


# The header boxes read whole (jp2h, uuid, asoc, xml ...): georeferencing is a few kB; a box
# claiming more is not read into memory (the code stream, jp2c, is never read here).
MAX_HEADER_BOX_BYTES = 16 * 1024 * 1024
_SUPERBOXES = {b"jp2h", b"asoc", b"res "}


@dataclass
class _Box:
    """One box as the checks ask of it: its type, its children (a superbox) and its XML."""

    box_id: str
    payload: bytes = b""
    box: list[_Box] = field(default_factory=list)
    xml: object = None


def read_jp2(path: Path) -> Jp2Info:
    """The header and georeferencing of a JP2, read box by box by pdsgen's own walk (every box
    length checked against the bytes there); the GeoTIFF of a GeoJP2 box is parsed by
    tiff_tags, whose counts are checked too. A general JP2 reader parsed that GeoTIFF itself,
    allocating whatever count a tag claimed."""
    from ..errors import InputError
    from ..formats.jp2 import jp2_boxes

    try:
        boxes = [_Box(kind.decode("latin-1"), _payload(path, offset, length), [])
                 for kind, offset, length in jp2_boxes(path) if kind != b"jp2c"]
        for box in boxes:
            _open_superbox(box)
    except (InputError, struct.error, OSError) as exc:
        raise Jp2Error(str(exc.problem if isinstance(exc, InputError) else exc)) from None
    ihdr = next((b for box in boxes if box.box_id == "jp2h" for b in box.box if b.box_id == "ihdr"), None)
    georefs: list[Georef] = []
    unreadable: list[str] = []
    for box in boxes:
        try:
            if box.box_id == "uuid" and box.payload[:16] == GEOJP2_UUID.bytes:
                ref = geotiff_georef(box.payload[16:])
            elif box.box_id == "asoc":
                ref = _gml_georef(box)
            else:
                continue
        except GeorefError as exc:
            unreadable.append(str(exc))
            continue
        if ref is not None:
            georefs.append(ref)
    if ihdr is None or len(ihdr.payload) < 14:
        raise Jp2Error("no JP2 header (ihdr) box")
    height, width, bands, depth = struct.unpack_from(">IIHB", ihdr.payload)
    if depth == 255:  # the components differ: the first one's, from the bpcc box
        bpcc = next((b for box in boxes if box.box_id == "jp2h" for b in box.box if b.box_id == "bpcc"), None)
        depth = bpcc.payload[0] if bpcc is not None and bpcc.payload else 0
    return Jp2Info(height, width, bands, (depth & 0x7F) + 1, bool(depth & 0x80), georefs, unreadable)


def _payload(path: Path, offset: int, length: int) -> bytes:
    """The contents of the box at OFFSET (its header skipped), refused past MAX_HEADER_BOX_BYTES."""
    from ..errors import InputError

    with open(path, "rb") as handle:
        handle.seek(offset)
        header = handle.read(16)
        skip = 16 if struct.unpack_from(">I", header)[0] == 1 else 8
        if length - skip > MAX_HEADER_BOX_BYTES:
            raise InputError(path, f"a JP2 header box of {length} bytes at byte {offset} is larger than "
                                   f"{MAX_HEADER_BOX_BYTES} bytes")
        handle.seek(offset + skip)
        return handle.read(length - skip)


def _open_superbox(box: _Box, depth: int = 0) -> None:
    """The children of a superbox (jp2h, asoc, res), walked within its payload, each length
    checked against the bytes there; an xml box's text parsed without network or entities."""
    from lxml import etree

    from ..bounded import MAX_DEPTH, checked_count

    if box.box_id == "xml ":
        parser = etree.XMLParser(no_network=True, resolve_entities=False, huge_tree=False)
        try:
            box.xml = etree.fromstring(box.payload, parser)
        except etree.XMLSyntaxError:
            box.xml = None
        return
    if box.box_id.encode("latin-1") not in _SUPERBOXES or depth > MAX_DEPTH:
        return
    data, position = box.payload, 0
    while position + 8 <= len(data):
        length, kind = struct.unpack_from(">I4s", data, position)
        skip = 8
        if length == 1:
            (length,) = struct.unpack_from(">Q", data, position + 8)
            skip = 16
        elif length == 0:
            length = len(data) - position
        if length < skip:
            break
        checked_count(box.box_id, f"the JP2 {kind.decode('latin-1')!r} box", length, 1, len(data) - position)
        child = _Box(kind.decode("latin-1"), data[position + skip:position + length])
        _open_superbox(child, depth + 1)
        box.box.append(child)
        position += length


def geotiff_georef(data: bytes) -> Georef | None:
    """Geotransform and GeoKeys of the GeoTIFF inside a GeoJP2 box; None when it gives its grid
    by ModelTransformation alone (not what the checks compare). Raises GeorefError, saying
    why, when the box is not a GeoTIFF, its grid tags are not finite numbers or a GeoKey the
    checks read is not of its GeoTIFF type - a box a reader would misread or ignore, which is
    a finding of its own, not "no GeoJP2 box"."""
    try:
        tags = _tiff_tags(data)
        keys = geokeys_of(tags)
    except (ValueError, struct.error) as exc:
        raise GeorefError(f"GeoJP2 box: its GeoTIFF cannot be read ({exc})") from None
    if MODEL_PIXEL_SCALE_TAG not in tags and MODEL_TIEPOINT_TAG not in tags and MODEL_TRANSFORMATION_TAG in tags:
        return None
    scale = _finite_numbers(tags, MODEL_PIXEL_SCALE_TAG, "ModelPixelScale", 2)
    tie = _finite_numbers(tags, MODEL_TIEPOINT_TAG, "ModelTiepoint", 6)
    keys = _typed_geokeys(keys)
    sx, sy = scale[0], scale[1]
    i, j, x, y = tie[0], tie[1], tie[3], tie[4]
    ulx, uly = x - i * sx, y + j * sy
    if keys.get(GT_RASTER_TYPE) == 2:  # PixelIsPoint: the tie point is a pixel centre
        ulx, uly = ulx - sx / 2, uly + sy / 2
    return Georef("GeoJP2", ulx, uly, sx, sy, keys)


def _finite_numbers(tags: dict[int, tuple], tag: int, name: str, at_least: int) -> tuple[float, ...]:
    """The values of a GeoTIFF grid tag, DOUBLE as GeoTIFF gives it (a FLOAT read too), at least
    AT_LEAST of them, every one finite."""
    values = tags.get(tag)
    if values is None:
        raise GeorefError(f"GeoJP2 box: its GeoTIFF has no {name} ({tag})")
    if len(values) < at_least or not all(isinstance(v, float) and math.isfinite(v) for v in values):
        raise GeorefError(f"GeoJP2 box: {name} ({tag}) holds {_shown(values)}, not {at_least} or more "
                          "finite DOUBLE values")
    return tuple(float(v) for v in values)


def _typed_geokeys(keys: dict[int, object]) -> dict[int, object]:
    """KEYS with each one the checks read of its GeoTIFF type: a DOUBLE key a finite float (a
    SHORT taken as its number), a SHORT key an int."""
    typed = dict(keys)
    for key, value in keys.items():
        if key in _DOUBLE_KEYS:
            if type(value) not in (int, float) or not math.isfinite(value):  # type: ignore[arg-type]
                raise GeorefError(f"GeoJP2 box: GeoKey {key} holds {_shown(value)}, not one finite number")
            typed[key] = float(value)  # type: ignore[arg-type]
        elif key in _SHORT_KEYS and type(value) is not int:
            raise GeorefError(f"GeoJP2 box: GeoKey {key} holds {_shown(value)}, not a SHORT code")
    return typed


def _shown(value: object) -> str:
    """A value from the box as a finding shows it: its repr, at most 60 characters."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _gml_georef(box) -> Georef | None:
    """Origin and offset vectors of a GMLJP2 RectifiedGrid, if the asoc box holds one."""
    for child in getattr(box, "box", []) or []:
        xml = getattr(child, "xml", None)
        if xml is None and getattr(child, "box", None):
            found = _gml_georef(child)
            if found is not None:
                return found
        if xml is None:
            continue
        root = xml.getroot() if hasattr(xml, "getroot") else xml
        origin = [e for e in root.iter() if isinstance(e.tag, str) and e.tag.endswith("}pos")
                  and e.getparent() is not None and e.getparent().tag.endswith("}Point")]
        vectors = [e for e in root.iter() if isinstance(e.tag, str) and e.tag.endswith("}offsetVector")]
        if not origin or len(vectors) < 2:
            continue
        ox, oy = _gml_pair(origin[0], "the grid origin")
        v1 = _gml_pair(vectors[0], "the first offset vector")
        v2 = _gml_pair(vectors[1], "the second offset vector")
        xres, yres = v1[0], -v2[1]
        # GML grid origin is the centre of the first pixel
        return Georef("GMLJP2", ox - xres / 2, oy + yres / 2, xres, yres)
    return None


def _gml_pair(element, what: str) -> tuple[float, float]:
    """The first two numbers of a GML position or vector, both finite, or GeorefError."""
    words = (element.text or "").split()[:2]
    try:
        pair = tuple(float(word) for word in words)
    except ValueError:
        pair = ()
    if len(pair) != 2 or not all(math.isfinite(v) for v in pair):
        raise GeorefError(f"GMLJP2 box: {what} is {_shown(element.text)}, not two finite numbers")
    return pair
