"""PDS4 products: DTMs in the three projections and a HiRISE orthoimage pass XML Schema and
Schematron, and independent readers (GDAL's PDS4 driver, pds4_tools, OpenJPEG) read back
the same grid, CRS, nodata and samples."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import rasterio
from lxml import etree

from pdsgen import write_dtm, write_ortho
from pdsgen.validate import validate_paths
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.label_checks import validate_pds4

from helpers import ORIGINS, elevation_array, run_cli, stated_keywords, write_raster

# Without saxonche validation is schema-only: the Schematron acceptance tests need it.
needs_saxon = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")


def pds4(product) -> SimpleNamespace:
    """The PDS4 label a `--label pds4` product wrote: its path and text."""
    return SimpleNamespace(path=product.pds4_label_path, text=product.pds4_label_path.read_text(), product=product)


@pytest.fixture(scope="module")
def dtms(tmp_path_factory):
    """One small DTM per projection (with a nodata pixel), written as PDS4; the MSB one polar."""
    root = tmp_path_factory.mktemp("pds4_dtm")
    made = {}
    for name, (crs, transform) in ORIGINS.items():
        data = elevation_array(37, 53, seed=len(name))
        data[3, 5] = -9999.0
        source = write_raster(root / f"{name}.tif", data, crs, transform, nodata=-9999.0)
        label = pds4(write_dtm(source, root / "out", product_id=f"DTM_{name.upper()}", label="pds4",
                               byte_order="msb" if name == "polar" else "lsb", params=stated_keywords()))
        made[name] = (source, label)
    return made


@needs_saxon
@pytest.mark.parametrize("name", sorted(ORIGINS))
def test_dtm_label_passes_schema_and_schematron(dtms, name):
    _, label = dtms[name]
    assert validate_pds4(label.path) == []
    assert "cart:Geo_Transformation" in label.text and "IEEE754" in label.text


@pytest.mark.parametrize("name", sorted(ORIGINS))
def test_gdal_reads_dtm_back_to_same_grid_crs_and_nodata(dtms, name):
    source, label = dtms[name]
    with rasterio.open(source) as original, rasterio.open(label.path) as product:
        assert product.driver == "PDS4"
        assert product.transform == original.transform
        assert product.crs == original.crs
        assert product.nodata == pytest.approx(-3.4028226550889045e38, rel=1e-15)
        data, expected = product.read(1), original.read(1)
        valid = expected != -9999.0
        assert np.array_equal(data[valid], expected[valid])
        assert data[3, 5] == np.float32(product.nodata)


@pytest.mark.parametrize("name", sorted(ORIGINS))
def test_pds4_tools_reads_the_array(dtms, name):
    pds4_tools = pytest.importorskip("pds4_tools")
    source, label = dtms[name]
    structures = pds4_tools.read(str(label.path), quiet=True, lazy_load=True)
    array = np.asarray(structures["image"].data)
    with rasterio.open(source) as original:
        expected = original.read(1)
    valid = expected != -9999.0
    assert array.shape == expected.shape
    assert np.array_equal(array[valid], expected[valid])


def test_dtm_statistics_are_those_of_the_valid_samples(dtms):
    source, label = dtms["equirectangular"]
    with rasterio.open(source) as original:
        values = original.read(1).astype(np.float64)
    values = values[values != -9999.0]
    namespace = {"p": "http://pds.nasa.gov/pds4/pds/v1"}
    stats = etree.fromstring(label.text.encode()).find(".//p:Object_Statistics", namespace)
    stated = {child.tag.split("}")[1]: float(child.text) for child in stats}
    assert np.float32(stated["minimum"]) == values.min() and np.float32(stated["maximum"]) == values.max()
    assert stated["mean"] == pytest.approx(values.mean(), rel=1e-12)
    assert stated["standard_deviation"] == pytest.approx(values.std(), rel=1e-9)


@pytest.fixture(scope="module")
def ortho(tmp_path_factory):
    root = tmp_path_factory.mktemp("pds4_ortho")
    crs, transform = ORIGINS["equirectangular"]
    rng = np.random.default_rng(5)
    data = (rng.random((45, 70)) * 0.2 + 0.05).astype("float32")
    data[0, :4] = np.nan
    source = write_raster(root / "ortho.tif", data, crs, transform)
    label = pds4(write_ortho(source, root / "out", product_id="PSP_008669_1705_RED_C_01_ORTHO", profile="hirise",
                             label="pds4"))
    return source, label


@needs_saxon
def test_hirise_ortho_passes_schema_and_schematron(ortho):
    _, label = ortho
    assert validate_pds4(label.path) == []
    assert "<encoding_standard_id>JP2</encoding_standard_id>" in label.text
    assert "urn:nasa:pds:context:instrument:hirise.mro" in label.text  # as PDS registers it


def test_ortho_primary_array_equals_the_jp2_and_keeps_the_grid(ortho):
    source, label = ortho
    jp2 = label.product.jp2_path
    with rasterio.open(label.path) as primary, rasterio.open(jp2) as encoded, rasterio.open(source) as original:
        assert primary.transform == original.transform and primary.crs == original.crs
        assert encoded.transform == original.transform
        dns = primary.read(1)
        assert np.array_equal(dns, encoded.read(1))
        assert primary.nodata == 0 and (dns[0, :4] == 0).all() and dns[1:].min() >= 3


def test_three_band_ortho_is_an_array_3d_image_gdal_reads_band_by_band(tmp_path):
    crs, transform = ORIGINS["polar"]
    data = np.random.default_rng(8).integers(3, 1000, (3, 30, 41)).astype("uint16")
    source = write_raster(tmp_path / "irb.tif", data, crs, transform)
    label = pds4(write_ortho(source, tmp_path / "out", product_id="PSP_008669_1705_IRB_C_01_ORTHO",
                             profile="hirise", bits=10, label="pds4"))
    assert validate_pds4(label.path) == []
    assert "<Array_3D_Image>" in label.text and "<axis_name>Band</axis_name>" in label.text
    with rasterio.open(label.path) as primary, rasterio.open(label.product.jp2_path) as encoded:
        assert primary.count == 3 and primary.crs == encoded.crs
        assert np.array_equal(primary.read(), data) and np.array_equal(encoded.read(), data)


def test_label_both_describes_the_pds3_image_without_a_second_copy(tmp_path):
    crs, transform = ORIGINS["sinusoidal"]
    data = elevation_array(21, 34, seed=4)
    source = write_raster(tmp_path / "both.tif", data, crs, transform)
    product = write_dtm(source, tmp_path / "out", product_id="BOTH_DTM", label="both", params=stated_keywords())
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["BOTH_DTM.IMG", "BOTH_DTM.xml"]
    assert validate_pds4(product.pds4_label_path) == []
    text = product.pds4_label_path.read_text()
    assert f'<offset unit="byte">{product.records.label_bytes}</offset>' in text
    assert "<parsing_standard_id>PDS3</parsing_standard_id>" in text
    with rasterio.open(product.pds4_label_path) as pds4_view, rasterio.open(product.path) as pds3_view:
        assert pds4_view.driver == "PDS4" and pds3_view.driver == "PDS"
        assert pds4_view.transform == pds3_view.transform and pds4_view.crs == pds3_view.crs
        assert np.array_equal(pds4_view.read(1), data)
    report = validate_paths([tmp_path / "out"], strict=True)
    problems = [f for f in report.findings if f.severity != "info" and f.rule != "PDS4-007"]  # 007: no Saxon
    assert problems == [], [f.message for f in problems]


def test_ortho_label_both_writes_lbl_and_pds4_form(tmp_path):
    crs, transform = ORIGINS["equirectangular"]
    data = np.random.default_rng(6).integers(3, 1000, (16, 23)).astype("uint16")
    source = write_raster(tmp_path / "o.tif", data, crs, transform)
    product = write_ortho(source, tmp_path / "out", product_id="BOTH_ORTHO", bits=10, label="both",
                          params=stated_keywords())
    assert sorted(p.name for p in product.files) == ["BOTH_ORTHO.JP2", "BOTH_ORTHO.LBL", "BOTH_ORTHO.img",
                                                    "BOTH_ORTHO.xml"]
    assert validate_pds4(product.pds4_label_path) == []
    with rasterio.open(product.pds4_label_path) as primary:
        assert np.array_equal(primary.read(1), data)


def test_label_option_is_refused_where_the_profile_has_its_own_form(tmp_path):
    crs, transform = ORIGINS["sinusoidal"]
    source = write_raster(tmp_path / "h.tif", elevation_array(8, 8), crs, transform)
    result = run_cli("dtm", source, "-o", tmp_path / "out", "--profile", "imars", "--product-id", "h1234_0000",
                     "--label", "pds4")
    assert result.returncode == 2 and "--label" in result.stderr
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())



def test_labels_are_formatted_as_xmllint_formats_them(dtms, ortho):
    """libxml2's own indentation (what `xmllint --format` writes), UTF-8, a final newline."""
    for label in [*(written for _, written in dtms.values()), ortho[1]]:
        data = label.path.read_bytes()
        tree = etree.fromstring(data, etree.XMLParser(remove_blank_text=True)).getroottree()
        formatted = etree.tostring(tree, pretty_print=True, encoding="UTF-8", xml_declaration=False)
        declaration, _, body = data.partition(b"?>\n")
        assert declaration == b'<?xml version="1.0" encoding="UTF-8"'
        assert body.split(b"<Product_Observational", 1)[1] == formatted.split(b"<Product_Observational", 1)[1]


