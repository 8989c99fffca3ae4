"""Georeferencing boxes for JP2 files: GeoJP2 (always) and GMLJP2 (optional).

GeoJP2 is a UUID box holding a degenerate 1 x 1 GeoTIFF whose tags
(ModelPixelScale, ModelTiepoint, GeoKeys) apply to the JP2 image grid. GDAL
writes the GeoTIFF, so the GeoKeys follow GDAL's mapping of the CRS; for
equirectangular that puts the standard parallel in ProjStdParallel1GeoKey
(3078), not in ProjCenterLatGeoKey (3089) as an early HiRISE writer did.
`geokeys()` reads the keys back so tests and callers can check that.

GMLJP2 (version 1 layout) is an association box labelled ``gml.data`` holding
a ``gml.root-instance`` feature collection with a RectifiedGrid (origin and
offset vectors at pixel centres, as the standard defines them) and a
``CRSDictionary.gml`` entry holding the CRS as WKT in a gml:remarks element.
GDAL takes the grid from it; GML has no encoding GDAL reads for planetary
projections, so a reader gets the CRS from the GeoJP2 box.
"""

from __future__ import annotations

import struct
import uuid
from typing import Any

import numpy as np
from affine import Affine
from rasterio.crs import CRS
from rasterio.io import MemoryFile

from ..bounded import checked_count
from .jp2 import box, jp2_boxes

GEOJP2_UUID = uuid.UUID("b14bf8bd-083d-4b43-a5ae-8cd7d5a6ce03")
GEOKEY_DIRECTORY_TAG = 34735
GEO_DOUBLE_PARAMS_TAG = 34736
GEO_ASCII_PARAMS_TAG = 34737
MODEL_PIXEL_SCALE_TAG = 33550
MODEL_TIEPOINT_TAG = 33922
MODEL_TRANSFORMATION_TAG = 34264
PROJ_STD_PARALLEL1 = 3078
PROJ_CENTER_LAT = 3089

GML = "http://www.opengis.net/gml"
_NSMAP = {"gml": GML, "xlink": "http://www.w3.org/1999/xlink"}


def degenerate_geotiff(crs: CRS, transform: Affine) -> bytes:
    """A 1 x 1 GeoTIFF whose georeferencing is `crs` and `transform`."""
    with MemoryFile() as memory:
        with memory.open(
            driver="GTiff", width=1, height=1, count=1, dtype="uint8", crs=crs, transform=transform
        ) as dataset:
            dataset.write(np.zeros((1, 1, 1), dtype=np.uint8))
        return bytes(memory.read())


def geojp2_box(crs: CRS, transform: Affine) -> bytes:
    """The GeoJP2 UUID box for a JP2 image with this CRS and geotransform."""
    return box(b"uuid", GEOJP2_UUID.bytes + degenerate_geotiff(crs, transform))


def geokeys(tiff: bytes) -> dict[int, object]:
    """GeoKey number -> value (int, float, tuple of floats, or str) of a GeoTIFF."""
    return geokeys_of(tiff_tags(tiff))


# TIFF field type -> (struct code, bytes per value); 5 (RATIONAL) is two longs.
_TIFF_TYPES = {1: ("B", 1), 2: ("c", 1), 3: ("H", 2), 4: ("I", 4), 5: ("II", 8), 6: ("b", 1),
               8: ("h", 2), 9: ("i", 4), 11: ("f", 4), 12: ("d", 8), 16: ("Q", 8)}


