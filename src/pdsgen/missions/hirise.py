"""MRO HiRISE: product names (DTMs and orthoimages), keywords, credit, filters.

Names (pds3-products.md): DTMs `DT` + `E` (areoid) + projection letter (E/P) +
scale letter (A = 0.25 m ... J = 128 m, within 10 %) + the two source
observations' `OOOOOO_LLLL` + institution letter + two-digit version
(`DTEEC_008669_1705_009025_1705_U01`); orthoimages observation + colour
(RED/IRB) + scale letter + sequence + `_ORTHO` (`ESP_042252_1930_IRB_B_41_ORTHO`).
"""

from __future__ import annotations

import re

from ..errors import PdsgenError, param
from ..geo.geometry import EQUIRECTANGULAR, POLAR_STEREOGRAPHIC
from .base import (
    STANDARD_OPTIONS,
    ContextReference,
    LabelFacts,
    Mission,
    Pds4Facts,
    ProductIdRequest,
    data_set_names_mission,
)

INSTRUMENT_ID = "HIRISE"
DATA_SET_PREFIX = "MRO-M-HIRISE"
CREDIT = "NASA/JPL/University of Arizona"
HEIGHT_DATUM = "the Mars 2000 areoid"  # every HiRISE DTM's heights (DTM_NOTE says so too)

# HiRISE scale letters: A = 0.25 m, doubling to J = 128 m; a scale must be within 10 %.
SCALE_LETTERS = {letter: 0.25 * 2**i for i, letter in enumerate("ABCDEFGHIJ")}
OBSERVATION_RE = re.compile(r"^(?:[A-Z]{3}_)?(?P<orbit>\d{6})_(?P<lat>\d{4})(?:_\w+)?$")
ORTHO_OBSERVATION_RE = re.compile(r"^[A-Z]{3}_\d{6}_\d{4}$")
# Mission phases that start an observation ID (PSP_008669_1705): aerobraking, transition,
# primary and extended science, instrument checkout, calibration.
OBSERVATION_PHASES = ("AEB", "TRA", "PSP", "ESP", "INS", "CAL")
# What a HiRISE PRODUCT_ID starts with: an observation ID (RDRs, orthoimages) or a DTM's
# DT + datum/projection/scale letters + its two source observations (DTEEC_008669_1705_009025_1705).
PRODUCT_ID_RE = re.compile(
    rf"^(?:(?:{'|'.join(OBSERVATION_PHASES)})_\d{{6}}_\d{{4}}|DT[EP][A-Z]{{2}}_\d{{6}}_\d{{4}}_\d{{6}}_\d{{4}})",
    re.IGNORECASE,
)
PROJECTION_LETTERS = {EQUIRECTANGULAR: "E", POLAR_STEREOGRAPHIC: "P"}
# A whole HiRISE DTM product ID (what an orthoimage's source DTM is): DTEEC_008669_1705_009025_1705_U01.
DTM_ID_RE = re.compile(r"DT[EP][A-Z]{2}_\d{6}_\d{4}_\d{6}_\d{4}_[A-Z]\d{2}")

# HiRISE filters: band names as HiRISE labels write them, centre wavelengths in nm.
FILTER_WAVELENGTHS_NM = {"RED": 700, "NEAR-INFRARED": 900, "BLUE-GREEN": 500}
ORTHO_COLOR_CODES = {1: "RED", 3: "IRB"}