def test_pds4_products_are_byte_for_byte_reproducible(dtms, tmp_path):
    source, first = dtms["sinusoidal"]
    again = write_dtm(source, tmp_path, product_id="DTM_SINUSOIDAL", label="pds4", params=stated_keywords())
    assert again.pds4_label_path.read_bytes() == first.path.read_bytes()
    assert again.path.read_bytes() == first.path.with_suffix(".img").read_bytes()



HRSC_SINUSOIDAL = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"


def _headers(label_path):
    tree = etree.parse(str(label_path))
    ns = {"pds": "http://pds.nasa.gov/pds4/pds/v1"}
    return [(h.findtext("pds:parsing_standard_id", namespaces=ns), int(h.findtext("pds:offset", namespaces=ns)),
             int(h.findtext("pds:object_length", namespaces=ns))) for h in tree.iterfind(".//pds:Header", ns)]


def test_hrsc_dtm_label_both_describes_the_headed_int16_image(tmp_path):
    """The HRSC .img is PDS3 label, VICAR label, then MSB int16 DNs: two Headers and the scaled array."""
    from affine import Affine

    data = elevation_array(30, 40, seed=12)
    source = write_raster(tmp_path / "h.tif", data, HRSC_SINUSOIDAL, Affine(50, 0, 100000, 0, -50, 300000))
    product = write_dtm(source, tmp_path / "out", profile="hrsc", product_id="h1234_0000", precision=0.5,
                        label="both")
    assert product.pds4_label_path.name == "h1234_0000_dt4.xml" and product.pds4_label_path in product.files
    assert validate_pds4(product.pds4_label_path) == []
    text = product.pds4_label_path.read_text()
    assert "urn:esa:psa:mex_hrsc:data_dtm:h1234_0000_dt4" in text and "<data_type>SignedMSB2</data_type>" in text
    (pds3, zero, pds3_length), (vicar, vicar_offset, vicar_length) = _headers(product.pds4_label_path)
    raw = product.path.read_bytes()
    assert (pds3, zero, vicar, vicar_offset) == ("PDS3", 0, "VICAR2", pds3_length)
    assert raw[:14] == b"PDS_VERSION_ID" and raw[vicar_offset:vicar_offset + 7] == b"LBLSIZE"
    assert f'<offset unit="byte">{vicar_offset + vicar_length}</offset>' in text
    with rasterio.open(product.pds4_label_path) as pds4_view, rasterio.open(product.path) as pds3_view:
        assert pds4_view.driver == "PDS4" and pds4_view.scales == (0.5,) and pds4_view.nodata == -32768
        assert np.array_equal(pds4_view.read(1), pds3_view.read(1))
        heights = pds4_view.read(1) * 0.5 + pds4_view.offsets[0]
        assert np.abs(heights - data).max() <= 0.25 + 1e-3
        assert pds4_view.transform.almost_equals(pds3_view.transform)
    import pds4_tools  # an independent PDS4 reader: the scaled heights through both Headers

    structures = pds4_tools.read(str(product.pds4_label_path), quiet=True)
    assert [s.id for s in structures] == ["pds3_label", "vicar_label", "image"]
    assert np.abs(np.asarray(structures["image"].data) - data).max() <= 0.25 + 1e-3
    report = validate_paths([tmp_path / "out"], strict=True)
    problems = [f for f in report.findings if f.severity == "error"]
    assert problems == [], [f.message for f in problems]


