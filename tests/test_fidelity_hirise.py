"""HiRISE DTM and orthoimage labels against the keyword sequence of the real release.

The fixtures below are keyword names, their order, and value formats, written from
the structure of these references (no label text is copied):

- ISIS hidtmgen DTM templates, repository DOI-USGS/ISIS3, commit
  7ca57fa91efb62be48d7890347b8f9184f5b9711, paths
  isis/src/mro/apps/hidtmgen/MroHirisePdsDTMEqui.pft and MroHirisePdsDTMPolar.pft
  (IMAGE directly after the pointers; the radius note in equirectangular labels only,
  the CENTER_LATITUDE/LONGITUDE note in both).
- hidtmgen's ortho identification and projection, same commit,
  isis/src/mro/apps/hidtmgen/hidtmgen.cpp (SOURCE_PRODUCT_ID = DTM id, observation id)
  and isis/tests/FunctionalTestsHidtmgen.cpp (FIRST/SECOND_STANDARD_PARALLEL "N/A"),
  placed by isis/appdata/templates/labels/pdsExportAllMapping.pft (after C_AXIS_RADIUS).
- The released HiRISE RDR JP2 label tests/data/corpus/real/ESP_013951_1955_RED.LBL
  (IMAGE keywords: CENTER_FILTER_WAVELENGTH, MRO:MINIMUM_STRETCH, MRO:MAXIMUM_STRETCH,
  FILTER_NAME) and the released DTM label
  tests/data/corpus/real/DTEEC_008669_1705_009025_1705_A01__gdal_pds_3177.lbl.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.transform import Affine

from pdsgen import write_dtm, write_ortho
from pdsgen.label.values import Fixed, format_value
from pdsgen.products.dtm import valid_bound

MARS_EQC = (
    "+proj=eqc +lat_ts=-5 +lat_0=0 +lon_0=180 +x_0=0 +y_0=0 +R=3396190 +units=m +no_defs"
)
MARS_POLAR = "+proj=stere +lat_0=90 +lon_0=0 +k=1 +x_0=0 +y_0=0 +R=3376200 +units=m +no_defs"

COMMENT = "/*"  # a comment line in a keyword sequence
IMAGE_OBJECT = [
    "LINES", "LINE_SAMPLES", "BANDS", "OFFSET", "SCALING_FACTOR", "NOTE", "SAMPLE_BITS",
    "SAMPLE_BIT_MASK", "SAMPLE_TYPE", "MISSING_CONSTANT", "VALID_MINIMUM", "VALID_MAXIMUM",
]
IDENTIFICATION = [
    "DATA_SET_ID", "DATA_SET_NAME", "PRODUCER_INSTITUTION_NAME", "PRODUCER_ID",
    "PRODUCER_FULL_NAME", "PRODUCT_ID", "PRODUCT_VERSION_ID", "INSTRUMENT_HOST_NAME",
    "INSTRUMENT_HOST_ID", "INSTRUMENT_NAME", "INSTRUMENT_ID", "TARGET_NAME",
    "SOURCE_PRODUCT_ID", "RATIONALE_DESC", "SOFTWARE_NAME",
]
PROJECTION_TAIL = [
    "CENTER_LATITUDE", "CENTER_LONGITUDE", "LINE_FIRST_PIXEL", "LINE_LAST_PIXEL",
    "SAMPLE_FIRST_PIXEL", "SAMPLE_LAST_PIXEL", "MAP_PROJECTION_ROTATION", "MAP_RESOLUTION",
    "MAP_SCALE", "MAXIMUM_LATITUDE", "MINIMUM_LATITUDE", "LINE_PROJECTION_OFFSET",
    "SAMPLE_PROJECTION_OFFSET", "EASTERNMOST_LONGITUDE", "WESTERNMOST_LONGITUDE",
]


def _projection(radius_note: bool, standard_parallels: bool) -> list[str]:
    return [
        "OBJECT=IMAGE_MAP_PROJECTION", "^DATA_SET_MAP_PROJECTION", "MAP_PROJECTION_TYPE",
        "PROJECTION_LATITUDE_TYPE", *([COMMENT] if radius_note else []),
        "A_AXIS_RADIUS", "B_AXIS_RADIUS", "C_AXIS_RADIUS",
        *(["FIRST_STANDARD_PARALLEL", "SECOND_STANDARD_PARALLEL"] if standard_parallels else []),
        "COORDINATE_SYSTEM_NAME", "POSITIVE_LONGITUDE_DIRECTION", "KEYWORD_LATITUDE_TYPE", COMMENT,
        *PROJECTION_TAIL, "END_OBJECT=IMAGE_MAP_PROJECTION",
    ]


def dtm_sequence(equirectangular: bool) -> list[str]:
    return [
        "PDS_VERSION_ID", COMMENT, "RECORD_TYPE", "RECORD_BYTES", "FILE_RECORDS", "LABEL_RECORDS",
        "^IMAGE", "OBJECT=IMAGE", *IMAGE_OBJECT, "END_OBJECT=IMAGE", COMMENT, *IDENTIFICATION,
        *_projection(equirectangular, False),
        "OBJECT=VIEWING_PARAMETERS", "NORTH_AZIMUTH", "END_OBJECT=VIEWING_PARAMETERS", "END",
    ]


ORTHO_IMAGE_TAIL = [
    "BAND_STORAGE_TYPE", "CORE_NULL", "CORE_LOW_REPR_SATURATION", "CORE_LOW_INSTR_SATURATION",
    "CORE_HIGH_REPR_SATURATION", "CORE_HIGH_INSTR_SATURATION", "CENTER_FILTER_WAVELENGTH",
    "MRO:MINIMUM_STRETCH", "MRO:MAXIMUM_STRETCH", "FILTER_NAME", "END_OBJECT=IMAGE",
]
# Value formats of the release (regular expressions on the value text).
DTM_FORMATS = {
    "PRODUCT_VERSION_ID": r'"\d+\.\d+"',
    "SOURCE_PRODUCT_ID": r"\([A-Z]{3}_\d{6}_\d{4}, [A-Z]{3}_\d{6}_\d{4}\)",
    "MISSING_CONSTANT": r"16#FF7FFFFB#",
    "SAMPLE_BIT_MASK": r"2#1{32}#",
    "SAMPLE_TYPE": r"PC_REAL",
    "A_AXIS_RADIUS": r"\d+\.\d+ <KM>",
    "MAP_RESOLUTION": r"\d+\.\d+ <PIX/DEG>",
    "MAP_SCALE": r"\d+\.\d+ <METERS/PIXEL>",
    "LINE_PROJECTION_OFFSET": r"-?\d+\.\d+ <PIXEL>",
    "CENTER_LATITUDE": r"-?\d+\.\d+ <DEG>",
    "NORTH_AZIMUTH": r"\d+\.\d+ <DEG>",
}


def keyword_sequence(text: str) -> tuple[list[str], dict[str, str]]:
    """Statement keys in order (comments as COMMENT, OBJECT/END_OBJECT with their names),
    and each key's value text with continuation lines joined."""
    sequence: list[str] = []
    values: dict[str, str] = {}
    last = None
    for line in text.split("\r\n"):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("/*"):
            if sequence[-1] != COMMENT:
                sequence.append(COMMENT)
            continue
        match = re.match(r"^(\^?[A-Z][A-Z0-9_:]*)\s*=\s*(.*)$", stripped)
        if match is None:
            if stripped == "END":
                sequence.append("END")
            elif last is not None:
                values[last] += " " + stripped
            continue
        key, value = match.groups()
        if key in ("OBJECT", "END_OBJECT", "GROUP", "END_GROUP"):
            sequence.append(f"{key}={value}")
            last = None
        else:
            sequence.append(key)
            values.setdefault(key, value)
            last = key
    return sequence, values