def tiff_tags(data: bytes, source: str = "GeoTIFF") -> dict[int, tuple[Any, ...]]:
    """Tag number -> values of the first image directory of a classic TIFF (ASCII as a 1-tuple).

    The one GeoTIFF reader of the package: the tests read the writer's GeoJP2 box
    with it, and the validator reads any producer's. Raises ValueError (or
    struct.error on a truncated file) when the bytes are not a classic TIFF; a directory or
    tag claiming more values than the bytes hold is refused (InputError, a ValueError, naming
    SOURCE) before anything of that size is made.
    """
    order = {b"II": "<", b"MM": ">"}.get(data[:2])
    if order is None:
        raise ValueError("not a TIFF")
    (magic,) = struct.unpack_from(order + "H", data, 2)
    if magic != 42:
        raise ValueError("not a classic TIFF")
    (ifd,) = struct.unpack_from(order + "I", data, 4)
    (count,) = struct.unpack_from(order + "H", data, ifd)
    checked_count(source, "the TIFF image directory", count, 12, len(data) - ifd - 2)
    tags: dict[int, tuple[Any, ...]] = {}
    for i in range(count):
        tag, typ, n, raw = struct.unpack_from(order + "HHI4s", data, ifd + 2 + 12 * i)
        if typ not in _TIFF_TYPES:
            continue
        fmt, size = _TIFF_TYPES[typ]
        total = size * n
        if total <= 4:
            blob = raw[:total]
        else:
            (offset,) = struct.unpack(order + "I", raw)
            checked_count(source, f"TIFF tag {tag}", n, size, len(data) - offset)
            blob = data[offset : offset + total]
        if typ == 2:
            tags[tag] = (blob.rstrip(b"\x00").decode("latin-1"),)
        else:
            tags[tag] = struct.unpack(f"{order}{n * len(fmt)}{fmt[0]}", blob)
    return tags