def test_hrsc_nd4_label_both_and_pds4_alone_refused(tmp_path):
    from affine import Affine

    data = np.random.default_rng(13).integers(1, 256, (20, 30)).astype("uint8")
    data[0, :3] = 0
    source = write_raster(tmp_path / "n.tif", data, HRSC_SINUSOIDAL, Affine(12.5, 0, 100000, 0, -12.5, 300000))
    product = write_ortho(source, tmp_path / "out", profile="hrsc", product_id="h1234_0000", label="both")
    assert product.pds4_label_path.name == "h1234_0000_nd4.xml"
    assert validate_pds4(product.pds4_label_path) == []
    assert [kind for kind, _, _ in _headers(product.pds4_label_path)] == ["PDS3", "VICAR2"]
    with rasterio.open(product.pds4_label_path) as pds4_view:
        assert pds4_view.nodata == 0 and np.array_equal(pds4_view.read(1), data)
    shown = run_cli("ortho", source, "-o", tmp_path / "cli", "--profile", "hrsc", "--product-id", "h1234_0000",
                    "--label", "both")
    assert shown.returncode == 0, shown.stderr
    assert "h1234_0000_nd4.xml" in shown.stdout and (tmp_path / "cli" / "h1234_0000_nd4.xml").is_file()
    refused = run_cli("dtm", source, "-o", tmp_path / "again", "--profile", "hrsc", "--product-id", "h1234_0000",
                      "--label", "pds4")
    assert refused.returncode == 2 and "--label both" in refused.stderr
    assert not (tmp_path / "again").exists() or not any((tmp_path / "again").iterdir())
