"""`pdsgen migrate` on genuine PDS3 products with their data (tests/data/corpus/products).

References from outside pdsgen: the copies' MD5 against the originals (hashlib, not pdsgen's
helper), the shipped XSD with lxml and Schematron with Saxon, pds4_tools reading each
migrated array or table against pdr's and GDAL's reading of the PDS3 product, and GDAL's
placement of the PDS3 grid (its PDS driver) against the cart: corners.
"""

from __future__ import annotations

import hashlib
import shutil
import struct
from pathlib import Path

import numpy as np
import pytest
import rasterio
from lxml import etree

from conftest import CORPUS_DIR
from pdsgen.migrate import MigratedProduct, Refused, migrate_product
from pdsgen.migrate.mapping import KEYWORD_TABLE
from pdsgen.validate import validate_paths
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.label_checks import validate_pds4

from helpers import UNNAMED, assert_pds4_clean, run_cli

PRODUCTS = CORPUS_DIR / "products"
needs_saxon = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")
NS = {"pds": "http://pds.nasa.gov/pds4/pds/v1", "cart": "http://pds.nasa.gov/pds4/cart/v1"}

# name -> (PDS3 label, pdr's key of the array, GDAL config that reads the grid as the validator decides)
GENUINE = {
    "mola_megdr": (PRODUCTS / "MOLA_MEGDR_megt90n000cb" / "megt90n000cb.lbl", "IMAGE",
                   # the validator finds MEGDR's offsets one pixel apart (MAP-005); GDAL reads such
                   # labels with these options (pds3-products.md section 4)
                   {"PDS_SampleProjOffset_Shift": "-0.5", "PDS_LineProjOffset_Shift": "-0.5"}),
    "magellan_fmidr": (PRODUCTS / "MGN_FMIDR_FF01" / "FF01.LBL", "IMAGE", None),
    "crism_mrdr": (PRODUCTS / "CRISM_MRDR_t1865_cropped" / "t1865_mrrde_70n185_0256_1_cropped.lbl", "IMAGE", {}),
    "pathfinder_imp": (PRODUCTS / "MPF_IMP_i985135l" / "i985135l.img", "IMAGE", None),
}