def _raster(path: Path, crs: str, transform: Affine, bands: int = 1, dtype: str = "float32") -> Path:
    rng = np.random.default_rng(3)
    data = (rng.random((bands, 24, 20)) * (0.2 if dtype == "float32" else 900)).astype(dtype)
    if dtype == "float32" and bands == 1:
        data = data * 1000 - 4000
    with rasterio.open(path, "w", driver="GTiff", width=20, height=24, count=bands, dtype=dtype,
                       crs=crs, transform=transform) as out:
        out.write(data)
    return path


@pytest.mark.parametrize("projection", ["equirectangular", "polar"])
def test_hirise_dtm_label_follows_the_release_sequence(tmp_path, projection):
    if projection == "equirectangular":
        source = _raster(tmp_path / "dtm.tif", MARS_EQC, Affine(1.0, 0, 6123456.0, 0, -1.0, 563211.0))
    else:
        source = _raster(tmp_path / "dtm.tif", MARS_POLAR, Affine(1.0, 0, 1000.0, 0, -1.0, 2000.0))
    product = write_dtm(source, tmp_path / "out", profile="hirise", institution="U",
                        source_product_ids=["PSP_008669_1705", "PSP_009025_1705"])
    sequence, values = keyword_sequence(product.label_text)
    assert sequence == dtm_sequence(projection == "equirectangular")
    for key, pattern in DTM_FORMATS.items():
        assert re.fullmatch(pattern, values[key]), (key, values[key])