def geokeys_of(tags: dict[int, tuple[Any, ...]]) -> dict[int, object]:
    """The GeoKeys a GeoKeyDirectory (34735) lists, with their double (34736) and ASCII (34737) values.

    Raises ValueError when the three tags are not of the types GeoTIFF gives them (the
    directory SHORT, the parameters DOUBLE and ASCII) or a key's values lie past the end of
    its parameter tag: another producer's bytes, not a directory to index blindly."""
    keys: dict[int, object] = {}
    directory = tags.get(GEOKEY_DIRECTORY_TAG)
    doubles = tags.get(GEO_DOUBLE_PARAMS_TAG, ())
    asciis = tags.get(GEO_ASCII_PARAMS_TAG, ("",))[0]
    if directory is not None and not all(type(v) is int for v in directory):
        raise ValueError("the GeoKeyDirectory (34735) does not hold SHORT values")
    if not all(isinstance(v, float) for v in doubles):
        raise ValueError("GeoDoubleParams (34736) does not hold DOUBLE values")
    if not isinstance(asciis, str):
        raise ValueError("GeoAsciiParams (34737) does not hold ASCII text")
    if directory and len(directory) >= 4:
        for k in range(min(directory[3], (len(directory) - 4) // 4)):  # no more keys than entries
            key, loc, count, value = directory[4 + 4 * k : 8 + 4 * k]
            if loc in (GEO_DOUBLE_PARAMS_TAG, GEO_ASCII_PARAMS_TAG) and value + count > len(
                    doubles if loc == GEO_DOUBLE_PARAMS_TAG else asciis):
                raise ValueError(f"GeoKey {key} lies past the end of its parameters (tag {loc})")
            if loc == 0:
                keys[key] = value
            elif loc == GEO_DOUBLE_PARAMS_TAG:
                keys[key] = doubles[value] if count == 1 else tuple(doubles[value : value + count])
            elif loc == GEO_ASCII_PARAMS_TAG:
                keys[key] = asciis[value : value + count].rstrip("|")
    return keys


def read_geojp2(path) -> bytes:
    """The GeoTIFF inside a JP2 file's GeoJP2 box (for checks and tests)."""
    with open(path, "rb") as handle:
        for kind, offset, length in jp2_boxes(path):
            if kind != b"uuid":
                continue
            handle.seek(offset + 8)
            if handle.read(16) == GEOJP2_UUID.bytes:
                return handle.read(max(length - 24, 0))
    raise ValueError(f"{path} has no GeoJP2 box")


def gmljp2_box(crs: CRS, transform: Affine, lines: int, samples: int) -> bytes:
    """A GMLJP2 association box consistent with the GeoJP2 box."""
    from lxml import etree  # only needed here; keeps lxml out of the common path

    root = _feature_collection(etree, transform, lines, samples)
    dictionary = _crs_dictionary(etree, crs)
    return box(
        b"asoc",
        box(b"lbl ", b"gml.data")
        + box(b"asoc", box(b"lbl ", b"gml.root-instance") + box(b"xml ", _xml_bytes(etree, root)))
        + box(b"asoc", box(b"lbl ", b"CRSDictionary.gml") + box(b"xml ", _xml_bytes(etree, dictionary))),
    )


_CRS_REF = "gmljp2://xml/CRSDictionary.gml#pdsgen_crs"


def _feature_collection(etree, transform: Affine, lines: int, samples: int):
    g = f"{{{GML}}}"
    collection = etree.Element(g + "FeatureCollection", nsmap=_NSMAP)
    west, north = transform @ (0, 0)
    east, south = transform @ (samples, lines)
    envelope = etree.SubElement(etree.SubElement(collection, g + "boundedBy"), g + "Envelope", srsName=_CRS_REF)
    etree.SubElement(envelope, g + "lowerCorner").text = f"{_num(min(west, east))} {_num(min(south, north))}"
    etree.SubElement(envelope, g + "upperCorner").text = f"{_num(max(west, east))} {_num(max(south, north))}"
    coverage = etree.SubElement(etree.SubElement(collection, g + "featureMember"), g + "FeatureCollection")
    feature = etree.SubElement(etree.SubElement(coverage, g + "featureMember"), g + "RectifiedGridCoverage",
                               attrib={g + "id": "RGC0001"})
    grid = etree.SubElement(etree.SubElement(feature, g + "rectifiedGridDomain"), g + "RectifiedGrid",
                            dimension="2")
    limits = etree.SubElement(etree.SubElement(grid, g + "limits"), g + "GridEnvelope")
    etree.SubElement(limits, g + "low").text = "0 0"
    etree.SubElement(limits, g + "high").text = f"{samples - 1} {lines - 1}"
    etree.SubElement(grid, g + "axisName").text = "x"
    etree.SubElement(grid, g + "axisName").text = "y"
    centre_x, centre_y = transform @ (0.5, 0.5)  # GML grid points are pixel centres
    point = etree.SubElement(etree.SubElement(grid, g + "origin"), g + "Point", srsName=_CRS_REF,
                             attrib={g + "id": "P0001"})
    etree.SubElement(point, g + "pos").text = f"{_num(centre_x)} {_num(centre_y)}"
    etree.SubElement(grid, g + "offsetVector", srsName=_CRS_REF).text = f"{_num(transform.a)} {_num(transform.d)}"
    etree.SubElement(grid, g + "offsetVector", srsName=_CRS_REF).text = f"{_num(transform.b)} {_num(transform.e)}"
    range_set = etree.SubElement(etree.SubElement(feature, g + "rangeSet"), g + "File")
    etree.SubElement(range_set, g + "fileName").text = "gmljp2://codestream/0"
    etree.SubElement(range_set, g + "fileStructure").text = "Record Interleaved"
    return collection


def _crs_dictionary(etree, crs: CRS):
    g = f"{{{GML}}}"
    dictionary = etree.Element(g + "Dictionary", nsmap=_NSMAP, attrib={g + "id": "CRSU1"})
    etree.SubElement(dictionary, g + "name").text = "CRSDictionary.gml"
    entry = etree.SubElement(etree.SubElement(dictionary, g + "dictionaryEntry"), g + "Definition",
                             attrib={g + "id": "pdsgen_crs"})
    etree.SubElement(entry, g + "remarks").text = crs.to_wkt()
    etree.SubElement(entry, g + "name").text = crs.to_dict().get("proj", "projected") + " (WKT in remarks)"
    return dictionary


def _num(value: float) -> str:
    return repr(float(value))


def _xml_bytes(etree, element) -> bytes:
    return etree.tostring(element, xml_declaration=True, encoding="UTF-8", pretty_print=True)
