"""HRSC-AX, the airborne High Resolution Stereo Camera (DLR): names, constants, keywords.

An HRSC-AX tile is a set of VICAR files, one per channel, named after the tile's
upper-left corner in kilometres of the map grid and its size:
`430-8765_5.0x5.0km.dsm` is the tile 430 km east, 8,765 km north (UTM zone 33
north), 5 x 5 km; its extension names the channel (`dsm` heights, `pan` nadir
panchromatic, `re` `gr` `bl` red/green/blue, `cir_re` `cir_gr` `cir_bl` the
colour-infrared composite: infrared, red and green merged with the nadir channel).

Heights are ellipsoid heights above the rotational ellipsoid A = B = 6378.14 km,
C = 6356.75 km (not geoid heights: sea level lies at about +36.5 m). The VICAR MAP
group's LINE/SAMPLE_PROJECTION_OFFSET are, by the HRSC-AX image description (Table B2),
"the offset value of the map projection origin position from the center of the pixel at
line and sample position 1,1": the PDS3 standard convention, as GDAL's VICAR reader reads
them. DLR's Mars Express HRSC labels count one pixel further (DSMAP.CAT); a producer whose
tiles were written that way says so (`vicar_offsets="dlr"`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError, PdsgenError, param
from .base import LabelFacts, Mission, OptionUse, ProductIdRequest
from .hrsc import OFFSET_CONVENTIONS

NAME = "hrsc-ax"
INSTRUMENT_ID = "HRSC-AX"
INSTRUMENT_NAME = "HIGH RESOLUTION STEREO CAMERA - AIRBORNE EXTENDED"
CREDIT = "DLR"
TARGET_NAME = "EARTH"

# The HRSC-AX ellipsoid (km) the heights and the map grid are on.
A_AXIS_KM = 6378.14
B_AXIS_KM = 6378.14
C_AXIS_KM = 6356.75
GEOID_NOTE = "sea level lies at about +36.5 m above this ellipsoid"
HEIGHT_DATUM = f"the {A_AXIS_KM} x {C_AXIS_KM} km ellipsoid (sea level at about +36.5 m)"

# How a tile's VICAR MAP offsets count: "standard" by Table B2 of the HRSC-AX image
# description (from the centre of pixel 1,1: the PDS3 standard convention itself, nothing to
# subtract; the default), "dlr" one pixel further as DLR's HRSC Mars labels do (missions/hrsc.py,
# for producers who wrote their tiles that way). Pixels to subtract to reach the standard values.
TABLE_B2_SHIFT = 0.0
VICAR_OFFSETS = {"standard": TABLE_B2_SHIFT, "dlr": OFFSET_CONVENTIONS["dlr"]}
VICAR_OFFSET_NOTES = {
    "standard": (
        "/* The source tile's VICAR LINE/SAMPLE_PROJECTION_OFFSET were read  */",
        "/* as the HRSC-AX image description defines them (Table B2): from   */",
        "/* the centre of pixel 1,1, the PDS3 standard convention GDAL reads. */",
    ),
    "dlr": (
        "/* The source tile's VICAR LINE/SAMPLE_PROJECTION_OFFSET were read  */",
        "/* in DLR's HRSC Mars counting (DSMAP.CAT), one pixel beyond the    */",
        "/* HRSC-AX image description's Table B2, as the producer chose.     */",
    ),
}
# Missing data: stored DEM values at or below this are no data (DLR's VICAR DEMs and the
# PDS products derived from them use -32768 for a missing post).
MISSING_STORED = -32768.0


@dataclass(frozen=True)
class Channel:
    """One HRSC-AX channel file: what it holds and its centre wavelength (nm, None for heights)."""

    extension: str
    band_name: str
    wavelength_nm: int | None


# Centre wavelengths of the HRSC filters (nm): blue 440, green 530, red 750, near-infrared 970,
# nadir (panchromatic) 675.
CHANNELS = {
    "dsm": Channel("dsm", "HEIGHT", None),
    "pan": Channel("pan", "PANCHROMATIC", 675),
    "re": Channel("re", "RED", 750),
    "gr": Channel("gr", "GREEN", 530),
    "bl": Channel("bl", "BLUE", 440),
    "cir_re": Channel("cir_re", "NEAR-INFRARED", 970),
    "cir_gr": Channel("cir_gr", "RED", 750),
    "cir_bl": Channel("cir_bl", "GREEN", 530),
}
# Products of several channels, by the channels in the order the bands are stored.
COMPOSITES = {("re", "gr", "bl"): "RGB", ("cir_re", "cir_gr", "cir_bl"): "CIR"}
PRODUCT_KINDS = {"dsm": "DEM", "pan": "PAN"}  # products of one channel file
FILTER_WAVELENGTHS_NM = {c.band_name: c.wavelength_nm for c in CHANNELS.values() if c.wavelength_nm}

# The one parser of tile names: 430-8765_5.0x5.0km(.dsm)
TILE_RE = re.compile(
    r"^(?P<east>\d+)-(?P<north>\d+)_(?P<width>\d+(?:\.\d+)?)x(?P<height>\d+(?:\.\d+)?)km"
    r"(?:\.(?P<channel>[a-z_]+))?$", re.IGNORECASE)

# No archive has registered an HRSC-AX data set: its ID and name are the producer's to give
# (--params DATA_SET_ID / DATA_SET_NAME), UNK until then.
KEYWORDS = {
    "DATA_SET_ID": "UNK",
    "DATA_SET_NAME": "UNK",
    "PRODUCER_INSTITUTION_NAME": "DEUTSCHES ZENTRUM FUER LUFT- UND RAUMFAHRT",
    "PRODUCER_ID": "DLR",
    "PRODUCER_FULL_NAME": "UNK",
    "INSTRUMENT_HOST_NAME": "AIRCRAFT",
    "INSTRUMENT_HOST_ID": "AIRCRAFT",
    "INSTRUMENT_NAME": INSTRUMENT_NAME,
    "INSTRUMENT_ID": INSTRUMENT_ID,
    "TARGET_NAME": TARGET_NAME,
    "RATIONALE_DESC": "UNK",
}


def channel_of(path: str | Path) -> Channel:
    """The channel a file holds, from its extension (`.dsm`, `.pan`, `.cir_re` ...)."""
    extension = Path(path).suffix.lstrip(".").lower()
    try:
        return CHANNELS[extension]
    except KeyError:
        raise InputError(path, f"is not an HRSC-AX channel file: the extension .{extension} is none of "
                               f"{', '.join('.' + c for c in CHANNELS)}") from None


def product_kind(paths: list[Path]) -> str:
    """DEM, PAN, RGB or CIR for the files given, in the order given; anything else is refused."""
    channels = tuple(channel_of(path).extension for path in paths)
    if len(channels) == 1 and channels[0] in PRODUCT_KINDS:
        return PRODUCT_KINDS[channels[0]]
    if channels in COMPOSITES:
        return COMPOSITES[channels]
    bands = set(channels)
    for composite, kind in COMPOSITES.items():
        if bands == set(composite):  # the right files in another order: the bands would be misnamed
            order = " ".join(f"TILE.{c}" for c in composite)
            raise PdsgenError(None, f"an HRSC-AX {kind} product takes its channels in the order {order}")
    raise PdsgenError(None, "HRSC-AX products are one .dsm, one .pan, TILE.re TILE.gr TILE.bl (RGB) or "
                            f"TILE.cir_re TILE.cir_gr TILE.cir_bl (CIR); got {' '.join('.' + c for c in channels)}")


def tile_product_id(tile_stem: str, kind: str) -> str:
    """`HRSCAX_430_8765_5_0X5_0KM_DEM` from the tile `430-8765_5.0x5.0km` and the product kind.

    A legal PDS identifier: letters, digits and underscores, starting with a letter.
    """
    match = TILE_RE.match(tile_stem)
    if match is None:
        raise PdsgenError(None, f"{tile_stem!r} is not an HRSC-AX tile name (EAST-NORTH_WxHkm, e.g. "
                                f"430-8765_5.0x5.0km); give {param('product_id')}")
    width, height = (match.group(k).replace(".", "_") for k in ("width", "height"))
    product_id = f"HRSCAX_{match.group('east')}_{match.group('north')}_{width}X{height}KM_{kind}"
    if len(product_id) > 40:
        raise PdsgenError(None, f"the product ID {product_id} would be longer than 40 characters; "
                                f"give {param('product_id')}")
    return product_id


def tile_stem(path: str | Path) -> str:
    """The tile name of a channel file: `430-8765_5.0x5.0km` of `430-8765_5.0x5.0km.cir_re`."""
    return Path(path).name[: -len(Path(path).suffix)] if Path(path).suffix else Path(path).name


def survey_sentence(survey_date: str | None) -> str:
    """Who flew the survey, and when when known (a NOTE's or DESCRIPTION's last sentence)."""
    return f"Airborne survey (HRSC-AX, DLR) of {survey_date}." if survey_date else \
        "Airborne survey by HRSC-AX (DLR)."


def dtm_note(offset: float, scaling_factor: float, cut_off: tuple[float, float] | None,
             survey_date: str | None) -> str:
    """A DEM's NOTE: what the numbers are (ellipsoid heights, how stored values became them),
    the producer's cut-off, the survey."""
    parts = [
        f"Pixel values are ellipsoid heights in meters above the HRSC-AX ellipsoid (A = B = "
        f"{A_AXIS_KM} km, C = {C_AXIS_KM} km), not geoid heights: {GEOID_NOTE}.",
        f"Heights = DTM_OFFSET + stored value * DTM_SCALING_FACTOR of the source "
        f"({offset:g} + value * {scaling_factor:g}).",
    ]
    if cut_off is not None:
        parts.append(f"Heights were cut off by the producer to DTM_RANGE {cut_off[0]:g} .. {cut_off[1]:g} m.")
    parts.append(survey_sentence(survey_date))
    parts.append("Pixels equal to MISSING_CONSTANT hold no data.")
    return " ".join(p for p in parts if p)


