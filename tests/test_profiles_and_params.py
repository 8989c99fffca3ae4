"""Mission naming rules and the --params file."""

from __future__ import annotations

import pytest
from affine import Affine
from rasterio.crs import CRS

from pdsgen.errors import PdsgenError
from pdsgen.geo.geometry import MapGeometry, describe_geometry
from pdsgen.missions import ProductIdRequest
from pdsgen.missions.generic import generic_product_id
from pdsgen.missions.hirise import dtm_product_id
from pdsgen.missions.hirise import scale_letter as hirise_scale_letter
from pdsgen.missions.hirise import version_code as hirise_version_code
from pdsgen.params import load_params


def hirise_dtm_product_id(geometry: MapGeometry, source_ids: list[str], institution: str | None, version: str) -> str:
    """The HiRISE DTM product ID the profile's writer would choose for these sources."""
    return dtm_product_id(ProductIdRequest("", geometry, source_ids, institution, version))

EQC = CRS.from_proj4("+proj=eqc +lat_ts=-5 +lon_0=180 +R=3396190 +units=m")
POLAR = CRS.from_proj4("+proj=stere +lat_0=90 +lon_0=0 +k=1 +R=3396190 +units=m")
SINU = CRS.from_proj4("+proj=sinu +lon_0=0 +R=3396190 +units=m")


@pytest.mark.parametrize(
    ("version", "code"), [("1.0", "01"), ("2.0", "02"), ("9.0", "09"), ("1.5", "15"), ("3.7", "37")]
)
def test_hirise_version_codes(version, code):
    assert hirise_version_code(version) == code


@pytest.mark.parametrize("version", ["1.05", "10.5", "0.105", "10.0", "0.5", "x"])
def test_unencodable_versions_are_refused(version):
    with pytest.raises(PdsgenError, match="cannot be encoded"):
        hirise_version_code(version)


def test_version_codes_never_collide():
    versions = [f"{major}.{minor}" for major in range(1, 10) for minor in range(10)]
    codes = [hirise_version_code(v) for v in versions]
    assert len(set(codes)) == len(codes)


@pytest.mark.parametrize(("scale", "letter"), [(0.25, "A"), (0.5, "B"), (1.0, "C"), (1.0113, "C"), (2.0, "D"),
                                               (128.0, "J"), (0.92, "C")])
def test_scale_letters(scale, letter):
    assert hirise_scale_letter(scale) == letter


def test_scale_outside_ten_percent_is_refused():
    with pytest.raises(PdsgenError):
        hirise_scale_letter(1.5)


def test_hirise_dtm_product_id_from_sources():
    geometry = describe_geometry(EQC, Affine(1.0, 0, 6e6, 0, -1.0, -5e5), 10, 10)
    product_id = hirise_dtm_product_id(geometry, ["PSP_008669_1705", "PSP_009025_1705"], "A", "1.0")
    assert product_id == "DTEEC_008669_1705_009025_1705_A01"
    polar = describe_geometry(POLAR, Affine(2.0, 0, 1e5, 0, -2.0, 1e5), 10, 10)
    assert hirise_dtm_product_id(polar, ["ESP_012345_0850", "ESP_012346_0850"], "U", "2.0") \
        == "DTEPD_012345_0850_012346_0850_U02"


def test_hirise_product_id_refuses_what_it_cannot_name():
    geometry = describe_geometry(EQC, Affine(1.0, 0, 6e6, 0, -1.0, -5e5), 10, 10)
    with pytest.raises(PdsgenError, match="two `source_product_ids`"):
        hirise_dtm_product_id(geometry, ["PSP_008669_1705"], "A", "1.0")
    with pytest.raises(PdsgenError, match="institution"):
        hirise_dtm_product_id(geometry, ["PSP_008669_1705", "PSP_009025_1705"], "ab", "1.0")
    sinusoidal = describe_geometry(SINU, Affine(1.0, 0, 0, 0, -1.0, 0), 10, 10)
    with pytest.raises(PdsgenError, match="no letter for SINUSOIDAL"):
        hirise_dtm_product_id(sinusoidal, ["PSP_008669_1705", "PSP_009025_1705"], "A", "1.0")


def test_generic_product_id_is_pds_safe():
    assert generic_product_id("my dtm-v2.final") == "MY_DTM_V2_FINAL"


def test_params_from_pvl_and_toml_agree(tmp_path):
    pvl_file = tmp_path / "p.pvl"
    pvl_file.write_text('PRODUCER_FULL_NAME = "Jane Doe"\nSOURCE_PRODUCT_ID = (PSP_1, PSP_2)\n'
                        "PRODUCT_VERSION_ID = 2.0\nEND\n")
    toml_file = tmp_path / "p.toml"
    toml_file.write_text('producer_full_name = "Jane Doe"\nsource_product_id = ["PSP_1", "PSP_2"]\n'
                         'product_version_id = "2.0"\n')
    expected = {"PRODUCER_FULL_NAME": "Jane Doe", "SOURCE_PRODUCT_ID": ["PSP_1", "PSP_2"],
                "PRODUCT_VERSION_ID": "2.0"}
    assert load_params(pvl_file) == expected
    assert load_params(toml_file) == expected


def test_params_refuse_non_ascii_and_broken_files(tmp_path):
    bad = tmp_path / "p.toml"
    bad.write_text('producer_full_name = "Jos\u00e9"\n', encoding="utf-8")
    with pytest.raises(PdsgenError, match="7-bit ASCII"):
        load_params(bad)
    broken = tmp_path / "q.toml"
    broken.write_text("producer_full_name = \n")
    with pytest.raises(PdsgenError, match="not valid TOML"):
        load_params(broken)
