"""Is a product a DTM (heights) or an orthoimage? Decide from what it says, then its data.

The decision changes everything the Extras show (shaded relief and a height ramp,
or a stretched image), so it is made from evidence and stated: every decision
carries a one-line reason the CLI prints. In order:

1. A PDS3 label: a JPEG 2000 product (COMPRESSED_FILE) is an image; an IMAGE
   object whose UNIT is a length or whose name/description speaks of heights is a
   DTM; any other labelled image is an orthoimage.
2. GDAL metadata (descriptions, tags, band unit): height words or a length unit
   mean a DTM, reflectance words (I/F, reflectance, radiance) an orthoimage; so do
   HRSC/iMars DTM names (`_dt4`, `_da4`) and int16 with a band scale or offset
   (how iMars and others pack heights).
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

from ..errors import PdsgenError, param
from ..missions.hrsc import is_dtm_name as is_hrsc_dtm_name

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
                path: Path, value_range: ValueRange) -> KindDecision:
    """DTM or orthoimage and why; PdsgenError (suggesting --kind) when it cannot tell."""
    if "COMPRESSED_FILE" in label:
        return KindDecision(ORTHO, "its label describes a JPEG 2000 image")
    if image:
        return _from_label_image(image)
    if label:
        return KindDecision(ORTHO, "its label describes no heights")
    hinted = _from_metadata(info, path)
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


def _from_metadata(info: Mapping[str, Any], path: Path) -> KindDecision | None:
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
    if is_hrsc_dtm_name(path.stem):
        return KindDecision(DTM, "its name is an HRSC DTM's (_dt4/_da4)")
    if info["dtype"] == "int16" and (info["scale"] not in (None, 1.0)
                                     or info["offset"] not in (None, 0.0)):
        return KindDecision(DTM, "int16 with a band scale/offset is how heights are packed")
    return None


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