def md5(path: Path) -> str:
    return hashlib.md5(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def migrated(tmp_path_factory) -> dict[str, MigratedProduct]:
    out = tmp_path_factory.mktemp("migrated")
    return {name: migrate_product(label, out / name, bundle_lid="urn:nasa:pds:pdsgen_migrate_test")
            for name, (label, _, _) in GENUINE.items()}


@pytest.mark.parametrize("name", sorted(GENUINE))
def test_data_files_are_copied_byte_for_byte(migrated, name):
    label = GENUINE[name][0]
    product = migrated[name]
    assert product.files
    for copy in product.files:
        original = next(p for p in label.parent.iterdir() if p.name == copy.name)
        assert md5(copy) == md5(original)
    text = product.label_path.read_text()
    for copy in product.files:  # the label states each file's size and MD5 as they are
        assert f"<file_name>{copy.name}</file_name>" in text and md5(copy) in text
        assert f'<file_size unit="byte">{copy.stat().st_size}</file_size>' in text


@needs_saxon
@pytest.mark.parametrize("name", sorted(GENUINE))
def test_labels_pass_the_shipped_schema_schematron_and_pdsgen_validate(migrated, name):
    product = migrated[name]
    assert validate_pds4(product.label_path) == []
    report = validate_paths([product.label_path])
    assert [f for f in report.findings if f.severity in ("error", "warning")] == []


@pytest.mark.parametrize("name", sorted(GENUINE))
def test_identification_keeps_the_pds3_ids(migrated, name):
    product = migrated[name]
    root = etree.parse(str(product.label_path)).getroot()
    lid = root.findtext("pds:Identification_Area/pds:logical_identifier", namespaces=NS)
    assert lid == product.lid and lid.startswith("urn:nasa:pds:pdsgen_migrate_test:data:")
    aliases = root.findall(".//pds:Alias_List/pds:Alias", NS)
    comments = {a.findtext("pds:comment", namespaces=NS): a.findtext("pds:alternate_id", namespaces=NS)
                for a in aliases}
    assert comments.get("PDS3 PRODUCT_ID", comments.get("PDS3 IMAGE_ID")) == product.product_id
    assert "PDS3 DATA_SET_ID" in comments


@pytest.mark.parametrize("name", sorted(GENUINE))
def test_source_product_id_becomes_source_product_external(migrated, name):
    """Pathfinder's EDR names its source (SOURCE_PRODUCT_ID = "SEQ_S0154C_IMPEK"); the others none."""
    root = etree.parse(str(migrated[name].label_path)).getroot()
    named = root.xpath("pds:Reference_List/pds:Source_Product_External/pds:external_source_product_identifier/text()",
                       namespaces=NS)
    assert named == (["SEQ_S0154C_IMPEK"] if name == "pathfinder_imp" else [])


@pytest.mark.parametrize("name", sorted(GENUINE))
def test_pds4_tools_reads_the_array_pdr_and_gdal_read_from_the_pds3_product(migrated, name):
    pds4_tools = pytest.importorskip("pds4_tools")
    import pdr

    label, key, _ = GENUINE[name]
    structures = pds4_tools.read(str(migrated[name].label_path), quiet=True, lazy_load=True)
    array = np.asarray(structures["image"].data)
    if name != "crism_mrdr":  # pdr 1.x cannot load this MRDR's IMAGE ('NoneType' ... 'get'): GDAL only
        expected = np.asarray(pdr.read(str(label))[key])
        assert array.shape == expected.shape and np.array_equal(array, expected)
    if name == "crism_mrdr":  # GDAL too refuses the cropped MRDR (FILE_RECORDS 9 for 10 lines): the
        # samples as the PDS3 label defines them (PC_REAL, 10 x 980, from byte 0) with numpy
        expected = np.fromfile(label.with_suffix(".img"), dtype="<f4").reshape(10, 980)
        assert np.array_equal(array, expected)
        return
    with rasterio.open(label) as pds3:
        assert np.array_equal(array, pds3.read(1) if pds3.count == 1 else pds3.read())


def _corners(transform, width: int, height: int) -> np.ndarray:
    return np.array([transform @ (c, r) for c, r in ((0, 0), (width, 0), (0, height), (width, height))])


@pytest.mark.parametrize("name", ["mola_megdr", "crism_mrdr"])
def test_cart_corners_are_where_gdal_places_the_pds3_grid(migrated, name):
    label, _, config = GENUINE[name]
    root = etree.parse(str(migrated[name].label_path)).getroot()
    x0 = float(root.findtext(".//cart:upperleft_corner_x", namespaces=NS))
    y0 = float(root.findtext(".//cart:upperleft_corner_y", namespaces=NS))
    size = float(root.findtext(".//cart:pixel_resolution_x", namespaces=NS))
    with rasterio.Env(**config), rasterio.open(label) as pds3:
        expected = _corners(pds3.transform, pds3.width, pds3.height)
        width, height = pds3.width, pds3.height
    stated = _corners(rasterio.Affine(size, 0, x0, 0, -size, y0), width, height)
    assert np.abs(stated - expected).max() < 0.01  # metres
    with rasterio.open(migrated[name].label_path) as pds4:  # GDAL's PDS4 driver reads the cart: grid
        assert np.abs(_corners(pds4.transform, width, height) - expected).max() < 0.01


def test_attached_label_is_a_header_and_the_image_follows_it(migrated):
    root = etree.parse(str(migrated["pathfinder_imp"].label_path)).getroot()
    header = root.find(".//pds:File_Area_Observational/pds:Header", NS)
    assert header.findtext("pds:parsing_standard_id", namespaces=NS) == "PDS3"
    assert header.findtext("pds:offset", namespaces=NS) == "0"
    assert header.findtext("pds:object_length", namespaces=NS) == str(116 * 96)  # LABEL_RECORDS x RECORD_BYTES
    image = root.find(".//pds:Array_2D_Image", NS)
    assert image.findtext("pds:offset", namespaces=NS) == str(116 * 96)  # ^IMAGE = 117
    assert image.findtext("pds:Element_Array/pds:data_type", namespaces=NS) == "UnsignedMSB2"


def test_detached_label_and_vicar_header_are_described(migrated):
    root = etree.parse(str(migrated["magellan_fmidr"].label_path)).getroot()
    headers = root.findall(".//pds:File_Area_Observational/pds:Header", NS)
    assert [h.findtext("pds:parsing_standard_id", namespaces=NS) for h in headers] == ["VICAR2"]
    supplemental = root.find(".//pds:File_Area_Observational_Supplemental", NS)
    assert supplemental.findtext("pds:File/pds:file_name", namespaces=NS) == "FF01.LBL"
    assert supplemental.findtext("pds:Header/pds:parsing_standard_id", namespaces=NS) == "PDS3"


def test_magellan_cart_grid_puts_pixel_centres_on_the_label_bounds(migrated):
    """FF01.LBL states its pixel-centre bounds (the data set's DSMAPF.LBL: integral lines and samples
    are pixel centres): latitudes -18.1813 .. -17.4548, longitudes 141.6269 .. 142.4009. The cart:
    grid, evaluated with PROJ from its own values alone, puts the extreme pixel centres there to
    half a pixel. (Read with the label's A_AXIS_RADIUS 6051.92 km instead of the 6051.0 km sphere
    of the catalog's SCALE equation, the latitudes were 3.4 and 3.6 px off; geo/magellan.py.)"""
    from rasterio.crs import CRS
    from rasterio.warp import transform as warp_transform

    root = etree.parse(str(migrated["magellan_fmidr"].label_path)).getroot()

    def number(name: str) -> float:
        return float(root.findtext(f".//cart:{name}", namespaces=NS))

    radius, size = number("a_axis_radius"), number("pixel_resolution_x")
    lon0 = number("longitude_of_central_meridian")
    crs = CRS.from_proj4(f"+proj=sinu +lon_0={lon0} +R={radius} +units=m +no_defs")
    centres = np.arange(1024) + 0.5
    cols, rows = np.meshgrid(centres, centres)
    xs = number("upperleft_corner_x") + cols.ravel() * size
    ys = number("upperleft_corner_y") - rows.ravel() * size
    lon, lat = (np.asarray(v) for v in warp_transform(crs, CRS.from_proj4(f"+proj=longlat +R={radius}"),
                                                      xs.tolist(), ys.tolist()))
    px_per_deg = np.pi * radius / 180.0 / size
    cos_lat = np.cos(np.radians(17.8))
    residuals = [(lat.min() + 18.1813) * px_per_deg, (lat.max() + 17.4548) * px_per_deg,
                 (lon.min() % 360 - 141.6269) * px_per_deg * cos_lat,
                 (lon.max() % 360 - 142.4009) * px_per_deg * cos_lat]
    assert max(abs(r) for r in residuals) < 0.5, residuals


# -- tables: written here by the PDS3 Standards' definition of TABLE and ^STRUCTURE ---------------

def _binary_table(directory: Path) -> tuple[Path, list[tuple[float, int, bytes, list[int]]]]:
    """A detached binary TABLE of MSB columns, its COLUMNs in a ^STRUCTURE format file, one
    column of ITEMS, and a 2-byte row suffix (RECORD_BYTES = ROW_BYTES + ROW_SUFFIX_BYTES)."""
    rows = [(1.5, -7, b"AB", [1, 2, 3]), (-2.25, 40000, b"CD", [65535, 0, 9])]
    data = b"".join(struct.pack(">di2s3H", r, i, s, *items) + b"\0\0" for r, i, s, items in rows)
    (directory / "ROWS.DAT").write_bytes(data)
    (directory / "ROWS.FMT").write_text(
        "OBJECT = COLUMN\r\n NAME = VALUE\r\n DATA_TYPE = IEEE_REAL\r\n START_BYTE = 1\r\n BYTES = 8\r\n"
        " UNIT = KM\r\nEND_OBJECT = COLUMN\r\n"
        "OBJECT = COLUMN\r\n NAME = COUNT\r\n DATA_TYPE = MSB_INTEGER\r\n START_BYTE = 9\r\n BYTES = 4\r\n"
        " MISSING_CONSTANT = -999\r\nEND_OBJECT = COLUMN\r\n", newline="")
    label = directory / "ROWS.LBL"
    label.write_text(
        "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 22\r\nFILE_RECORDS = 2\r\n"
        '^TABLE = "ROWS.DAT"\r\nPRODUCT_ID = "ROWS_1"\r\nDATA_SET_ID = "X-X-TEST-2-EDR-V1.0"\r\n'
        "TARGET_NAME = MARS\r\nSTART_TIME = 2004-017T12:00:00.5\r\n"
        "OBJECT = TABLE\r\n INTERCHANGE_FORMAT = BINARY\r\n ROWS = 2\r\n COLUMNS = 4\r\n ROW_BYTES = 20\r\n"
        ' ROW_SUFFIX_BYTES = 2\r\n ^STRUCTURE = "ROWS.FMT"\r\n'
        " OBJECT = COLUMN\r\n  NAME = CODE\r\n  DATA_TYPE = CHARACTER\r\n  START_BYTE = 13\r\n  BYTES = 2\r\n"
        " END_OBJECT = COLUMN\r\n"
        " OBJECT = COLUMN\r\n  NAME = COUNTS\r\n  DATA_TYPE = MSB_UNSIGNED_INTEGER\r\n  START_BYTE = 15\r\n"
        "  BYTES = 6\r\n  ITEMS = 3\r\n  ITEM_BYTES = 2\r\n END_OBJECT = COLUMN\r\n"
        "END_OBJECT = TABLE\r\nEND\r\n", newline="")
    return label, rows


def _ascii_table(directory: Path) -> Path:
    records = ['  1.250,   12,"ALPHA"', ' -3.500,    7,"BETA "']
    (directory / "SPOTS.TAB").write_bytes(b"".join(r.encode() + b"\r\n" for r in records))
    label = directory / "SPOTS.LBL"
    label.write_text(
        "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 23\r\nFILE_RECORDS = 2\r\n"
        '^SPOT_TABLE = "SPOTS.TAB"\r\nPRODUCT_ID = "SPOTS_1"\r\nTARGET_NAME = MOON\r\n'
        "OBJECT = SPOT_TABLE\r\n INTERCHANGE_FORMAT = ASCII\r\n ROWS = 2\r\n COLUMNS = 3\r\n ROW_BYTES = 23\r\n"
        " OBJECT = COLUMN\r\n  NAME = SIZE\r\n  DATA_TYPE = ASCII_REAL\r\n  START_BYTE = 1\r\n  BYTES = 7\r\n"
        " END_OBJECT = COLUMN\r\n"
        " OBJECT = COLUMN\r\n  NAME = N\r\n  DATA_TYPE = ASCII_INTEGER\r\n  START_BYTE = 9\r\n  BYTES = 5\r\n"
        " END_OBJECT = COLUMN\r\n"
        " OBJECT = COLUMN\r\n  NAME = LABEL\r\n  DATA_TYPE = CHARACTER\r\n  START_BYTE = 16\r\n  BYTES = 5\r\n"
        " END_OBJECT = COLUMN\r\nEND_OBJECT = SPOT_TABLE\r\nEND\r\n", newline="")
    return label


@needs_saxon
def test_binary_table_with_structure_file_items_and_suffix(tmp_path):
    pds4_tools = pytest.importorskip("pds4_tools")
    import pdr

    source = tmp_path / "src"
    source.mkdir()
    label, rows = _binary_table(source)
    product = migrate_product(label, tmp_path / "out", bundle_lid="urn:nasa:pds:test")
    assert_pds4_clean(product.label_path, ("Observing_System_Component",))
    assert [f for f in validate_paths([product.label_path]).findings if f.severity == "error"] == []
    table = pds4_tools.read(str(product.label_path), quiet=True)["table"]
    assert list(table["VALUE"]) == [r for r, _, _, _ in rows]
    assert list(table["COUNT"]) == [i for _, i, _, _ in rows]
    assert [str(s) for s in table["CODE"]] == [s.decode() for _, _, s, _ in rows]
    assert np.asarray(table["COUNTS"]).tolist() == [items for _, _, _, items in rows]
    # pdr reads the PDS3 table's ^STRUCTURE columns the same, but steps ROW_BYTES (20), not the
    # record with its ROW_SUFFIX_BYTES (22): its first row is the reference here
    reference = pdr.read(str(label))["TABLE"]
    assert (reference["VALUE"][0], reference["COUNT"][0]) == (table["VALUE"][0], table["COUNT"][0])
    text = product.label_path.read_text()
    assert "<missing_constant>-999</missing_constant>" in text and "<unit>KM</unit>" in text
    assert "<start_date_time>2004-01-17T12:00:00.5Z</start_date_time>" in text  # day of year 017
    assert md5(tmp_path / "out" / "ROWS.DAT") == md5(source / "ROWS.DAT")


@needs_saxon
def test_ascii_table_as_table_character(tmp_path):
    pds4_tools = pytest.importorskip("pds4_tools")
    import pdr

    source = tmp_path / "src"
    source.mkdir()
    product = migrate_product(_ascii_table(source), tmp_path / "out", bundle_lid="urn:nasa:pds:test")
    assert_pds4_clean(product.label_path, ("Observing_System_Component",))
    assert "<record_delimiter>Carriage-Return Line-Feed</record_delimiter>" in product.label_path.read_text()
    table = pds4_tools.read(str(product.label_path), quiet=True)["spot_table"]
    reference = pdr.read(str(source / "SPOTS.LBL"))["SPOT_TABLE"]
    assert list(table["SIZE"]) == list(reference["SIZE"]) == [1.25, -3.5]
    assert list(table["N"]) == list(reference["N"]) == [12, 7]


# -- refusals --------------------------------------------------------------------------------------

def _vax_product(directory: Path) -> Path:
    """The Pathfinder product with its SAMPLE_TYPE made VAX_REAL (32 bits): PDS4 has no VAX float."""
    data = (PRODUCTS / "MPF_IMP_i985135l" / "i985135l.img").read_bytes()
    data = data.replace(b"MSB_UNSIGNED_INTEGER", b"VAX_REAL            ", 1)
    data = data.replace(b"SAMPLE_BITS                  = 16", b"SAMPLE_BITS                  = 32", 1)
    path = directory / "vax.img"
    path.write_bytes(data)
    return path


def _line_prefix_product(directory: Path, storage: str = "BAND_SEQUENTIAL") -> tuple[Path, np.ndarray]:
    """An attached-label image of 2 bands x 5 lines x 6 MSB 16-bit samples, each line after a
    4-byte prefix (as HiRISE EDRs carry), written by the PDS3 definition of records."""
    rng = np.random.default_rng(5)
    image = rng.integers(-3000, 3000, (2, 5, 6)).astype(">i2")
    lines = b"".join(struct.pack(">I", 1000 + n) + image[b, line].tobytes()
                     for n, (b, line) in enumerate((b, line) for b in range(2) for line in range(5)))
    record = 4 + 12
    text = ("PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 16\r\n"
            "FILE_RECORDS = 40\r\nLABEL_RECORDS = 30\r\n^IMAGE = 31\r\nPRODUCT_ID = PREFIXED\r\n"
            "OBJECT = IMAGE\r\n LINES = 5\r\n LINE_SAMPLES = 6\r\n BANDS = 2\r\n"
            f" BAND_STORAGE_TYPE = {storage}\r\n SAMPLE_TYPE = MSB_INTEGER\r\n SAMPLE_BITS = 16\r\n"
            " LINE_PREFIX_BYTES = 4\r\n MISSING_CONSTANT = -32768\r\nEND_OBJECT = IMAGE\r\nEND\r\n")
    header = text.encode().ljust(30 * record)
    path = directory / f"prefix_{storage.lower()}.img"
    path.write_bytes(header + lines)
    return path, image


def test_refusals_are_one_line_each_others_go_on_and_nothing_is_written_for_them(tmp_path):
    bad = tmp_path / "bad"
    bad.mkdir()
    shutil.copy(PRODUCTS / "MGN_FMIDR_FF01" / "FF01.LBL", bad)  # its FF01.IMG left behind
    refused = {
        "VAX_REAL": _vax_product(bad),
        "LINE_INTERLEAVED bands are not described": _line_prefix_product(bad, "LINE_INTERLEAVED")[0],
        "FF01.IMG is missing": bad / "FF01.LBL",
        "truncated": PRODUCTS / "synthetic_pds3_1band" / "pds3_1band.IMG",  # 712 of 840 bytes
        # ISIS's exported table label: no PDS_VERSION_ID, no END
        "no END statement": CORPUS_DIR / "tables" / "ISIS_binary_tables" / "msb_pds_binary_table.lbl",
    }
    good = PRODUCTS / "MPF_IMP_i985135l" / "i985135l.img"
    out = tmp_path / "out"
    result = run_cli("migrate", *refused.values(), good, "-o", out, "--bundle-lid", "urn:nasa:pds:test")
    assert result.returncode == 2
    errors = result.stderr.strip().splitlines()
    assert len(errors) == len(refused) and "Traceback" not in result.stderr
    for (what, path), line in zip(refused.items(), errors, strict=True):
        assert line.startswith(f"pdsgen: error: {path}") and what in line
    assert sorted(p.name for p in out.iterdir()) == ["i985135l.img", "i985135l.xml"]


@needs_saxon
def test_image_lines_with_prefixes_are_described_exactly_as_table_records(tmp_path):
    pds4_tools = pytest.importorskip("pds4_tools")

    path, image = _line_prefix_product(tmp_path)
    product = migrate_product(path, tmp_path / "out", bundle_lid="urn:nasa:pds:test")
    assert_pds4_clean(product.label_path, UNNAMED)
    assert [f for f in validate_paths([product.label_path]).findings if f.severity == "error"] == []
    table = pds4_tools.read(str(product.label_path), quiet=True)["image"]
    samples = np.asarray(table["SAMPLES"]).reshape(2, 5, 6)
    assert np.array_equal(samples, image)
    prefixes = np.asarray(table["LINE_PREFIX"]).astype(np.uint8)
    assert [int.from_bytes(bytes(p), "big") for p in prefixes] == list(range(1000, 1010))
    with rasterio.open(path) as pds3:  # GDAL's PDS driver skips the prefixes too
        assert np.array_equal(pds3.read(), image)


@needs_saxon
@pytest.mark.parametrize(("storage", "order"), [("BAND_SEQUENTIAL", (0, 1, 2)), ("LINE_INTERLEAVED", (1, 0, 2)),
                                                ("SAMPLE_INTERLEAVED", (1, 2, 0))])
def test_band_storage_is_the_axis_order(tmp_path, storage, order):
    """A 3-band detached product written by the PDS3 definition of each storage; pds4_tools's
    array, axes in the label's order, against GDAL's reading of the PDS3 product."""
    pds4_tools = pytest.importorskip("pds4_tools")
    cube = np.arange(3 * 4 * 5, dtype="<i2").reshape(3, 4, 5) * 7 - 200  # band, line, sample
    (tmp_path / "CUBE.IMG").write_bytes(np.ascontiguousarray(cube.transpose(order)).tobytes())
    (tmp_path / "CUBE.LBL").write_text(
        "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = UNDEFINED\r\n^IMAGE = \"CUBE.IMG\"\r\nPRODUCT_ID = CUBE\r\n"
        "OBJECT = IMAGE\r\n LINES = 4\r\n LINE_SAMPLES = 5\r\n BANDS = 3\r\n"
        f" BAND_STORAGE_TYPE = {storage}\r\n SAMPLE_TYPE = LSB_INTEGER\r\n SAMPLE_BITS = 16\r\n"
        " SCALING_FACTOR = 0.5\r\n OFFSET = 10.0\r\nEND_OBJECT = IMAGE\r\nEND\r\n", newline="")
    product = migrate_product(tmp_path / "CUBE.LBL", tmp_path / "out", bundle_lid="urn:nasa:pds:test")
    assert_pds4_clean(product.label_path, UNNAMED)
    array = np.asarray(pds4_tools.read(str(product.label_path), quiet=True, lazy_load=True)["image"].data)
    physical = array.transpose(np.argsort(order))  # pds4_tools applies scaling_factor and value_offset
    assert np.array_equal(physical, cube * 0.5 + 10.0)
    if storage != "SAMPLE_INTERLEAVED":  # GDAL 3.6's PDS driver reads a SAMPLE_INTERLEAVED IMAGE as bands
        with rasterio.open(tmp_path / "CUBE.LBL") as pds3:
            assert np.array_equal(physical, pds3.read() * 0.5 + 10.0)
    text = product.label_path.read_text()
    assert "<scaling_factor>0.5</scaling_factor>" in text and "<value_offset>10.0</value_offset>" in text


def test_refused_product_raises_refused_and_writes_nothing(tmp_path):
    with pytest.raises(Refused, match="VAX_REAL"):
        migrate_product(_vax_product(tmp_path), tmp_path / "out")
    assert not (tmp_path / "out").exists() or list((tmp_path / "out").iterdir()) == []


def test_in_place_writes_only_the_label(tmp_path):
    source = tmp_path / "p"
    shutil.copytree(PRODUCTS / "CRISM_MRDR_t1865_cropped", source)
    before = sorted(p.name for p in source.iterdir())
    result = run_cli("migrate", source / "t1865_mrrde_70n185_0256_1_cropped.img", "--in-place")
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in source.iterdir()) == sorted(before + ["t1865_mrrde_70n185_0256_1_cropped.xml"])