MRO_KEYWORDS = {
    "PRODUCER_INSTITUTION_NAME": "UNIVERSITY OF ARIZONA",
    "PRODUCER_ID": "UA",
    "PRODUCER_FULL_NAME": "UNK",
    "INSTRUMENT_HOST_NAME": "MARS RECONNAISSANCE ORBITER",
    "INSTRUMENT_HOST_ID": "MRO",
    "INSTRUMENT_NAME": "HIGH RESOLUTION IMAGING SCIENCE EXPERIMENT",
    "INSTRUMENT_ID": INSTRUMENT_ID,
}
KEYWORDS = {
    "DATA_SET_ID": "MRO-M-HIRISE-5-DTM-V1.0",
    "DATA_SET_NAME": "MRO MARS HIGH RESOLUTION IMAGING SCIENCE EXPERIMENT DTM V1.0",
    **MRO_KEYWORDS,
    "TARGET_NAME": "MARS",
    "RATIONALE_DESC": "UNK",
}
DTM_NOTE = (
    "Pixel values are elevations in meters above the Mars 2000 areoid "
    "(equipotential surface, Smith et al., 2001). Physical value = "
    "DN * SCALING_FACTOR + OFFSET. Pixels equal to MISSING_CONSTANT hold no data."
)
# The release (and hidtmgen's REAL,2 format) gives VALID_MINIMUM/MAXIMUM to two decimals.
# pdsgen rounds them outwards, so they still bound every valid sample (hidtmgen rounds to
# the nearest, which the validator's IMG-007 reports as a warning when it cuts a sample off).
RELEASE_VALID_RANGE_DECIMALS = 2
VALID_RANGE_DECIMALS: int | None = RELEASE_VALID_RANGE_DECIMALS
# Orthoimages of HiRISE DTMs are released in the DTM data set, beside the DTM.
ORTHO_DESCRIPTION = "HiRISE orthorectified image, projected onto the DTM named in SOURCE_PRODUCT_ID"


# HiRISE RDR Extras, as the release names them: per observation six map-projected files
# from the RDRs <OBS>_RED and <OBS>_COLOR (IR, RED, BG) and six NOMAP files, the CCD
# images stitched in the camera's geometry, not map-projected.
RDR_COLOURS = ("RED", "COLOR")
RDR_DATA_SET_PREFIX = "MRO-M-HIRISE-3-RDR"  # the RDR data sets (V1.0, V1.1 ...)
RDR_EXTRAS_SUFFIXES = ("QLOOK.JP2", "browse.jpg", "abrowse.jpg")
NOMAP_TAG = "NOMAP"
NOMAP_INPUTS = ("RED", "IRB")          # the two NOMAP mosaics an observation has
NOMAP_PRODUCTS = ("RED", "IRB", "RGB")  # the NOMAP Extras made from them
NOMAP_SUFFIXES = ("JP2", "browse.jpg")
NOMAP_BROWSE_WIDTH = 2048
# Band order of the IRB mosaic (and of the COLOR RDR): near-infrared, red, blue-green.
IRB_BAND_NAMES = ("NEAR-INFRARED", "RED", "BLUE-GREEN")
# The RGB rendering: RED, BG and a synthetic blue = 2 x BG - 0.3 x RED, per pixel.
SYNTHETIC_BLUE_BG, SYNTHETIC_BLUE_RED = 2.0, -0.3
# DN 0 is no data in HiRISE images (CORE_NULL = 0 in every RDR label).
CORE_NULL = 0
OBSERVATION_IN_NAME_RE = re.compile(r"(?<![A-Z0-9])([A-Z]{3}_\d{6}_\d{4})(?![0-9])")


# README.TXT's one-line index of an observation's Extras: what each product shows and
# what each file is.
RDR_EXTRAS_PRODUCT_RE = re.compile(
    r"^(?P<observation>[A-Z]{3}_\d{6}_\d{4})_(?P<product>RED|COLOR|IRB|RGB)(?P<nomap>\.NOMAP)?$")
RDR_EXTRAS_SHOWS = {"RED": "RED", "COLOR": "colour", "IRB": "IRB", "RGB": "RGB"}
RDR_EXTRAS_FILES = {"QLOOK.JP2": "quick look, full scale, lossy", "browse.jpg": "browse",
                    "abrowse.jpg": "browse, title and scale bar", "thumb.jpg": "thumbnail",
                    "JP2": "NOMAP, full scale, lossy", "browse.jpg.NOMAP": "NOMAP browse"}