def test_hirise_ortho_label_follows_the_release_sequence(tmp_path):
    source = _raster(tmp_path / "ortho.tif", MARS_EQC, Affine(0.5, 0, 6123456.0, 0, -0.5, 563211.0), 3)
    product = write_ortho(source, tmp_path / "out", profile="hirise", observation_id="ESP_042252_1930",
                          source_dtm_id="DTEEC_042252_1930_042753_1930_A01", sequence=41)
    sequence, values = keyword_sequence(product.label_text)
    start = sequence.index("OBJECT=IMAGE_MAP_PROJECTION")
    end = sequence.index("END_OBJECT=IMAGE_MAP_PROJECTION") + 1
    assert sequence[start:end] == _projection(radius_note=True, standard_parallels=True)
    assert sequence[1:start] == [COMMENT, *IDENTIFICATION]
    assert sequence[-len(ORTHO_IMAGE_TAIL) - 2:-2] == ORTHO_IMAGE_TAIL
    assert values["SOURCE_PRODUCT_ID"] == "(DTEEC_042252_1930_042753_1930_A01, ESP_042252_1930)"
    assert values["FIRST_STANDARD_PARALLEL"] == values["SECOND_STANDARD_PARALLEL"] == '"N/A"'
    assert values["FILTER_NAME"] == '("NEAR-INFRARED", "RED", "BLUE-GREEN")'
    assert values["CENTER_FILTER_WAVELENGTH"] == "(900 <NM>, 700 <NM>, 500 <NM>)"
    # 10-bit data: the linear stretch spans the valid DNs 3..1021, as in the release
    assert values["MRO:MINIMUM_STRETCH"] == "(3, 3, 3)"
    assert values["MRO:MAXIMUM_STRETCH"] == "(1021, 1021, 1021)"


def test_generic_ortho_has_no_mro_keywords(tmp_path):
    source = _raster(tmp_path / "ortho.tif", MARS_EQC, Affine(0.5, 0, 6123456.0, 0, -0.5, 563211.0))
    product = write_ortho(source, tmp_path / "out", product_id="MY_ORTHO", any_kind=True)  # height-like values
    sequence, _ = keyword_sequence(product.label_text)
    assert not [key for key in sequence if key.startswith("MRO:") or "STANDARD_PARALLEL" in key]


def test_release_format_of_valid_range_rounds_outwards():
    """Two decimals (the release's VALID_MINIMUM/MAXIMUM format) still bound the data."""
    low = valid_bound(-4049.4746, 2, "minimum")
    high = valid_bound(-2965.6045, 2, "maximum")
    assert isinstance(low, Fixed) and isinstance(high, Fixed)
    assert (format_value(low), format_value(high)) == ("-4049.48", "-2965.60")
    assert valid_bound(12.5, None, "minimum") == 12.5
    # the sample's float32 decimal is what is rounded: float32 1.26 is 1.2599999904632568
    assert [format_value(valid_bound(float(np.float32(1.26)), 2, side)) for side in ("minimum", "maximum")] \
        == ["1.26", "1.26"]
    assert format_value(valid_bound(-1e-9, 2, "minimum")) == "-0.01"  # float32 -1e-09 floors below zero
    assert format_value(valid_bound(1e-9, 2, "minimum")) == "0.00"
    assert valid_bound(-3.4e38, 2, "minimum").value == -3.4e38  # any float32 fits the decimal context
