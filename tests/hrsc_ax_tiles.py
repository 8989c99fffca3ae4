"""HRSC-AX-like tiles built at run time: VICAR files written from the keyword list of the
HRSC-AX deliveries (system items, PROPERTY='MAP', PROPERTY='DIGITAL_TERRAIN_MODEL'),
Transverse Mercator (UTM zone 33 north) on the HRSC-AX ellipsoid.

The writer here is the tests' own (not pdsgen's), so that pdsgen's reader is checked
against an independent rendering of the format.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

A_KM, C_KM = 6378.14, 6356.75
K0 = 0.9996
LON0 = 15.0  # UTM zone 33
FALSE_EASTING = 500000.0
TILE = "430-8765_0.0x0.0km"  # named by its upper-left corner (km); size filled in per test
UTM33_HRSCAX = (f"+proj=tmerc +lat_0=0 +lon_0={LON0} +k={K0} +x_0={FALSE_EASTING} +y_0=0 "
                f"+a={A_KM * 1000} +b={C_KM * 1000} +units=m +no_defs")
GEODETIC = f"+proj=longlat +a={A_KM * 1000} +b={C_KM * 1000} +no_defs"

_FORMATS = {np.dtype("u1"): "BYTE", np.dtype("i2"): "HALF", np.dtype("f4"): "REAL"}


def _item(key: str, value) -> str:
    if isinstance(value, str):
        return f"{key}='{value}'"
    if isinstance(value, float):
        return f"{key}={value!r}"
    return f"{key}={value}"


# How the offsets count from pixel (1, 1): by the HRSC-AX image description (Table B2) "the
# offset value of the map projection origin position from the center of the pixel at line
# and sample position 1,1"; DLR's HRSC Mars labels (DSMAP.CAT) count one pixel further.
OFFSET_COUNTING = {"table_b2": 0.0, "dlr": 1.0}


def map_group(east_m: float, north_m: float, pixel_m: float, *, scale_factor: float | None = K0,
              projection: str = "TRANSVERSE_MERCATOR", false_easting: float = FALSE_EASTING,
              counting: str = "table_b2") -> dict:
    """The MAP group of a tile whose upper-left corner is (east_m, north_m) grid metres of a
    TM grid with false easting `false_easting` (UTM 33N by default).

    Offsets as Table B2 defines them: the projection origin's position, in lines and samples,
    from the centre of pixel (1, 1) - the centre of pixel (1, 1) lies half a pixel inside the
    corner, so the origin is (north / pixel - 1/2) lines above it and (-x / pixel - 1/2)
    samples left of it. `counting="dlr"` writes DLR's Mars counting instead.
    """
    x_natural = east_m - false_easting
    shift = OFFSET_COUNTING[counting]
    group = {
        "TARGET_NAME": "EARTH",
        "A_AXIS_RADIUS": A_KM, "B_AXIS_RADIUS": A_KM, "C_AXIS_RADIUS": C_KM,
        "BODY_LONG_AXIS_LONGITUDE": 0.0, "CARTESIAN_AZIMUTH": 0.0,
        "CENTER_LATITUDE": 0.0, "CENTER_LONGITUDE": LON0,
        "COORDINATE_SYSTEM_NAME": "PLANETOGRAPHIC",
        "LINE_PROJECTION_OFFSET": north_m / pixel_m - 0.5 + shift,
        "SAMPLE_PROJECTION_OFFSET": -x_natural / pixel_m - 0.5 + shift,
        "MAP_PROJECTION_TYPE": projection,
        "MAP_SCALE": pixel_m / 1000.0,
        "POSITIVE_LONGITUDE_DIRECTION": "EAST",
        "SPHERICAL_AZIMUTH": 0.0,
    }
    if scale_factor is not None:
        group["SCALE_FACTOR"] = scale_factor
    return group


def dtm_group(offset: float, scaling: float, low: float, high: float) -> dict:
    return {
        "DTM_A_AXIS_RADIUS": A_KM, "DTM_B_AXIS_RADIUS": A_KM, "DTM_C_AXIS_RADIUS": C_KM,
        "DTM_OFFSET": offset, "DTM_SCALING_FACTOR": scaling,
        "DTM_DESC": "HEIGHT ABOVE ELLIPSOID", "DTM_RANGE": (low, high),
    }


def write_vicar(path: Path, data: np.ndarray, groups: dict[str, dict], *, big_endian: bool = False,
                record_pad: int = 0) -> Path:
    """A VICAR file: system label, property groups, a history task, then the BSQ image."""
    data = np.asarray(data)
    lines, samples = data.shape
    fmt = _FORMATS[np.dtype(data.dtype.str.lstrip("<>=|"))]
    recsize = samples * data.dtype.itemsize + record_pad
    system = [
        ("FORMAT", fmt), ("TYPE", "IMAGE"), ("BUFSIZ", recsize), ("DIM", 3), ("EOL", 0),
        ("RECSIZE", recsize), ("ORG", "BSQ"), ("NL", lines), ("NS", samples), ("NB", 1),
        ("N1", samples), ("N2", lines), ("N3", 1), ("N4", 0), ("NBB", record_pad), ("NLB", 0),
        ("HOST", "X86-LINUX"), ("INTFMT", "HIGH" if big_endian else "LOW"),
        ("REALFMT", "IEEE" if big_endian else "RIEEE"),
    ]
    parts = [_item(k, v) for k, v in system]
    for name, group in groups.items():
        parts.append(_item("PROPERTY", name))
        for key, value in group.items():
            if isinstance(value, tuple):
                parts.append(f"{key}=({','.join(repr(v) for v in value)})")
            else:
                parts.append(_item(key, value))
    parts += [_item("TASK", "HRORTHO"), _item("USER", "dlr"), _item("DAT_TIM", "Thu Jul 17 12:00:00 2008")]
    body = "  ".join(parts)
    size = recsize
    while True:
        text = f"LBLSIZE={size:<10d}{body}"
        need = math.ceil(len(text) / recsize) * recsize
        if need == size:
            break
        size = need
    order = ">" if big_endian else "<"
    with open(path, "wb") as handle:
        handle.write(text.encode("ascii").ljust(size, b" "))
        stored = data.astype(data.dtype.newbyteorder(order) if data.dtype.itemsize > 1 else data.dtype)
        for row in stored:
            handle.write(b"\0" * record_pad + row.tobytes())
    return path


def tile_name(east_km: int, north_km: int, lines: int, pixel_m: float) -> str:
    size_km = lines * pixel_m / 1000.0
    return f"{east_km}-{north_km}_{size_km:.1f}x{size_km:.1f}km"


def grid_corner_positions(east_m: float, north_m: float, pixel_m: float, lines: int, samples: int):
    """Geodetic (lon, lat) of the centres of the four corner pixels and of the centre pixel,
    as the source label places them (UTM 33N grid on the HRSC-AX ellipsoid)."""
    pixels = [(0, 0), (0, samples - 1), (lines - 1, 0), (lines - 1, samples - 1), (lines // 2, samples // 2)]
    xs = [east_m + (s + 0.5) * pixel_m for _, s in pixels]
    ys = [north_m - (r + 0.5) * pixel_m for r, _ in pixels]
    lon, lat = warp_transform(CRS.from_proj4(UTM33_HRSCAX), CRS.from_proj4(GEODETIC), xs, ys)
    return pixels, np.array(lon), np.array(lat)