def rdr_extras_line(product_id: str, file_name: str) -> tuple[str, str] | None:
    """(observation, what FILE_NAME is) for a HiRISE RDR or NOMAP product's Extras file."""
    match = RDR_EXTRAS_PRODUCT_RE.match(product_id)
    if match is None or not file_name.startswith(product_id + "."):
        return None
    suffix = file_name[len(product_id) + 1:] + (".NOMAP" if match["nomap"] and
                                                file_name.endswith(".browse.jpg") else "")
    what = RDR_EXTRAS_FILES.get(suffix)
    if what is None:
        return None
    return match["observation"], f"{RDR_EXTRAS_SHOWS[match['product']]} {what}"


def is_rdr(data_set_id: str) -> bool:
    """A HiRISE RDR (RED or COLOR map-projected mosaic) by its DATA_SET_ID."""
    return data_set_id.strip().upper().startswith(RDR_DATA_SET_PREFIX)


def nomap_product_id(observation: str, product: str) -> str:
    """`PSP_005000_1000` + RGB -> `PSP_005000_1000_RGB.NOMAP` (its files add .JP2, .browse.jpg)."""
    return f"{observation}_{product}.{NOMAP_TAG}"


def rdr_extras_names(observation: str) -> list[str]:
    """The twelve Extras file names of one observation, map-projected then NOMAP."""
    names = [f"{observation}_{colour}.{suffix}" for colour in RDR_COLOURS
             for suffix in RDR_EXTRAS_SUFFIXES]
    return names + [f"{nomap_product_id(observation, product)}.{suffix}"
                    for product in NOMAP_PRODUCTS for suffix in NOMAP_SUFFIXES]


def observation_in_name(name: str) -> str | None:
    """The observation ID a file name carries (`PSP_005000_1000_RED.NOMAP.cub`), if any."""
    match = OBSERVATION_IN_NAME_RE.search(name.upper())
    return match.group(1) if match else None


def scale_letter(map_scale: float) -> str:
    """The letter of the nominal HiRISE post spacing within 10 % of `map_scale`."""
    for letter, nominal in SCALE_LETTERS.items():
        if abs(map_scale - nominal) <= 0.1 * nominal:
            return letter
    raise PdsgenError(
        None,
        f"map scale {map_scale:g} m is not within 10 % of a HiRISE scale "
        f"(0.25, 0.5, 1, 2 ... 128 m); give {param('product_id')}",
    )


def version_code(version: str) -> str:
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


def observation_code(source_id: str) -> str:
    """`PSP_008669_1705` (or `008669_1705`) -> `008669_1705`."""
    match = OBSERVATION_RE.match(source_id.strip().upper())
    if match is None:
        raise PdsgenError(None, f"{source_id!r} is not a HiRISE observation ID like PSP_008669_1705")
    return f"{match.group('orbit')}_{match.group('lat')}"


def dtm_product_id(request: ProductIdRequest) -> str:
    """DT + E (areoid) + projection letter + scale letter + sources + institution + version."""
    sources, institution, geometry = list(request.sources), request.institution, request.geometry
    if len(sources) != 2:
        raise PdsgenError(
            None,
            f"the hirise profile builds the DTM product ID from two {param('source_product_ids')} "
            f"(got {len(sources)}); or give {param('product_id')}",
        )
    if institution is None or not re.fullmatch(r"[A-Z]", institution):
        raise PdsgenError(
            None,
            f"the hirise profile needs {param('institution')} as one upper-case letter "
            f"to build the product ID; or give {param('product_id')}",
        )
    if geometry.projection_type not in PROJECTION_LETTERS:
        raise PdsgenError(
            None,
            f"HiRISE DTM names have no letter for {geometry.projection_type} products; "
            f"give {param('product_id')}",
        )
    first, second = (observation_code(s) for s in sources)
    return (
        f"DTE{PROJECTION_LETTERS[geometry.projection_type]}"
        f"{scale_letter(geometry.map_scale)}_{first}_{second}_"
        f"{institution}{version_code(request.version)}"
    )


