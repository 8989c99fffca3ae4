"""A delivery's parts agree with each other, whatever they are named: seeded into pdsgen's own
deliveries (PDS3, PDS4, both), each inconsistency is caught by a finding naming the file, and the
clean deliveries pass --strict with no finding of these rules.

NASA's validate reports a file of a bundle that no label describes as a warning
(NASA-PDS/validate src/main/java/gov/nasa/pds/tools/validate/ProblemType.java @ 0572d9ad:
UNLABELED_FILE "warning.file.not_referenced_in_label"): DLV-016 has that severity.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from pdsgen.deliver import make_delivery
from pdsgen.errors import InputError
from pdsgen.extras import make_extras
from pdsgen.products.dtm import write_dtm
from pdsgen.review.collect import delivery_checks
from pdsgen.synthetic import make_scene, write_geotiff
from pdsgen.validate import validate_paths

from helpers import demo_products

PDS_NS = {"pds": "http://pds.nasa.gov/pds4/pds/v1"}
BUNDLE_LID = "urn:nasa:pds:demo_dtm"
# The rules of this issue: a clean delivery has none of them (the demo's UNK texts are DLV-007's).
CONSISTENCY = ("DLV-011", "DLV-016", "DLV-017", "DLV-018", "DLV-019", "DLV-025", "DLV-026", "DLV-027", "DLV-028",
               "DLV-029", "IDN-001", "IDN-002", "IDN-003", "IDN-004", "IDN-012", "IDN-013")


@pytest.fixture(scope="module")
def products(tmp_path_factory) -> Path:
    """A DTM and an orthoimage made on it (PDS3 and PDS4 labels), with their Extras."""
    return demo_products(tmp_path_factory.mktemp("consistency"), width=120, height=160)


@pytest.fixture(scope="module")
def made(products, tmp_path_factory) -> dict[str, Path]:
    """One clean delivery of each dialect, made once; tests seed copies of them."""
    root = tmp_path_factory.mktemp("deliveries")
    deliveries = {}
    for dialect in ("pds3", "pds4", "both"):
        deliveries[dialect] = root / dialect
        make_delivery(products, root / dialect, dialect=dialect, volume_id="DEMO_0001" if dialect != "pds4" else None,
                      bundle_lid=BUNDLE_LID if dialect != "pds3" else None)
    return deliveries


def _copy(made: dict[str, Path], dialect: str, tmp_path: Path) -> Path:
    return Path(shutil.copytree(made[dialect], tmp_path / dialect))


def _found(path: Path, *rules: str, labels_only: bool = True) -> list[tuple[str, str, str]]:
    report = validate_paths([path], labels_only=labels_only)
    return sorted((f.rule, f.severity, Path(f.file).name) for f in report.findings if f.rule in rules)


@pytest.mark.parametrize("dialect", ["pds3", "pds4", "both"])
def test_clean_deliveries_have_no_consistency_finding(made, dialect):
    assert _found(made[dialect], *CONSISTENCY, labels_only=False) == []


def test_a_bundle_is_what_its_root_says_whatever_its_name(made, tmp_path):
    """bundle.xml (the common name) with no manifest beside it: still a bundle, its inventories
    checked - a product missing from its inventory is found."""
    bundle = _copy(made, "pds4", tmp_path)
    (bundle / "bundle_demo_dtm.xml").rename(bundle / "bundle.xml")
    for name in ("MD5SUMS.TXT", "MD5SUMS.xml", "REVIEW.html"):
        (bundle / name).unlink()
    shutil.rmtree(bundle / "MISCELLANEOUS")
    text = (bundle / "bundle.xml").read_text()
    start = text.index("<Bundle_Member_Entry>\n    <lidvid_reference>urn:nasa:pds:demo_dtm:miscellaneous")
    end = text.index("</Bundle_Member_Entry>", start) + len("</Bundle_Member_Entry>")
    (bundle / "bundle.xml").write_text(text[:start] + text[end:])
    assert _found(bundle, *CONSISTENCY) == []
    assert ("inventories", "pass") in delivery_checks(bundle, validate_paths([bundle], labels_only=True).findings)
    inventory = bundle / "DATA" / "collection_data_inventory.csv"
    rows = inventory.read_bytes().split(b"\r\n")
    inventory.write_bytes(b"\r\n".join(rows[1:]))
    assert _found(bundle, "DLV-011") == [("DLV-011", "error", "DTEEC_008669_1705_009025_1705_U01.xml")]
    # the review page's summary reviews a bundle.xml's inventories as any bundle label's
    checks = delivery_checks(bundle, validate_paths([bundle], labels_only=True).findings)
    assert ("inventories", "fail: 1 error(s)") in checks


@pytest.mark.parametrize("dialect", ["pds4", "both"])
def test_a_file_no_label_describes_is_named(made, dialect, tmp_path):
    bundle = _copy(made, dialect, tmp_path)
    (bundle / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.JP2.aux.xml").write_text(
        "<PAMDataset><PAMRasterBand band=\"1\"/></PAMDataset>\n")
    found = _found(bundle, "DLV-016")
    assert found == [("DLV-016", "warning", "PSP_008669_1705_RED_C_01_ORTHO.JP2.aux.xml")]


def test_the_manifest_is_a_labelled_product_and_unlabelled_without_its_label(made, tmp_path):
    bundle = _copy(made, "pds4", tmp_path)
    label = etree.parse(str(bundle / "MD5SUMS.xml"))
    assert label.getroot().tag == "{http://pds.nasa.gov/pds4/pds/v1}Product_Ancillary"
    assert label.findtext(".//pds:Checksum_Manifest/pds:parsing_standard_id", namespaces=PDS_NS) == "MD5Deep 4.n"
    inventory = (bundle / "MISCELLANEOUS" / "collection_miscellaneous_inventory.csv").read_bytes().decode()
    assert inventory == "P,urn:nasa:pds:demo_dtm:miscellaneous:md5sums::1.0\r\n"
    (bundle / "MD5SUMS.xml").unlink()
    found = _found(bundle, "DLV-016", "DLV-010")
    assert ("DLV-016", "warning", "MD5SUMS.TXT") in found and ("DLV-010", "error",
                                                               "collection_miscellaneous_inventory.csv") in found


# --- identification: any product, any dialect ----------------------------------------------------

ORTHO = "DATA/PSP_008669_1705_RED_C_01_ORTHO"
DTM_IMG = "DATA/DTEEC_008669_1705_009025_1705_U01.IMG"
NOW = "1767225600"  # SOURCE_DATE_EPOCH: 2026-01-01T00:00:00Z, so no test depends on today's date


def _seed(root: Path, relative: str, old: str, new: str) -> None:
    path = root / relative
    data = path.read_bytes()
    assert old.encode() in data, (relative, old)
    path.write_bytes(data.replace(old.encode(), new.encode(), 1))


def test_a_product_without_product_id_is_found(made, tmp_path):
    volume = _copy(made, "pds3", tmp_path)
    _seed(volume, f"{ORTHO}.LBL", 'PRODUCT_ID                = "PSP_008669_1705_RED_C_01_ORTHO"\r\n', "")
    assert _found(volume, "IDN-001") == [("IDN-001", "warning", "PSP_008669_1705_RED_C_01_ORTHO.LBL")]


def test_unk_identification_is_found_in_a_pds4_label_in_a_bundle_or_alone(made, tmp_path):
    """DLV-008 (DLV-007's PDS4 side) reads every PDS4 label: in a bundle, and one checked alone."""
    assert _found(made["pds4"], "DLV-008") == []  # the demo's PDS4 labels name what they show
    bundle = _copy(made, "pds4", tmp_path)
    _seed(bundle, f"{ORTHO}.xml", "<name>Mars</name>", "<name>UNK</name>")
    assert _found(bundle, "DLV-008") == [("DLV-008", "warning", "PSP_008669_1705_RED_C_01_ORTHO.xml")]
    alone = bundle / f"{ORTHO}.xml"
    assert _found(alone, "DLV-008") == [("DLV-008", "warning", "PSP_008669_1705_RED_C_01_ORTHO.xml")]
    assert validate_paths([alone], labels_only=True, strict=True).failed


def test_a_remade_ortho_with_its_old_jp2info_and_quick_look_is_found(products, tmp_path):
    """The orthoimage remade at another size (--overwrite) and its Extras remade, but the old
    JP2INFO.TXT and the old quick look put back: DLV-025 names JP2INFO.TXT (in the product
    directory and in the delivery), DLV-026 the quick look. The JP2 sizes the findings quote are
    GDAL's (rasterio), not the validator's box walk."""
    from pdsgen.products.ortho import write_ortho

    remade = Path(shutil.copytree(products, tmp_path / "products"))
    name, dtm = Path(ORTHO).name, Path(DTM_IMG).name
    qlook = f"{name}.QLOOK.JP2"
    old_info, old_qlook = (remade / "JP2INFO.TXT").read_bytes(), (remade / "extras" / qlook).read_bytes()
    scene = make_scene(width=100, height=140)
    source = write_geotiff(tmp_path / "ortho.tif", scene.reflectance, scene.transform, scene.crs, None)
    ortho = write_ortho(source, remade, profile="hirise", observation_id="PSP_008669_1705",
                        source_dtm_id=Path(dtm).stem, label="both", overwrite=True)
    make_extras([remade / dtm, ortho.label_path], remade / "extras", overwrite=True)
    consistent = tmp_path / "consistent"
    make_delivery(remade, consistent, dialect="both", volume_id="DEMO_0001", bundle_lid=BUNDLE_LID)
    assert _found(consistent, *CONSISTENCY, labels_only=False) == []  # the consistent remake: clean
    (remade / "JP2INFO.TXT").write_bytes(old_info)
    (remade / "extras" / qlook).write_bytes(old_qlook)
    assert _gdal_size(remade / f"{name}.JP2") == (100, 140) and _gdal_size(remade / "extras" / qlook) == (120, 160)
    assert _found(remade, "DLV-025", labels_only=False) == [("DLV-025", "error", "JP2INFO.TXT")]
    for dialect in ("pds3", "both"):
        delivery = tmp_path / dialect
        make_delivery(remade, delivery, dialect=dialect, volume_id="DEMO_0001",
                      bundle_lid=BUNDLE_LID if dialect == "both" else None)
        assert _found(delivery, "DLV-025", "DLV-026", labels_only=False) == [("DLV-025", "error", "JP2INFO.TXT"),
                                                                             ("DLV-026", "error", qlook)]
        report = validate_paths([delivery], strict=True)
        jp2info = next(f for f in report.findings if f.rule == "DLV-025")
        assert "as 120 samples x 160 lines" in jp2info.message and "JP2 is 100 samples x 140 lines" in jp2info.message


def _gdal_size(path: Path) -> tuple[int, int]:
    """(width, height) of a JP2 as GDAL reads it."""
    import rasterio

    with rasterio.open(path) as dataset:
        return dataset.width, dataset.height


@pytest.mark.parametrize("dialect", ["pds3", "both"])
def test_a_creation_time_in_the_future_is_found(made, dialect, tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", NOW)
    delivery = _copy(made, dialect, tmp_path)
    _seed(delivery, f"{ORTHO}.LBL", 'PRODUCER_FULL_NAME        = "UNK"', "PRODUCT_CREATION_TIME = 2031-01-01T00:00:00")
    assert _found(delivery, "IDN-002") == [("IDN-002", "warning", "PSP_008669_1705_RED_C_01_ORTHO.LBL")]
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1956000000")  # 2031-12-26: then it is no longer ahead
    assert _found(delivery, "IDN-002") == []


def test_a_product_made_before_its_source_is_found(made, tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", NOW)
    volume = _copy(made, "pds3", tmp_path)
    # the same length as the line it replaces: the attached label's records keep their bytes
    _seed(volume, DTM_IMG, 'PRODUCER_FULL_NAME        = "UNK"', "PRODUCT_CREATION_TIME = 2020-01-02")
    _seed(volume, f"{ORTHO}.LBL", 'PRODUCER_FULL_NAME        = "UNK"', "PRODUCT_CREATION_TIME = 2020-01-01T00:00:00")
    found = [f for f in validate_paths([volume], labels_only=True).findings if f.rule == "IDN-004"]
    assert [(Path(f.file).name, "DTEEC_008669_1705_009025_1705_U01" in f.message) for f in found] == [
        ("PSP_008669_1705_RED_C_01_ORTHO.LBL", True)]
    _seed(volume, f"{ORTHO}.LBL", "2020-01-01T00:00:00", "2020-01-03T00:00:00")
    assert _found(volume, "IDN-004") == []


def test_stop_before_start_is_found_in_both_dialects(made, tmp_path):
    delivery = _copy(made, "both", tmp_path)
    _seed(delivery, f"{ORTHO}.xml", '<start_date_time xsi:nil="true" nilReason="unknown"/>',
          "<start_date_time>2020-01-02T00:00:00Z</start_date_time>")
    _seed(delivery, f"{ORTHO}.xml", '<stop_date_time xsi:nil="true" nilReason="unknown"/>',
          "<stop_date_time>2020-01-01T00:00:00Z</stop_date_time>")
    _seed(delivery, f"{ORTHO}.LBL", 'PRODUCER_FULL_NAME        = "UNK"',
          "START_TIME = 2020-01-02T00:00:00\r\nSTOP_TIME = 2020-001T00:00:00")
    assert _found(delivery, "IDN-003", "IDN-013") == [("IDN-003", "warning", "PSP_008669_1705_RED_C_01_ORTHO.LBL"),
                                                      ("IDN-013", "warning", "PSP_008669_1705_RED_C_01_ORTHO.xml")]


# --- stale Extras ----------------------------------------------------------------------------------

README = "EXTRAS/README.TXT"


def test_extras_record_the_label_they_were_made_from(products):
    """README.TXT's Label MD5 of the orthoimage is the MD5 of its detached label file, as md5sum
    computes it (an attached label's is that of the label's bytes)."""
    text = (products / "extras" / "README.TXT").read_text()
    digest = subprocess.run(["md5sum", "PSP_008669_1705_RED_C_01_ORTHO.LBL"], cwd=products, capture_output=True,
                            text=True, check=True).stdout.split()[0]
    assert f"  Label MD5:       {digest}\n" in text


def test_seeded_stale_and_undelivered_extras_are_found(made, tmp_path):
    delivery = _copy(made, "both", tmp_path)
    text = (delivery / README).read_text()
    recorded = text.split("  Label MD5:       ", 1)[1][:32]
    _seed(delivery, README, recorded, "0" * 32)
    assert _found(delivery, "DLV-017") == [("DLV-017", "error", "README.TXT")]
    _seed(delivery, README, "0" * 32, recorded)
    _seed(delivery, README, "120 samples x 160 lines", "120 samples x 150 lines")
    _seed(delivery, README, "  VALID_MINIMUM:   ", "  VALID_MINIMUM:   1")  # -4367.89 -> 1-4367.89: not a number
    assert _found(delivery, "DLV-018") == [("DLV-018", "error", "README.TXT")]
    (delivery / "EXTRAS" / "DTEEC_008669_1705_009025_1705_U01.th.jpg").unlink()
    (delivery / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.JP2").unlink()
    (delivery / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.LBL").unlink()
    found = [f for f in validate_paths([delivery], labels_only=True).findings if f.rule == "DLV-019"]
    assert sorted(f.message.split(",")[0] for f in found) == [
        "documents preview DTEEC_008669_1705_009025_1705_U01.th.jpg of DTEEC_008669_1705_009025_1705_U01",
        "documents product PSP_008669_1705_RED_C_01_ORTHO (PSP_008669_1705_RED_C_01_ORTHO.LBL)"]


def test_a_remade_product_with_old_extras_is_refused_and_a_consistent_remake_passes(products, tmp_path):
    """The README's flow: remake a DTM (--overwrite), deliver again. With the old Extras deliver
    refuses, naming README.TXT and the remedy; with the Extras made again the delivery passes
    --strict with no finding of these rules."""
    source = Path(shutil.copytree(products, tmp_path / "products"))
    scene = make_scene(width=120, height=160)
    cropped = write_geotiff(tmp_path / "dtm.tif", scene.elevation[:140], scene.transform, scene.crs, None)
    dtm = write_dtm(cropped, source, profile="hirise", source_product_ids=("PSP_008669_1705", "PSP_009025_1705"),
                    institution="U", label="both", overwrite=True)
    with pytest.raises(InputError) as refused:
        make_delivery(source, tmp_path / "out", dialect="both", volume_id="DEMO_0001", bundle_lid=BUNDLE_LID)
    message = str(refused.value)
    assert "stale Extras" in message and "extras/README.TXT" in message and "make them again" in message
    assert "`overwrite=True`" in message  # the library's words; the command line says --overwrite
    assert not (tmp_path / "out").exists()
    make_extras([dtm.path], source / "extras", overwrite=True)
    make_delivery(source, tmp_path / "out", dialect="both", volume_id="DEMO_0001", bundle_lid=BUNDLE_LID)
    assert _found(tmp_path / "out", *CONSISTENCY) == []


# --- keyword agreement across a delivery's parts --------------------------------------------------


def test_pds3_and_pds4_times_of_one_product_agree(made, tmp_path):
    delivery = _copy(made, "both", tmp_path)
    _seed(delivery, f"{ORTHO}.xml", '<start_date_time xsi:nil="true" nilReason="unknown"/>',
          "<start_date_time>2020-01-02T00:00:00Z</start_date_time>")
    _seed(delivery, f"{ORTHO}.LBL", 'PRODUCER_FULL_NAME        = "UNK"', "START_TIME = 2020-01-02T00:00:00")
    assert _found(delivery, "DLV-022") == []
    _seed(delivery, f"{ORTHO}.LBL", "START_TIME = 2020-01-02T00:00:00", "START_TIME = 2020-01-03T00:00:00")
    assert _found(delivery, "DLV-022") == [("DLV-022", "error", "PSP_008669_1705_RED_C_01_ORTHO.xml")]


def test_a_cart_grid_one_pixel_east_of_its_pds3_label_is_found(made, tmp_path):
    """The DTM's attached PDS3 label against its PDS4 label: the corner moved one pixel east.
    The PDS3 grid is read back by GDAL (rasterio), independently of the check."""
    import rasterio

    delivery = _copy(made, "both", tmp_path)
    label = delivery / "DATA" / "DTEEC_008669_1705_009025_1705_U01.xml"
    text = label.read_text()
    corner = etree.fromstring(text.encode()).find(".//{http://pds.nasa.gov/pds4/cart/v1}upperleft_corner_x")
    with rasterio.open(delivery / DTM_IMG) as dataset:
        ulx, xres = dataset.transform.c, dataset.transform.a
    assert float(corner.text) == pytest.approx(ulx)  # the two agree as made
    assert _found(delivery, "DLV-023") == []
    element = f'<cart:upperleft_corner_x unit="m">{corner.text}</cart:upperleft_corner_x>'
    assert element in text
    label.write_text(text.replace(element, f'<cart:upperleft_corner_x unit="m">{float(corner.text) + xres}'
                                           "</cart:upperleft_corner_x>"))
    found = [f for f in validate_paths([delivery], labels_only=True).findings if f.rule == "DLV-023"]
    assert [(Path(f.file).name, "+1.00 pixel east" in f.message) for f in found] == [
        ("DTEEC_008669_1705_009025_1705_U01.xml", True)]


def test_the_volume_and_the_bundle_hold_the_same_products(made, tmp_path):
    delivery = _copy(made, "both", tmp_path)
    (delivery / f"{ORTHO}.xml").rename(delivery / "DATA" / "ELSEWHERE.txt")
    found = _found(delivery, "DLV-024")
    assert found == [("DLV-024", "error", "PSP_008669_1705_RED_C_01_ORTHO.LBL")]


def test_an_undeclared_data_set_id_in_a_label_and_its_row_is_found(made, tmp_path):
    volume = _copy(made, "pds3", tmp_path)
    for relative in (f"{ORTHO}.LBL", "INDEX/INDEX.TAB"):
        _seed(volume, relative, "MRO-M-HIRISE-5-DTM-V1.0", "MRO-M-HIRISE-5-DTX-V1.0")
    found = [f for f in validate_paths([volume], labels_only=True).findings if f.rule == "DLV-005"]
    assert [(Path(f.file).name, "DTX" in f.message) for f in found] == [("INDEX.TAB", True)]


def test_deliver_names_a_sidecar_no_label_describes(products, tmp_path):
    """A GDAL .aux.xml beside a product is XML but no PDS4 label: deliver says it is left out."""
    source = Path(shutil.copytree(products, tmp_path / "products"))
    (source / "PSP_008669_1705_RED_C_01_ORTHO.JP2.aux.xml").write_text("<PAMDataset/>\n")
    result = make_delivery(source, tmp_path / "out", dialect="pds4", bundle_lid=BUNDLE_LID)
    assert [line.split(":")[0] for line in result.warnings] == [
        str(source / "PSP_008669_1705_RED_C_01_ORTHO.JP2.aux.xml")]
    assert not (tmp_path / "out" / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.JP2.aux.xml").exists()


# --- the delivery's model: previews, README.TXT against the files, identifiers -----------------------

DTM_ID = "DTEEC_008669_1705_009025_1705_U01"


@pytest.fixture(scope="module")
def remade(products, tmp_path_factory) -> tuple[Path, dict[str, bytes]]:
    """The DTM remade 20 lines shorter (--overwrite) and its Extras made again: a consistent
    remake; and the old browse and thumbnail of its shaded relief, to be put back."""
    root = tmp_path_factory.mktemp("old_previews")
    source = Path(shutil.copytree(products, root / "products"))
    old = {name: (source / "extras" / name).read_bytes() for name in (f"{DTM_ID}.sb.jpg", f"{DTM_ID}.st.jpg")}
    scene = make_scene(width=120, height=160)
    cropped = write_geotiff(root / "dtm.tif", scene.elevation[:140], scene.transform, scene.crs, None)
    dtm = write_dtm(cropped, source, profile="hirise", source_product_ids=("PSP_008669_1705", "PSP_009025_1705"),
                    institution="U", label="both", overwrite=True)
    make_extras([dtm.path], source / "extras", overwrite=True)
    return source, old


@pytest.mark.parametrize("dialect", ["pds3", "pds4", "both"])
def test_a_browse_and_thumbnail_of_a_product_since_remade_are_found(remade, dialect, tmp_path):
    """The old browse and thumbnail put back into the delivery of the consistent remake: README.TXT
    and the labels agree, but DLV-027 names each JPEG not the size the Extras make of the delivered
    product: the DTM is 120 x 140 now (GDAL reads it so), the two JPEGs 120 x 160 (GDAL too)."""
    source, old = remade
    delivery = tmp_path / dialect
    make_delivery(source, delivery, dialect=dialect, volume_id="DEMO_0001" if dialect != "pds4" else None,
                  bundle_lid=BUNDLE_LID if dialect != "pds3" else None)
    assert _found(delivery, *CONSISTENCY, labels_only=False) == []  # the consistent remake: clean
    for name, data in old.items():  # a new file: the delivery's are hard links to the products'
        (delivery / "EXTRAS" / name).unlink()
        (delivery / "EXTRAS" / name).write_bytes(data)
    assert _gdal_size(delivery / DTM_IMG) == (120, 140)
    assert _gdal_size(delivery / "EXTRAS" / f"{DTM_ID}.sb.jpg") == (120, 160)
    assert _gdal_size(delivery / "EXTRAS" / f"{DTM_ID}.br.jpg") == (120, 140)  # made again: not named
    assert _found(delivery, *CONSISTENCY) == [("DLV-027", "error", f"{DTM_ID}.sb.jpg"),
                                              ("DLV-027", "error", f"{DTM_ID}.st.jpg")]
    message = next(f.message for f in validate_paths([delivery], labels_only=True).findings if f.rule == "DLV-027")
    assert "120 x 160 pixels" in message and "is 120 x 140" in message


def test_deliver_refuses_a_browse_of_a_product_since_remade(remade, tmp_path):
    """The same old previews in the products' Extras: deliver refuses them as stale Extras, naming
    the JPEG and the remedy, and writes nothing."""
    source, old = remade
    source = Path(shutil.copytree(source, tmp_path / "products"))
    for name, data in old.items():
        (source / "extras" / name).write_bytes(data)
    with pytest.raises(InputError) as refused:
        make_delivery(source, tmp_path / "out", dialect="pds3", volume_id="DEMO_0001")
    message = str(refused.value)
    assert "stale Extras" in message and f"extras/{DTM_ID}.sb.jpg" in message and "make the Extras again" in message
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("dialect", ["pds3", "pds4", "both"])
def test_a_preview_readme_does_not_document_is_found(made, dialect, tmp_path):
    delivery = _copy(made, dialect, tmp_path)
    shutil.copy(delivery / "EXTRAS" / f"{DTM_ID}.br.jpg", delivery / "EXTRAS" / "DTEEC_001_U01.br.jpg")
    assert _found(delivery, "DLV-028") == [("DLV-028", "warning", "DTEEC_001_U01.br.jpg")]
    # a bundle's file no label describes is DLV-016's too, whatever README.TXT says
    unlabelled = [("DLV-016", "warning", "DTEEC_001_U01.br.jpg")] if dialect != "pds3" else []
    assert _found(delivery, "DLV-016") == unlabelled


@pytest.mark.parametrize("dialect", ["pds3", "pds4", "both"])
def test_a_readme_entry_listing_another_products_preview_is_found(made, dialect, tmp_path):
    """The DTM's entry lists the orthoimage's thumbnail for its own: README.TXT is named (DLV-029),
    and the DTM's own thumbnail, no longer documented, too (DLV-028)."""
    delivery = _copy(made, dialect, tmp_path)
    _seed(delivery, README, f"    {DTM_ID}.th.jpg\r\n", "    PSP_008669_1705_RED_C_01_ORTHO.thumb.jpg\r\n")
    assert _found(delivery, *CONSISTENCY) == [("DLV-028", "warning", f"{DTM_ID}.th.jpg"),
                                              ("DLV-029", "error", "README.TXT")]


@pytest.mark.parametrize("dialect", ["pds4", "both"])
def test_a_pds4_label_naming_another_products_id_is_found(made, dialect, tmp_path):
    delivery = _copy(made, dialect, tmp_path)
    _seed(delivery, f"DATA/{DTM_ID}.xml", f":{DTM_ID.lower()}</logical_identifier>",
          ":psp_008669_1705_red_c_01_ortho</logical_identifier>")
    found = [f for f in validate_paths([delivery], labels_only=True).findings if f.rule == "DLV-029"]
    assert [(Path(f.file).name, "PSP_008669_1705_RED_C_01_ORTHO" in f.message) for f in found] == [
        (f"{DTM_ID}.xml", True)]


# --- a bundle found by what its root says: deliver's previous delivery, the look for deliveries ------

def test_delivering_again_finds_the_previous_bundle_named_bundle_xml(products, tmp_path):
    """The previous delivery's bundle label is found by its root element (Product_Bundle), as
    validate and review find it: renamed bundle.xml, its LID is still the one delivered again
    (without it, deliver asks for bundle_lid)."""
    out = tmp_path / "out"
    make_delivery(products, out, dialect="pds4", bundle_lid=BUNDLE_LID)
    (out / "bundle_demo_dtm.xml").rename(out / "bundle.xml")
    make_delivery(products, out, dialect="pds4")
    label = next(path for path in out.glob("*.xml") if path.name.startswith("bundle"))
    lid = etree.parse(str(label)).findtext(".//pds:Identification_Area/pds:logical_identifier", namespaces=PDS_NS)
    assert lid == BUNDLE_LID
    with pytest.raises(InputError, match="bundle_lid"):  # a directory with no bundle label: asked for
        make_delivery(products, tmp_path / "fresh", dialect="pds4")


def test_looking_for_deliveries_reads_each_directorys_prologs_once(made, tmp_path, monkeypatch):
    """is_delivery on a directory of XML files (no manifest, no index) reads their prologs once
    while they are unchanged; a file rewritten is read again, and what it now is counts."""
    from pdsgen.archive import scan
    from pdsgen.validate.families.delivery_rules import is_delivery

    directory = tmp_path / "labels"
    directory.mkdir()
    for name in ("a.xml", "b.xml", "c.xml"):
        shutil.copy(made["pds4"] / "DATA" / "collection_data.xml", directory / name)
    read: list[str] = []
    reader = scan.root_element
    monkeypatch.setattr(scan, "root_element", lambda path: read.append(path.name) or reader(path))
    assert not is_delivery(directory) and sorted(read) == ["a.xml", "b.xml", "c.xml"]
    read.clear()
    assert not is_delivery(directory) and read == []
    shutil.copy(made["pds4"] / "bundle_demo_dtm.xml", directory / "b.xml")
    assert is_delivery(directory) and "b.xml" in read


@pytest.mark.parametrize("data", [b"", b"\xff\xd8", b"\xff\xd8\xff\xe0\x00\x01", b"\xff\xd8" + b"\xff\xe1\xff\xff" * 3,
                                  b"\xff\xd8\xff\xc0\x00\x11\x08", b"GIF89a"])
def test_a_preview_that_is_no_jpeg_is_not_compared(made, data, tmp_path):
    """The JPEG frame walk of DLV-027 reads a browse that is no JPEG, or one cut short, as no size
    (the file is not compared; nothing is read past its end), never an exception."""
    from pdsgen.formats.jpeg_size import jpeg_size

    path = tmp_path / "x.jpg"
    path.write_bytes(data)
    assert jpeg_size(path) is None
    delivery = _copy(made, "pds3", tmp_path)
    (delivery / "EXTRAS" / f"{DTM_ID}.br.jpg").write_bytes(data)
    assert _found(delivery, "DLV-027") == []


def test_the_delivery_model_reads_each_product_label_once(made, monkeypatch):
    """Without a run's cache (a plain validate), the delivery's checks read each product label
    once for the model (the index row, both dialects, the Extras, the quick look and the
    identifiers all ask it), and once more for the MD5 README.TXT records of it (its bytes)."""
    from collections import Counter

    from pdsgen.label import read as label_read
    from pdsgen.validate.families.delivery_rules import check_delivery

    reads: Counter[str] = Counter()
    original = label_read.read_pds3_label

    def counted(path, labels=None):
        reads[Path(path).name] += 1
        return original(path, labels)

    monkeypatch.setattr(label_read, "read_pds3_label", counted)
    check_delivery(made["both"], labels_only=True)
    assert reads[Path(DTM_IMG).name] == 2 and reads[f"{Path(ORTHO).name}.LBL"] == 2


# Names that climb out of a directory, made on purpose (this module reads nothing outside the clone)
UP = os.pardir + "/"
CLIMBING = f"{UP}{UP}outside/ELSEWHERE.IMG"


def test_names_readme_gives_are_taken_by_the_containment_rule(made, tmp_path):
    """README.TXT's "Product file" and its Extras files are names from the delivery: one that climbs
    out (a parent segment) is never looked up or read - the product is not delivered (DLV-019), even where a
    file of that name lies outside with a label in it (before, it was read and compared)."""
    delivery = _copy(made, "pds3", tmp_path)
    outside = tmp_path / "outside"
    outside.mkdir()
    shutil.copy(delivery / "DATA" / f"{DTM_ID}.IMG", outside / "ELSEWHERE.IMG")
    readme = delivery / README
    text = readme.read_text(encoding="ascii")
    readme.write_text(text.replace(f"Product file:    {DTM_ID}.IMG", "Product file:    " + CLIMBING),
                      encoding="ascii")
    found = _found(delivery, "DLV-017", "DLV-018", "DLV-019", "DLV-027")
    assert ("DLV-019", "warning", "README.TXT") in found
    assert {rule for rule, _, _ in found} == {"DLV-019"}


@settings(max_examples=300, deadline=None, derandomize=True)
@given(name=st.text(max_size=40) | st.sampled_from([f"{UP}x", "/etc/passwd", f"a/{UP}{UP}x", "LEADS_OUT/x", "ok.jpg",
                                                     f"LEADS_OUT/{UP}ok.jpg", "./ok.jpg", "a\x00b"]))
def test_a_name_readme_gives_stays_in_its_directory(tmp_path_factory, name):
    """Whatever the name, named_in gives a path inside the directory (links resolved) or none."""
    from pdsgen.archive.extras_check import named_in

    base = tmp_path_factory.getbasetemp() / "named_in"
    directory = base / "extras"
    if not directory.exists():
        directory.mkdir(parents=True)
        (base / "secret").mkdir()
        (directory / "LEADS_OUT").symlink_to(base / "secret")
    path = named_in(directory, name)
    if path is not None:
        assert os.path.realpath(path).startswith(os.path.realpath(directory) + os.sep)