def ortho_description(kind: str, channels: tuple[Channel, ...], survey_date: str | None) -> str:
    """An orthoimage's DESCRIPTION: which band is which channel and wavelength, the survey."""
    if kind == "PAN":
        what = (f"HRSC-AX panchromatic nadir orthoimage ({CHANNELS['pan'].wavelength_nm} nm), "
                "8-bit DNs, DN 0 = no data.")
    else:
        bands = ", ".join(f"band {i} {c.band_name} {c.wavelength_nm} nm (.{c.extension})"
                          for i, c in enumerate(channels, start=1))
        merged = " merged with the nadir channel" if kind == "CIR" else ""
        what = f"HRSC-AX {kind} colour orthoimage{merged}: {bands}; 8-bit DNs, DN 0 = no data."
    return " ".join(p for p in (what, survey_sentence(survey_date)) if p)


def _product_id(request: ProductIdRequest) -> str:
    return tile_product_id(tile_stem(request.stem), "DEM")


def is_hrsc_ax(facts: LabelFacts) -> bool:
    """A label of an HRSC-AX product: its instrument says so."""
    return facts.instrument_id.strip().upper() == INSTRUMENT_ID


def height_datum(name: str) -> str | None:
    """What the heights of an HRSC-AX DEM are above (Extras legends)."""
    return HEIGHT_DATUM if "_DEM" in name.upper() or name.lower().endswith(".dsm") else None


