"""Mission profiles: product names and the mission's identification keywords.

A profile only decides names and keyword defaults; geometry and data handling
are the same for every mission. `--params` values override these defaults.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from .errors import PdsgenError
from .geometry import EQUIRECTANGULAR, POLAR_STEREOGRAPHIC, MapGeometry

# HiRISE scale letters: A = 0.25 m, doubling to J = 128 m; a scale must be within 10 %.
HIRISE_SCALE_LETTERS = {letter: 0.25 * 2**i for i, letter in enumerate("ABCDEFGHIJ")}
_HIRISE_OBSERVATION_RE = re.compile(r"^(?:[A-Z]{3}_)?(?P<orbit>\d{6})_(?P<lat>\d{4})(?:_\w+)?$")


@dataclass(frozen=True)
class Profile:
    name: str
    dtm_keywords: dict[str, str] = field(default_factory=dict)
    dtm_note: str = ""
    credit: str = ""


_MRO_KEYWORDS = {
    "PRODUCER_INSTITUTION_NAME": "UNIVERSITY OF ARIZONA",
    "PRODUCER_ID": "UA",
    "PRODUCER_FULL_NAME": "UNK",
    "INSTRUMENT_HOST_NAME": "MARS RECONNAISSANCE ORBITER",
    "INSTRUMENT_HOST_ID": "MRO",
    "INSTRUMENT_NAME": "HIGH RESOLUTION IMAGING SCIENCE EXPERIMENT",
    "INSTRUMENT_ID": "HIRISE",
}

PROFILES = {
    "hirise": Profile(
        name="hirise",
        dtm_keywords={
            "DATA_SET_ID": "MRO-M-HIRISE-5-DTM-V1.0",
            "DATA_SET_NAME": "MRO MARS HIGH RESOLUTION IMAGING SCIENCE EXPERIMENT DTM V1.0",
            **_MRO_KEYWORDS,
            "TARGET_NAME": "MARS",
            "RATIONALE_DESC": "UNK",
        },
        dtm_note=(
            "Pixel values are elevations in meters above the Mars 2000 areoid "
            "(equipotential surface, Smith et al., 2001). Physical value = "
            "DN * SCALING_FACTOR + OFFSET. Pixels equal to MISSING_CONSTANT hold no data."
        ),
        credit="NASA/JPL/University of Arizona",
    ),
    "generic": Profile(
        name="generic",
        dtm_keywords={
            "DATA_SET_ID": "UNK",
            "DATA_SET_NAME": "UNK",
            "PRODUCER_INSTITUTION_NAME": "UNK",
            "PRODUCER_ID": "UNK",
            "PRODUCER_FULL_NAME": "UNK",
            "INSTRUMENT_HOST_NAME": "UNK",
            "INSTRUMENT_HOST_ID": "UNK",
            "INSTRUMENT_NAME": "UNK",
            "INSTRUMENT_ID": "UNK",
            "RATIONALE_DESC": "UNK",
        },
        dtm_note=(
            "Pixel values are elevations in meters. Physical value = "
            "DN * SCALING_FACTOR + OFFSET. Pixels equal to MISSING_CONSTANT hold no data."
        ),
        credit="",
    ),
    "hrsc": Profile(
        name="hrsc",
        dtm_note="Heights in meters = DN * SCALING_FACTOR + OFFSET.",
        credit="ESA/DLR/FU Berlin",
    ),
    "imars": Profile(
        name="imars",
        dtm_note="Heights in meters = DN * SCALING_FACTOR + OFFSET.",
        credit="ESA/DLR/FU Berlin/UCL",
    ),
}


def get_profile(name: str) -> Profile:
    try:
        return PROFILES[name]
    except KeyError:
        raise PdsgenError(None, f"unknown profile {name!r}; choose from {', '.join(PROFILES)}") from None


def hirise_scale_letter(map_scale: float) -> str:
    """The letter of the nominal HiRISE post spacing within 10 % of `map_scale`."""
    for letter, nominal in HIRISE_SCALE_LETTERS.items():
        if abs(map_scale - nominal) <= 0.1 * nominal:
            return letter
    raise PdsgenError(
        None,
        f"map scale {map_scale:g} m is not within 10 % of a HiRISE scale "
        "(0.25, 0.5, 1, 2 ... 128 m); give --product-id",
    )


def hirise_version_code(version: str) -> str:
    """Two-digit version code: 1.0 -> 01, 9.0 -> 09, 1.5 -> 15.

    Only versions N.0 (N = 1..9) and N.M (N, M = 1..9) are encodable; the codes
    of the two forms never collide (N.0 gives 0N, N.M gives NM with M > 0), which
    ISIS's encoder does not guarantee. Anything else is refused.
    """
    match = re.fullmatch(r"([1-9])\.([0-9])", version.strip())
    if match is None:
        raise PdsgenError(
            None,
            f"version {version!r} cannot be encoded in a two-digit HiRISE code "
            "(use N.0 or N.M with single digits 1-9)",
        )
    major, minor = match.groups()
    return f"0{major}" if minor == "0" else f"{major}{minor}"


def hirise_observation_code(source_id: str) -> str:
    """`PSP_008669_1705` (or `008669_1705`) -> `008669_1705`."""
    match = _HIRISE_OBSERVATION_RE.match(source_id.strip().upper())
    if match is None:
        raise PdsgenError(None, f"{source_id!r} is not a HiRISE observation ID like PSP_008669_1705")
    return f"{match.group('orbit')}_{match.group('lat')}"


def hirise_dtm_product_id(
    geometry: MapGeometry, source_ids: list[str], institution: str | None, version: str
) -> str:
    """DT + E (areoid) + projection letter + scale letter + sources + institution + version."""
    if len(source_ids) != 2:
        raise PdsgenError(
            None,
            f"the hirise profile builds the DTM product ID from two --source-product-id "
            f"values (got {len(source_ids)}); or give --product-id",
        )
    if institution is None or not re.fullmatch(r"[A-Z]", institution):
        raise PdsgenError(
            None,
            "the hirise profile needs --institution as one upper-case letter "
            "to build the product ID; or give --product-id",
        )
    projection_letters = {EQUIRECTANGULAR: "E", POLAR_STEREOGRAPHIC: "P"}
    if geometry.projection_type not in projection_letters:
        raise PdsgenError(
            None,
            f"HiRISE DTM names have no letter for {geometry.projection_type} products; "
            "give --product-id",
        )
    first, second = (hirise_observation_code(s) for s in source_ids)
    return (
        f"DTE{projection_letters[geometry.projection_type]}"
        f"{hirise_scale_letter(geometry.map_scale)}_{first}_{second}_"
        f"{institution}{hirise_version_code(version)}"
    )


def generic_product_id(stem: str) -> str:
    """A PDS-safe product ID from a file name: upper case, [A-Z0-9_] only."""
    cleaned = re.sub(r"[^A-Z0-9_]+", "_", stem.upper()).strip("_")
    if not cleaned:
        raise PdsgenError(None, f"cannot derive a product ID from {stem!r}; give --product-id")
    return cleaned[:40]


def check_product_id(product_id: str) -> str:
    if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_\-.]{0,39}", product_id):
        raise PdsgenError(
            None, f"product ID {product_id!r} must be 1-40 letters, digits, '_', '-' or '.'"
        )
    return product_id


# --- Orthoimages -------------------------------------------------------------

# HiRISE filters: band names as HiRISE labels write them, centre wavelengths in nm.
HIRISE_FILTER_WAVELENGTHS_NM = {"RED": 700, "NEAR-INFRARED": 900, "BLUE-GREEN": 500}
ORTHO_FILTER_NAMES = {1: ("RED",), 3: ("NEAR-INFRARED", "RED", "BLUE-GREEN")}
ORTHO_COLOR_CODES = {1: "RED", 3: "IRB"}
_HIRISE_ORTHO_OBSERVATION_RE = re.compile(r"^[A-Z]{3}_\d{6}_\d{4}$")

# Orthoimages of HiRISE DTMs are released in the DTM data set, beside the DTM.
ORTHO_KEYWORDS = {
    "hirise": {
        **PROFILES["hirise"].dtm_keywords,
    },
    "generic": {
        **PROFILES["generic"].dtm_keywords,
    },
}
ORTHO_DESCRIPTIONS = {
    "hirise": "HiRISE orthorectified image, projected onto the DTM named in SOURCE_PRODUCT_ID",
    "generic": "Orthorectified image",
}


def ortho_keywords(profile: str) -> dict[str, str]:
    """Identification keyword defaults of a profile's orthoimage labels."""
    name = get_profile(profile).name
    if name not in ORTHO_KEYWORDS:
        raise PdsgenError(None, f"the {name} profile writes orthoimages in its own form, not as JP2 + LBL")
    return dict(ORTHO_KEYWORDS[name])


