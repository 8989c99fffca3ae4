"""Mars Express HRSC level 4: names, keywords, constants and detection.

Conventions (pds3-products.md section 7, the archive's DSMAP.CAT): file names
`hOOOO_NNNN_<kind>.img` (orbit of 4 or 5 digits, sequence of 4, kind such as
`dt4` heights above the sphere, `da4` heights above the areoid, `nd4` nadir
image); heights and maps on the 3396.0 km sphere; sinusoidal within 85 degrees
of the equator and polar stereographic poleward; int16 heights with the `MEX:DTM`
group repeating the IMAGE's scaling, -32768 meaning no data; -1e+32 where a
number does not apply.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

from ..errors import PdsgenError, param
from .base import ContextReference, LabelFacts, Mission, OptionUse, Pds4Facts, data_set_names_mission

INSTRUMENT_ID = "HRSC"
DATA_SET_PREFIX = "MEX-M-HRSC"
DTM_GROUP = "MEX:DTM"
CREDIT = "ESA/DLR/FU Berlin"

SPHERE_KM = 3396.0
SPHERE_M = SPHERE_KM * 1000.0
POLAR_LIMIT_DEG = 85.0
MISSING_DN = -32768
DN_LIMIT = 32767  # stored heights use -32767..32767; -32768 is MISSING_DN
NOT_APPLICABLE = -1e32  # HRSC's numeric "not applicable" value
SPHERE_DESC = "HEIGHT ABOVE SPHEROID"
AREOID_DESC = "HEIGHT ABOVE GM3-AREOID"
# The datums of DTM_KINDS in words (acronyms keep their case): Extras legends say "m above ...",
# the IMAGE NOTE of each kind names the datum's source after it.
HEIGHT_DATUMS = {"sphere": f"the {SPHERE_KM:.1f} km sphere", "areoid": "the GM3 areoid"}
DTM_NOTE_DATUMS = {
    "dt4": f"above {HEIGHT_DATUMS['sphere']} (SPHEROID)",
    "da4": f"above {HEIGHT_DATUMS['areoid']} (MGS-M-MOLA-5-MEGDR-L3-V1.0)",
}
# DTM kinds: the datum the stored heights are above, and MEX:DTM_DESC.
DTM_KINDS = {
    "dt4": ("sphere", SPHERE_DESC),
    "da4": ("areoid", AREOID_DESC),
}

# The one parser of HRSC names: `h1234_0000`, optionally `_dt4` (any two letters and a level digit).
NAME_RE = re.compile(r"^h(?P<orbit>\d{4,5})_(?P<sequence>\d{4})(?:_(?P<kind>[a-z]{2}\d))?", re.IGNORECASE)

KEYWORDS = {
    "DATA_SET_ID": "MEX-M-HRSC-5-REFDR-DTM-V1.0",
    "DATA_SET_NAME": "MARS EXPRESS HRSC REFERENCE DIGITAL TERRAIN MODEL V1.0",
    "PRODUCER_INSTITUTION_NAME": "DLR / FREIE UNIVERSITAET BERLIN",
    "PRODUCER_ID": "DLR_FUB",
    "PRODUCER_FULL_NAME": "UNK",
    "INSTRUMENT_HOST_NAME": "MARS EXPRESS",
    "INSTRUMENT_HOST_ID": "MEX",
    "INSTRUMENT_NAME": "HIGH RESOLUTION STEREO CAMERA",
    "INSTRUMENT_ID": INSTRUMENT_ID,
    "TARGET_NAME": "MARS",
    "RATIONALE_DESC": "UNK",
}
# Level-4 nadir images are released beside the DT4/DA4 of the same orbit, in the DTM data set.
ND4_KEYWORDS = dict(KEYWORDS)
PROCESSING_LEVEL = 4
MISSION_NAME = "MARS EXPRESS"

# Keywords DLR's pipeline carries from the source level-2/3 labels into level-4 labels,
# by label section, in DLR's order. Written only when a source label (--source-label)
# gives them: pdsgen never writes placeholders for them.
CARRIED_KEYWORDS = {
    "identification": ("DETECTOR_ID", "EVENT_TYPE"),
    "mission_phase": ("MISSION_PHASE_NAME",),
    "time": ("SPACECRAFT_CLOCK_START_COUNT", "SPACECRAFT_CLOCK_STOP_COUNT", "START_TIME", "STOP_TIME"),
    "orbit": (
        "ASCENDING_NODE_LONGITUDE", "ORBIT_NUMBER", "ORBITAL_ECCENTRICITY", "ORBITAL_INCLINATION",
        "ORBITAL_SEMIMAJOR_AXIS", "PERIAPSIS_ALTITUDE", "PERIAPSIS_ARGUMENT_ANGLE", "PERIAPSIS_TIME",
        "SPACECRAFT_ORIENTATION", "^MEX_ORIENTATION_DESC", "SPACECRAFT_POINTING_MODE",
        "^MEX_POINTING_DESC", "RIGHT_ASCENSION", "DECLINATION", "OFFSET_ANGLE",
        "SPACECRAFT_SOLAR_DISTANCE",
    ),
}
# Of several source labels, the time span runs from the earliest start to the latest stop.
START_KEYWORDS = ("SPACECRAFT_CLOCK_START_COUNT", "START_TIME")
STOP_KEYWORDS = ("SPACECRAFT_CLOCK_STOP_COUNT", "STOP_TIME")

# Projection offsets: "standard" is the PDS3 convention GDAL reads exactly; "dlr" is the
# one DLR's own pipeline writes (DSMAP.CAT's formula, one pixel apart from the standard
# values in both directions), for byte-compatibility with DLR's products.
OFFSET_CONVENTIONS = {"standard": 0.0, "dlr": 1.0}
OFFSET_NOTES = {
    "standard": (
        "/* LINE/SAMPLE_PROJECTION_OFFSET follow the PDS3 standard convention:  */",
        "/* the projection origin counted from the centre of the first pixel,   */",
        "/* as GDAL reads them (DLR's own products count one pixel further).    */",
    ),
    "dlr": (
        "/* LINE/SAMPLE_PROJECTION_OFFSET follow DLR's convention (DSMAP.CAT),   */",
        "/* one pixel beyond the PDS3 standard values: default GDAL places this  */",
        "/* grid one pixel off (pdsgen's default is the standard convention).    */",
    ),
}
DTM_NOTE = "Heights in meters = DN * SCALING_FACTOR + OFFSET."


def parse_name(name: str) -> re.Match[str] | None:
    """Orbit, sequence and (if present) kind of an HRSC file or product name."""
    return NAME_RE.match(Path(name).name)


def base_name(product_id: str | None, source_ids: Sequence[str]) -> tuple[str, int]:
    """`h6541_0000` and orbit 6541, from the product ID or the first source product."""
    for candidate in ([product_id] if product_id else []) + list(source_ids):
        match = parse_name(candidate)
        if match:
            return f"h{match.group('orbit')}_{match.group('sequence')}", int(match.group("orbit"))
    raise PdsgenError(
        None,
        f"HRSC names need the orbit and sequence: give {param('product_id', 'h1234_0000')} "
        f"or an HRSC {param('source_product_ids')} entry such as H1234_0000_ND3",
    )


def name_kind(name: str) -> str | None:
    """The product kind of an HRSC name (`dt4`, `da4`, `nd4`, `ir4` ...), lower case."""
    match = parse_name(name)
    kind = match.group("kind") if match else None
    return kind.lower() if kind else None


def is_dtm_name(name: str) -> bool:
    """An HRSC (or iMars) DTM file name: kind dt4 or da4."""
    return name_kind(name) in DTM_KINDS


def height_datum(name: str) -> str | None:
    """What an HRSC (or iMars) DTM's heights are above, from its kind (dt4, da4); None otherwise."""
    kind = name_kind(name)
    return HEIGHT_DATUMS[DTM_KINDS[kind][0]] if kind in DTM_KINDS else None


