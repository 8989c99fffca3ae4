"""PDS4 labels name the source products wherever the PDS3 label of the same product states
SOURCE_PRODUCT_ID: a DTM made from a stereo pair, a mosaic (`--label both`), a migrated
product. Read by XPath (lxml) and by pds4_tools; the labels pass the shipped IM 1.24 XSD and
Schematron (Source_Product_External needs a curating_facility or a doi, and its
reference_type is one of the Schematron's five) and `pdsgen validate`."""

from __future__ import annotations

import shutil

import pvl
import pytest
from lxml import etree

from pdsgen import write_dtm
from pdsgen.migrate import migrate_product
from pdsgen.mosaic import write_mosaic
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.label_checks import validate_pds4
from test_mosaic import make_strips

from helpers import ORIGINS, elevation_array, run_cli, stated_keywords, write_raster

needs_saxon = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")
NS = {"pds": "http://pds.nasa.gov/pds4/pds/v1"}
SOURCES = "/pds:Product_Observational/pds:Reference_List/pds:Source_Product_External"
PAIR = ["PSP_008669_1705", "PSP_009025_1705"]  # the stereo pair of pds3-products.md's HiRISE DTM


def named_sources(xml_path) -> list[str]:
    tree = etree.parse(str(xml_path))
    return [e.text for e in tree.xpath(f"{SOURCES}/pds:external_source_product_identifier", namespaces=NS)]


def pds3_sources(label_path) -> list[str]:
    value = pvl.load(str(label_path))["SOURCE_PRODUCT_ID"]
    return [value] if isinstance(value, str) else [str(v) for v in value]


def a_dtm(tmp_path, **options):
    crs, transform = ORIGINS["equirectangular"]
    source = write_raster(tmp_path / "in.tif", elevation_array(21, 17, seed=3), crs, transform, nodata=-9999.0)
    return write_dtm(source, tmp_path / "out", label="both", params=stated_keywords(options.get("profile", "generic")),
                     **options)


@needs_saxon
def test_dtm_from_a_stereo_pair_names_both_sources(tmp_path):
    product = a_dtm(tmp_path, product_id="PAIR_DTM", source_product_ids=PAIR)
    assert pds3_sources(product.path) == PAIR
    assert named_sources(product.pds4_label_path) == PAIR
    tree = etree.parse(str(product.pds4_label_path))
    assert tree.xpath(f"{SOURCES}/pds:reference_type/text()", namespaces=NS) == ["data_to_derived_source_product"]
    assert tree.xpath(f"{SOURCES}/pds:curating_facility/text()", namespaces=NS) == ["PDS"]
    # Reference_List sits where IM 1.24 puts it: after Observation_Area, before the files
    order = [etree.QName(e).localname for e in tree.getroot()]
    assert order.index("Observation_Area") + 1 == order.index("Reference_List") == order.index(
        "File_Area_Observational") - 1
    assert validate_pds4(product.pds4_label_path) == []
    result = run_cli("validate", product.pds4_label_path.parent)
    assert result.returncode == 0 and "0 error(s), 0 warning(s)" in result.stdout, result.stdout


@needs_saxon
def test_hirise_sources_are_curated_by_the_imaging_node(tmp_path):
    product = a_dtm(tmp_path, product_id="PAIR_DTM", source_product_ids=PAIR, profile="hirise")
    tree = etree.parse(str(product.pds4_label_path))
    assert tree.xpath(f"{SOURCES}/pds:curating_facility/text()", namespaces=NS) == ["PDS Imaging Node"]
    assert named_sources(product.pds4_label_path) == PAIR
    assert validate_pds4(product.pds4_label_path) == []


def test_pds4_tools_reads_the_sources(tmp_path):
    pds4_tools = pytest.importorskip("pds4_tools")
    product = a_dtm(tmp_path, product_id="PAIR_DTM", source_product_ids=PAIR)
    label = pds4_tools.read(str(product.pds4_label_path), quiet=True, lazy_load=True).label
    found = label.findall(".//Reference_List/Source_Product_External/external_source_product_identifier")
    assert [e.text for e in found] == PAIR


def test_no_sources_no_reference_list(tmp_path):
    product = a_dtm(tmp_path, product_id="LONE_DTM")
    assert pds3_sources(product.path) == ["N/A"]  # the PDS3 label: none
    assert "Reference_List" not in product.pds4_label_path.read_text()


@needs_saxon
@pytest.mark.skipif(shutil.which("gdal_merge.py") is None, reason="make_strips lives with the gdal_merge tests")
@pytest.mark.parametrize("kind", ["dtm", "ortho"])
def test_mosaic_with_both_labels_names_each_strip(tmp_path, kind):
    strips = make_strips(tmp_path, "float32" if kind == "dtm" else "uint8", count=3)
    product = write_mosaic(strips, tmp_path / "out", product_id=f"{kind.upper()}_MOSAIC", kind=kind, label="both",
                           params=stated_keywords())
    expected = [s.stem for s in strips]
    assert pds3_sources(product.path if kind == "dtm" else product.label_path) == expected
    assert named_sources(product.pds4_label_path) == expected
    assert validate_pds4(product.pds4_label_path) == []
    result = run_cli("validate", product.pds4_label_path.parent)
    assert result.returncode == 0 and "0 error(s)" in result.stdout, result.stdout


@needs_saxon
def test_migrate_carries_source_product_id(tmp_path):
    dtm = a_dtm(tmp_path, product_id="PAIR_DTM", source_product_ids=PAIR)
    migrated = migrate_product(dtm.path, tmp_path / "migrated", bundle_lid="urn:nasa:pds:pdsgen_sources_test")
    assert named_sources(migrated.label_path) == PAIR
    assert validate_pds4(migrated.label_path) == []
    (tmp_path / "lone").mkdir()
    lone = a_dtm(tmp_path / "lone", product_id="LONE_DTM")
    migrated = migrate_product(lone.path, tmp_path / "lone_migrated", bundle_lid="urn:nasa:pds:pdsgen_sources_test")
    assert "Reference_List" not in migrated.label_path.read_text()