def ortho_filter_wavelengths(profile: str, filters: tuple[str, ...]) -> tuple[int, ...] | None:
    """Centre wavelengths (nm) of the bands, when the profile knows its filters."""
    if get_profile(profile).name != "hirise":
        return None
    return tuple(HIRISE_FILTER_WAVELENGTHS_NM[name] for name in filters)


def hirise_ortho_product_id(observation_id: str, bands: int, map_scale: float, sequence: int) -> str:
    """`ESP_042252_1930` + IRB + 0.5 m + 41 -> `ESP_042252_1930_IRB_B_41_ORTHO`."""
    observation = observation_id.strip().upper()
    if not _HIRISE_ORTHO_OBSERVATION_RE.match(observation):
        raise PdsgenError(
            None, f"{observation_id!r} is not a HiRISE observation ID like ESP_042252_1930; give --observation-id"
        )
    if bands not in ORTHO_COLOR_CODES:
        raise PdsgenError(None, f"HiRISE orthoimages have 1 (RED) or 3 (IRB) bands, not {bands}")
    if not 0 <= sequence <= 99:
        raise PdsgenError(None, f"sequence number {sequence} does not fit the two digits of a HiRISE ID")
    return f"{observation}_{ORTHO_COLOR_CODES[bands]}_{hirise_scale_letter(map_scale)}_{sequence:02d}_ORTHO"