def is_hrsc(facts: LabelFacts) -> bool:
    """An HRSC product: the instrument, the data set, a MEX:DTM group or a level-4 file name says so."""
    kind = name_kind(facts.file_name)
    return (
        facts.instrument_id.strip().upper() == INSTRUMENT_ID
        or data_set_names_mission(facts, INSTRUMENT_ID, DATA_SET_PREFIX)
        or DTM_GROUP in facts.group_names
        or (kind is not None and kind.endswith("4"))
    )


# PDS4 (ESA's PSA holds Mars Express in PDS4): the mex_hrsc bundle and the registered
# Mars Express and HRSC context products.
PDS4 = Pds4Facts(
    bundle="mex_hrsc",
    authority="urn:esa:psa",
    curating_facility="ESA PSA",
    investigation=ContextReference("Mars Express", "Mission",
                                   "urn:esa:psa:context:investigation:mission.mars_express", "data_to_investigation"),
    observing_system=(
        ContextReference("Mars Express", "Host", "urn:esa:psa:context:instrument_host:spacecraft.mex",
                         "is_instrument_host"),
        ContextReference("High Resolution Stereo Camera", "Instrument",
                         "urn:esa:psa:context:instrument:mex.hrsc", "is_instrument"),
    ),
)

def mosaic_name_refusal(product_id: str) -> str | None:
    """An HRSC product is named by orbit and sequence; the HRSC writer would otherwise take
    them from the first source, naming the mosaic after (and as) one of its own strips."""
    if parse_name(product_id) is None:
        return (f"an HRSC mosaic is named by orbit and sequence: give {param('product_id', 'h1234_0000')} "
                "(not its first source's name)")
    return None


MISSION = Mission(
    name="hrsc",
    dtm_keywords=KEYWORDS,
    dtm_note=DTM_NOTE,
    credit=CREDIT,
    dtm_writer="pdsgen.products.hrsc:write_hrsc_dtm",
    ortho_writer="pdsgen.products.hrsc:write_hrsc_nd4",
    detect=is_hrsc,
    dtm_height_datum=height_datum,
    pds4=PDS4,
    options=OptionUse(
        dtm=frozenset({"source_product_ids", "source_labels", "offset_convention", "byte_order", "kind",
                       "vertical_datum", "areoid", "precision", "reproject_input", "label",
                       "allow_dictionary_deviations"}),
        ortho=frozenset({"source_product_ids", "source_labels", "offset_convention", "bits", "reproject_input",
                         "label", "allow_dictionary_deviations"}),
        mosaic=frozenset({"precision", "reproject_input", "label", "allow_dictionary_deviations"}),
        command_defaults={"vertical_datum": "sphere"},
        defaults={"byte_order": "msb", "vertical_datum": "sphere"},  # DLR's products are big-endian
    ),
    mosaic_product_id=mosaic_name_refusal,
)