def test_readme_mapping_table_is_the_codes():
    import docs_text
    readme = docs_text.all_text()
    for keyword, pds4 in KEYWORD_TABLE:
        assert f"| {keyword} | {pds4} |" in readme


def test_a_lid_made_from_the_file_name_is_said(tmp_path):
    """A label stating neither PRODUCT_ID nor IMAGE_ID gets a LID from its file's name - an
    identifier its producer never gave, so migrate says so (issue 49); one stating it does not."""
    source = tmp_path / "src"
    source.mkdir()
    stated = _ascii_table(source)
    unnamed = source / "UNNAMED.LBL"
    unnamed.write_bytes(stated.read_bytes().replace(b'PRODUCT_ID = "SPOTS_1"\r\n', b""))
    quiet = migrate_product(stated, tmp_path / "a", bundle_lid="urn:nasa:pds:test")
    said = migrate_product(unnamed, tmp_path / "b", bundle_lid="urn:nasa:pds:test")
    assert not any("file's name" in warning for warning in quiet.warnings)
    assert [w for w in said.warnings if "file's name" in w] == [
        f"{unnamed}: states no PRODUCT_ID or IMAGE_ID: its LID urn:nasa:pds:test:data:unnamed is made from "
        "the file's name"]
    assert etree.parse(str(said.label_path)).findtext(".//{*}Identification_Area/{*}logical_identifier") == \
        "urn:nasa:pds:test:data:unnamed"