MISSION = Mission(
    name=NAME,
    dtm_keywords=KEYWORDS,
    dtm_note="",
    credit=CREDIT,
    ortho_keywords=KEYWORDS,
    ortho_description="HRSC-AX orthoimage",
    filter_wavelengths_nm=FILTER_WAVELENGTHS_NM,
    default_ortho_bits_for_float=16,
    dtm_product_id=_product_id,
    dtm_writer="pdsgen.products.hrsc_ax:write_hrsc_ax_dtm",
    ortho_writer="pdsgen.products.hrsc_ax:write_hrsc_ax_ortho",
    detect=is_hrsc_ax,
    dtm_height_datum=height_datum,
    # A tile names no source products; its XML labels and VICAR offsets are its own.
    options=OptionUse(
        dtm=frozenset({"source_labels", "vicar_offsets", "byte_order", "label", "allow_dictionary_deviations"}),
        ortho=frozenset({"source_labels", "vicar_offsets", "gmljp2", "label", "allow_dictionary_deviations"}),
        mosaic=frozenset({"source_labels", "vicar_offsets", "byte_order", "label", "allow_dictionary_deviations"}),
    ),
    composes_ortho_bands=True,  # a colour product: one file per channel
    # A mosaic reads tiles as a tile's product does (grid, heights, offsets) and writes the standard forms.
    mosaic_reader="pdsgen.mosaic.hrsc_ax:tile_inputs",
    mosaic_reader_options=frozenset({"source_labels", "vicar_offsets"}),
)
