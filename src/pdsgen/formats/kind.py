"""Is a raster a DTM (heights) or an orthoimage? Decide from what it says, then its data.

The one home of the decision: the Extras take it to choose what they show (shaded relief
and a height ramp, or a stretched image), and the product writers to refuse the wrong kind
of input (`pdsgen dtm` of an 8-bit image, `pdsgen ortho` of heights). It is made from
evidence and stated: every decision carries a one-line reason the CLI prints. In order:

1. A PDS3 label: a JPEG 2000 product (COMPRESSED_FILE) is an image; an IMAGE
   object whose UNIT is a length or whose name/description speaks of heights is a
   DTM; any other labelled image is an orthoimage.
2. GDAL metadata (descriptions, tags, band unit): height words or a length unit
   mean a DTM, reflectance words (I/F, reflectance, radiance) an orthoimage; so do
   a name the caller knows for a DTM's (`named_dtm`: HRSC/iMars `_dt4`, `_da4`, a mission's
   fact, so the caller asks missions/) and int16 with a band scale or offset (how iMars and
   others pack heights).
3. Integer data without such hints are image DNs. Floating-point data are read
   (a small decimated sample): values within 0..2 are reflectance (I/F), values
   reaching well below zero are heights (an image has no negative brightness).
   Anything else - positive floats beyond 2 with nothing saying what they are -
   is ambiguous, and the user is asked for --kind rather than given a guess.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from rasterio.enums import Resampling

from ..errors import PdsgenError, param

DTM = "dtm"
ORTHO = "ortho"
KINDS = (DTM, ORTHO)
# HiRISE NOMAP mosaics (not map-projected): never detected, asked for with --kind nomap.
NOMAP = "nomap"

LENGTH_UNITS = {"M": 1.0, "METER": 1.0, "METERS": 1.0, "METRE": 1.0, "METRES": 1.0,
                "KM": 1000.0, "KILOMETER": 1000.0, "KILOMETERS": 1000.0}
# Whole words only ("DEMO" or "DTMAKER" do not count); "_" joins words in labels.
_HEIGHT_WORDS = re.compile(
    r"(?<![A-Z0-9])(TOPOGRAPHY|ELEVATIONS?|HEIGHTS?|DTMS?|DEMS?|ALTIMETRY)(?![A-Z0-9])")
_LABEL_HEIGHT_WORDS = re.compile(
    r"(?<![A-Z0-9])(TOPOGRAPHY|ELEVATIONS?|HEIGHTS?|RADI(?:US|I)|DTMS?|DEMS?|ALTIMETRY)"
    r"(?![A-Z0-9])")
_IMAGE_WORDS = re.compile(r"(?<![A-Z0-9])(I/F|IOF|REFLECTANCE|RADIANCE|ALBEDO|ORTHO\w*)(?![A-Z0-9])")
# Float data: reflectance (I/F) lies in 0..REFLECTANCE_MAX (a little below 0 from
# calibration noise); heights reach below HEIGHT_BELOW.
REFLECTANCE_MIN, REFLECTANCE_MAX = -0.05, 2.0
HEIGHT_BELOW = -1.0


@dataclass(frozen=True)
class KindDecision:
    kind: str
    reason: str


# Returns (minimum, maximum) of a decimated sample of the valid data, physical units.
ValueRange = Callable[[], "tuple[float, float] | None"]


def decide_kind(label: Mapping[str, Any], image: Mapping[str, Any], info: Mapping[str, Any],
                path: Path, value_range: ValueRange, named_dtm: bool = False) -> KindDecision:
    """DTM or orthoimage and why; PdsgenError (suggesting --kind) when it cannot tell.

    `info`: the raster's facts as `raster_facts` gives them; `named_dtm`: its file name is a
    DTM's by a mission's naming (HRSC's _dt4/_da4)."""
    if "COMPRESSED_FILE" in label:
        return KindDecision(ORTHO, "its label describes a JPEG 2000 image")
    if image:
        return _from_label_image(image)
    if label:
        return KindDecision(ORTHO, "its label describes no heights")
    hinted = _from_metadata(info, named_dtm)
    if hinted is not None:
        return hinted
    dtype = str(info["dtype"])
    if not dtype.startswith("float"):
        return KindDecision(ORTHO, f"{dtype} data without height metadata are image DNs")
    if info["band_count"] == 3:
        return KindDecision(ORTHO, "three floating-point bands are a colour image")
    return _from_values(dtype, value_range(), path)


def _from_label_image(image: Mapping[str, Any]) -> KindDecision:
    unit = str(image.get("UNIT", "") or "").upper()
    if unit in LENGTH_UNITS:
        return KindDecision(DTM, f"its label gives the image in {unit}")
    words = " ".join(str(image.get(k, "")) for k in ("NAME", "DESCRIPTION", "NOTE")).upper()
    found = _LABEL_HEIGHT_WORDS.search(words)
    if found:
        return KindDecision(DTM, f"its label describes the image as {found.group(1).lower()}")
    return KindDecision(ORTHO, "its label's IMAGE object describes no heights")


def _from_metadata(info: Mapping[str, Any], named_dtm: bool) -> KindDecision | None:
    hints = str(info["hints"])
    unit = str(info["unit"] or "").upper()
    if unit in LENGTH_UNITS:
        return KindDecision(DTM, f"its band unit is {info['unit']}")
    height = _HEIGHT_WORDS.search(hints)
    if height:
        return KindDecision(DTM, f"its metadata say {height.group(1).lower()}")
    picture = _IMAGE_WORDS.search(hints)
    if picture:
        return KindDecision(ORTHO, f"its metadata say {picture.group(1).lower()}")
    if named_dtm:
        return KindDecision(DTM, "its name is an HRSC DTM's (_dt4/_da4)")
    if info["dtype"] == "int16" and (info["scale"] not in (None, 1.0)
                                     or info["offset"] not in (None, 0.0)):
        return KindDecision(DTM, "int16 with a band scale/offset is how heights are packed")
    return None


# GDAL metadata items that may say what a raster holds.
DESCRIPTIVE_TAGS = ("DESCRIPTION", "TIFFTAG_IMAGEDESCRIPTION", "PRODUCT_ID", "PRODUCT_TYPE")
KIND_SAMPLE_SIDE = 256  # the decimated read that tells heights from reflectance


def raster_facts(ds: Any) -> dict[str, Any]:
    """What `decide_kind` reads of an open raster (rasterio dataset): size, bands, sample type,
    georeferencing, nodata, band 1's scale, offset and unit, and its descriptive metadata."""
    return {"width": ds.width, "height": ds.height, "band_count": ds.count,
            "dtype": ds.dtypes[0], "crs": ds.crs, "transform": ds.transform,
            "nodata": ds.nodata,
            "scale": ds.scales[0] if ds.scales else 1.0,
            "offset": ds.offsets[0] if ds.offsets else 0.0,
            "unit": (ds.units[0] or "") if ds.count else "",
            "hints": _gdal_hints(ds)}


def _gdal_hints(ds: Any) -> str:
    """GDAL metadata that may say what the raster holds (upper case, one line)."""
    tags = {**ds.tags(), **ds.tags(1)}
    texts = [tags.get(key, "") for key in DESCRIPTIVE_TAGS]
    texts += [ds.descriptions[0] or "", ds.units[0] or ""] if ds.count else []
    return " ".join(str(t) for t in texts).upper()


def sample_shape(width: int, height: int) -> tuple[int, int]:
    """(lines, samples) of the decimated read `sampled_range` makes of a WIDTH x HEIGHT raster."""
    factor = max(1.0, max(width, height) / KIND_SAMPLE_SIDE)
    return max(1, round(height / factor)), max(1, round(width / factor))


def sampled_range(ds: Any, scale: float = 1.0, offset: float = 0.0,
                  shape: tuple[int, int] | None = None) -> tuple[float, float] | None:
    """Minimum and maximum of a small decimated read of band 1 (its valid values), physical
    units (DN * scale + offset); None when no value is valid. `shape`: the read's, when `ds`
    is a reduced level of the raster (default: `sample_shape` of `ds`)."""
    shape = shape or sample_shape(ds.width, ds.height)
    dn = ds.read(1, out_shape=shape, resampling=Resampling.nearest, masked=True)
    values = dn.compressed().astype(np.float64) * scale + offset
    values = values[np.isfinite(values)]
    return (float(values.min()), float(values.max())) if values.size else None


def _from_values(dtype: str, found: tuple[float, float] | None, path: Path) -> KindDecision:
    if found is None:
        raise PdsgenError(path, "has no valid pixels (all no-data)")
    low, high = found
    span = f"{dtype} values {low:.4g} .. {high:.4g}"
    if REFLECTANCE_MIN <= low and high <= REFLECTANCE_MAX:
        return KindDecision(ORTHO, f"{span} look like reflectance (I/F)")
    if low < HEIGHT_BELOW:
        return KindDecision(DTM, f"{span} reach below zero, as heights do")
    raise PdsgenError(path, f"cannot tell whether it is a DTM or an orthoimage ({span}, no "
                            f"label or metadata saying which); give {param('kind', DTM)} or {param('kind', ORTHO)}")