def ortho_id(observation_id: str, bands: int, map_scale: float, sequence: int) -> str:
    """`ESP_042252_1930` + IRB + 0.5 m + 41 -> `ESP_042252_1930_IRB_B_41_ORTHO`."""
    observation = observation_id.strip().upper()
    if not ORTHO_OBSERVATION_RE.match(observation):
        raise PdsgenError(
            None, f"{observation_id!r} is not a HiRISE observation ID like ESP_042252_1930; "
                  f"give {param('observation_id')}"
        )
    if bands not in ORTHO_COLOR_CODES:
        raise PdsgenError(None, f"HiRISE orthoimages have 1 (RED) or 3 (IRB) bands, not {bands}")
    if not 0 <= sequence <= 99:
        raise PdsgenError(None, f"sequence number {sequence} does not fit the two digits of a HiRISE ID")
    return f"{observation}_{ORTHO_COLOR_CODES[bands]}_{scale_letter(map_scale)}_{sequence:02d}_ORTHO"


def ortho_product_id(request: ProductIdRequest) -> str:
    observation = request.observation_id or next(
        (s for s in request.sources if ORTHO_OBSERVATION_RE.match(s.strip().upper())), None
    )
    if not observation:
        raise PdsgenError(None, f"the hirise profile needs {param('observation_id')} "
                                f"(e.g. ESP_042252_1930) or {param('product_id')}")
    return ortho_id(observation, request.bands, request.geometry.map_scale, request.sequence)


def height_datum(name: str) -> str:
    """What a HiRISE DTM's heights are above, whatever its name."""
    return HEIGHT_DATUM


def is_dtm_id(product_id: str) -> bool:
    """Whether an ID names a HiRISE DTM (an orthoimage's source DTM must be one)."""
    return DTM_ID_RE.fullmatch(product_id) is not None


def is_hirise(facts: LabelFacts) -> bool:
    """A HiRISE label names the instrument (or the MRO HiRISE data set)."""
    return facts.instrument_id.upper() == INSTRUMENT_ID or data_set_names_mission(facts, INSTRUMENT_ID, DATA_SET_PREFIX)


# PDS4: the mro_hirise bundle and the registered MRO and HiRISE context products.
PDS4 = Pds4Facts(
    bundle="mro_hirise",
    curating_facility="PDS Imaging Node",  # HiRISE's PDS3 archive (its observations and DTMs)
    investigation=ContextReference(
        "Mars Reconnaissance Orbiter", "Mission",
        "urn:nasa:pds:context:investigation:mission.mars_reconnaissance_orbiter", "data_to_investigation"),
    observing_system=(
        ContextReference("Mars Reconnaissance Orbiter", "Host",
                         "urn:nasa:pds:context:instrument_host:spacecraft.mro", "is_instrument_host"),
        ContextReference("High Resolution Imaging Science Experiment", "Instrument",
                         "urn:nasa:pds:context:instrument:hirise.mro", "is_instrument"),
    ),
)

MISSION = Mission(
    name="hirise",
    dtm_keywords=KEYWORDS,
    dtm_note=DTM_NOTE,
    credit=CREDIT,
    ortho_keywords=KEYWORDS,
    ortho_description=ORTHO_DESCRIPTION,
    filter_wavelengths_nm=FILTER_WAVELENGTHS_NM,
    default_ortho_bits_for_float=10,
    valid_range_decimals=VALID_RANGE_DECIMALS,
    ortho_stretch_namespace="MRO",
    ortho_standard_parallels_na=True,
    dtm_product_id=dtm_product_id,
    ortho_product_id=ortho_product_id,
    detect=is_hirise,
    dtm_height_datum=height_datum,
    source_dtm_id=is_dtm_id,
    pds4=PDS4,
    options=STANDARD_OPTIONS.adding(dtm={"institution"}),  # institution letter of its DTM IDs
)
