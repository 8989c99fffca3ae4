"""`pdsgen migrate VOLUME_DIR`: a PDS3 volume pdsgen itself delivers (`deliver --pds3` of the demo's
HiRISE DTM and orthoimage with Extras, and an HRSC DT4) becomes a PDS4 bundle: data files
byte-identical, every label XSD + Schematron valid, inventories equal to the labels written,
every document labelled, the crosswalk complete, and the cart: geometry of each product the
same as `deliver --pds4` of the same products writes."""

from __future__ import annotations

import csv
import hashlib
import shutil
from pathlib import Path

import pytest
from affine import Affine
from lxml import etree

from pdsgen.extras import make_extras
from pdsgen.migrate.volume import migrate_volume
from pdsgen.migrate.volume_files import SOFTWARE_REASON
from pdsgen.products.dtm import write_dtm
from pdsgen.products.ortho import write_ortho
from pdsgen.synthetic import make_scene, write_geotiff
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.label_checks import validate_pds4

from helpers import elevation_array, run_cli, write_raster

needs_saxon = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")
PDS = "{http://pds.nasa.gov/pds4/pds/v1}"
CART = "{http://pds.nasa.gov/pds4/cart/v1}"
BUNDLE = "urn:nasa:pds:pdsgen_volume"


@pytest.fixture(scope="module")
def products(tmp_path_factory) -> Path:
    """PDS3-only products: the demo's HiRISE DTM and orthoimage (with Extras) and an HRSC DT4."""
    root = tmp_path_factory.mktemp("volume_products")
    scene = make_scene(width=60, height=80)
    (root / "in").mkdir()
    dtm_in = write_geotiff(root / "in" / "dtm.tif", scene.elevation, scene.transform, scene.crs, None)
    ortho_in = write_geotiff(root / "in" / "ortho.tif", scene.reflectance, scene.transform, scene.crs, None)
    made = root / "products"
    dtm = write_dtm(dtm_in, made, profile="hirise", source_product_ids=("PSP_008669_1705", "PSP_009025_1705"),
                    institution="U")
    ortho = write_ortho(ortho_in, made, profile="hirise", observation_id="PSP_008669_1705",
                        source_dtm_id=dtm.product_id)
    make_extras([dtm.path, ortho.label_path], made / "extras")
    hrsc_in = write_raster(root / "in" / "hrsc.tif", elevation_array(40, 30, seed=2),
                           "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs",
                           Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0))
    write_dtm(hrsc_in, made, profile="hrsc", precision=0.05, product_id="h1234_0000")
    return made


@pytest.fixture(scope="module")
def volume(products, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("pds3") / "MROHR_0001"
    made = run_cli("deliver", products, "--pds3", "-o", out, "--volume-id", "MROHR_0001")
    assert made.returncode == 0, made.stderr
    return out


@pytest.fixture(scope="module")
def bundle(volume, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("pds4") / "bundle"
    made = run_cli("migrate", volume, "-o", out, "--bundle-lid", BUNDLE)
    assert made.returncode == 0, made.stderr
    assert "0 row(s) without a product" in made.stdout and "0 product(s) without a row" in made.stdout
    return out


def _md5(path: Path) -> str:
    return hashlib.md5(path.read_bytes()).hexdigest()


def _labels(root: Path) -> list[Path]:
    return sorted(root.rglob("*.xml"))


def _identity(label: Path) -> tuple[str, str, str]:
    area = etree.parse(str(label)).getroot().find(f"{PDS}Identification_Area")
    return (area.findtext(f"{PDS}logical_identifier"), area.findtext(f"{PDS}version_id"),
            area.findtext(f"{PDS}product_class"))


def test_every_file_of_the_volume_is_in_the_bundle_byte_identical(volume, bundle):
    for path in volume.rglob("*"):
        relative = path.relative_to(volume).as_posix()
        if path.is_file() and relative not in ("MD5SUMS.TXT", "REVIEW.html"):
            assert _md5(bundle / relative) == _md5(path), relative


@needs_saxon
def test_every_label_is_xsd_and_schematron_valid(bundle):
    labels = _labels(bundle)
    assert len(labels) > 20
    for label in labels:
        assert [f for f in validate_pds4(label) if f.severity == "error"] == [], label


def test_the_validator_finds_the_bundle_clean_delivery_checks_included(bundle):
    checked = run_cli("validate", bundle)
    assert checked.returncode == 0, checked.stdout
    assert " 0 error(s)" in checked.stdout
    assert "DLV-01" not in checked.stdout and "DLV-02" not in checked.stdout  # inventories, members, checksums


def test_inventories_list_exactly_the_labels_written(bundle):
    """Every product label's LIDVID in exactly one inventory, under its collection's LID, and the
    bundle lists exactly the collections."""
    listed: dict[str, str] = {}
    for inventory in bundle.glob("collection_*_inventory.csv"):
        collection = f"{BUNDLE}:{inventory.name[len('collection_'):-len('_inventory.csv')]}"
        for row in inventory.read_text().splitlines():
            status, lidvid = row.split(",")
            assert status == "P" and lidvid.startswith(collection + ":")
            assert lidvid not in listed
            listed[lidvid] = collection
    made = {}
    collections = set()
    for label in _labels(bundle):
        lid, version, product_class = _identity(label)
        if product_class == "Product_Collection":
            collections.add(f"{lid}::{version}")
        elif product_class != "Product_Bundle":
            made[f"{lid}::{version}"] = label
    assert set(made) == set(listed)
    assert len({lid.split("::")[0] for lid in made}) == len(made)  # LIDs unique
    assert all(lidvid == lidvid.lower() for lidvid in made)
    root = etree.parse(str(bundle / "bundle_pdsgen_volume.xml")).getroot()
    members = {e.findtext(f"{PDS}lidvid_reference") for e in root.iter(f"{PDS}Bundle_Member_Entry")}
    assert members == collections
    # two data sets on the volume: a data collection each
    assert {c.split("::")[0] for c in collections} >= {f"{BUNDLE}:data_mro-m-hirise-5-dtm-v1.0", f"{BUNDLE}:browse",
                                                       f"{BUNDLE}:document", f"{BUNDLE}:miscellaneous"}


def test_every_document_and_browse_image_is_labelled(volume, bundle):
    described = {}
    for label in _labels(bundle):
        for name in etree.parse(str(label)).getroot().iter(f"{PDS}file_name"):
            described[(label.parent / name.text).relative_to(bundle).as_posix()] = _identity(label)[2]
    for name in ("VOLDESC.CAT", "AAREADME.TXT", "EXTRAS/README.TXT", "DATA/JP2INFO.TXT"):
        assert described[name] == "Product_Document", name
    for image in volume.glob("EXTRAS/*.jpg"):
        assert described[image.relative_to(volume).as_posix()] == "Product_Browse"
    standard = etree.parse(str(bundle / "VOLDESC.xml")).getroot().findtext(f".//{PDS}document_standard_id")
    assert standard == "7-Bit ASCII Text"
    browse = etree.parse(str(bundle / "EXTRAS" / "PSP_008669_1705_RED_C_01_ORTHO.QLOOK.xml")).getroot()
    assert browse.findtext(f".//{PDS}encoding_standard_id") == "JP2"
    assert browse.findtext(f".//{PDS}lidvid_reference") == f"{BUNDLE}:data_mro-m-hirise-5-dtm-v1.0:" \
                                                            "psp_008669_1705_red_c_01_ortho::1.0"


def test_the_crosswalk_maps_every_product_of_the_index(volume, bundle):
    index = {line.split(",")[1].strip().strip('"').strip() for line in
             (volume / "INDEX" / "INDEX.TAB").read_text().splitlines()}
    with open(bundle / "crosswalk.csv", newline="") as stream:
        rows = list(csv.reader(stream))
    paths = [path for _, path, _, _ in rows]
    assert index <= set(paths)
    assert len(paths) == len(set(paths))  # one row per PDS3 file
    lidvids = {lidvid for _, _, lidvid, _ in rows}
    for label in _labels(bundle):
        lid, version, product_class = _identity(label)
        if product_class in ("Product_Observational", "Product_Document", "Product_Browse"):
            assert f"{lid}::{version}" in lidvids, label
    # every file of the volume has its row: held by a product (a LIDVID), or left out with the reason
    assert set(paths) == {p.relative_to(volume).as_posix() for p in volume.rglob("*") if p.is_file()}
    assert all(lidvid or role.startswith(("left out: ", "format file kept")) for _, _, lidvid, role in rows)
    assert _identity(bundle / "crosswalk.xml")[2] == "Product_Ancillary"


def _cartography(label: Path) -> bytes:
    cart = etree.parse(str(label), etree.XMLParser(remove_blank_text=True)).getroot().find(f".//{CART}Cartography")
    assert cart is not None, label
    return etree.tostring(cart, method="c14n")


def test_cart_geometry_equals_deliver_pds4_of_the_same_products(products, bundle, tmp_path):
    source = tmp_path / "products"
    shutil.copytree(products, source)
    delivered = tmp_path / "delivered"
    made = run_cli("deliver", source, "--pds4", "-o", delivered, "--bundle-lid", BUNDLE)
    assert made.returncode == 0, made.stderr
    names = ["DTEEC_008669_1705_009025_1705_U01.xml", "PSP_008669_1705_RED_C_01_ORTHO.xml", "h1234_0000_dt4.xml"]
    for name in names:
        assert _cartography(bundle / "DATA" / name) == _cartography(delivered / "DATA" / name), name


def test_problems_are_reported_and_the_others_go_on(volume, tmp_path):
    """A product the index does not list, an index row without its product, a LID collision
    (one name in two directories), software, and a refused product: each reported by name."""
    messy = tmp_path / "messy"
    shutil.copytree(volume, messy)
    (messy / "DATA" / "h1234_0000_dt4.img").unlink()  # an index row without its product
    sub = messy / "DATA" / "SUB"
    sub.mkdir()
    shutil.copy(messy / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.LBL", sub)
    shutil.copy(messy / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.JP2", sub)
    (messy / "SOFTWARE").mkdir()
    (messy / "SOFTWARE" / "tool.exe").write_bytes(b"MZ\x90\x00")
    (messy / "DATA" / "BROKEN.LBL").write_text("PDS_VERSION_ID = PDS3\r\n^IMAGE = \"NONE.IMG\"\r\n"
                                               "OBJECT = IMAGE\r\n LINES = 2\r\nEND_OBJECT = IMAGE\r\nEND\r\n")
    out = tmp_path / "bundle"
    result = migrate_volume(messy, out, bundle_lid="urn:nasa:pds:messy")
    assert [r for r in result.refused if "BROKEN.LBL" in r]
    assert result.exit_code == 2
    assert any("DATA/SUB/PSP_008669_1705_RED_C_01_ORTHO.LBL" in w for w in result.unindexed)
    assert "DATA/BROKEN.LBL" in result.unindexed[0] or len(result.unindexed) == 1
    assert [m for m in result.missing if "H1234_0000_DT4.IMG" in m]
    assert [c for c in result.collisions if "data_sub_psp_008669_1705_red_c_01_ortho" in c]
    assert ("SOFTWARE/tool.exe", SOFTWARE_REASON) in result.left_out
    assert (out / "DATA" / "SUB" / "PSP_008669_1705_RED_C_01_ORTHO.xml").is_file()
    assert (out / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.xml").is_file()
    assert not (out / "SOFTWARE").exists()
    assert not list(tmp_path.glob(".bundle.*"))


def test_in_place_writes_labels_beside_the_volume_files(volume, tmp_path):
    copy = tmp_path / "vol"
    shutil.copytree(volume, copy)
    before = {p.relative_to(copy).as_posix(): _md5(p) for p in copy.rglob("*") if p.is_file()}
    made = run_cli("migrate", copy, "--in-place", "--bundle-lid", BUNDLE)
    assert made.returncode == 0, made.stderr
    for relative, digest in before.items():
        if relative != "MD5SUMS.TXT":
            assert _md5(copy / relative) == digest, relative
    assert (copy / "DATA" / "DTEEC_008669_1705_009025_1705_U01.xml").is_file()
    checked = run_cli("validate", copy)
    assert " 0 error(s)" in checked.stdout, checked.stdout
    again = run_cli("migrate", copy, "--in-place", "--bundle-lid", BUNDLE)  # a re-run makes the same labels
    assert again.returncode == 0, again.stderr
    assert not list(copy.rglob("*.xml.xml")) and not list(copy.rglob("*.TXT.xml"))


def test_bad_input_is_one_line_and_nothing_is_written(volume, tmp_path):
    made = run_cli("migrate", volume, "-o", tmp_path / "b")
    assert made.returncode == 2 and "--bundle-lid" in made.stderr and "Traceback" not in made.stderr
    made = run_cli("migrate", volume, "-o", tmp_path / "b", "--bundle-lid", "urn:nasa:pds:Bad Name")
    assert made.returncode == 2 and "Traceback" not in made.stderr
    assert len(made.stderr.strip().splitlines()) == 1
    made = run_cli("migrate", volume, "-o", tmp_path / "b", "--bundle-lid", BUNDLE, "--collection", "x")
    assert made.returncode == 2 and "--collection" in made.stderr  # not silently ignored
    made = run_cli("migrate", tmp_path / "no_such_volume", "-o", tmp_path / "b", "--bundle-lid", BUNDLE)
    assert made.returncode == 2 and "Traceback" not in made.stderr
    assert not (tmp_path / "b").exists()


def test_a_volume_carrying_pds4_labels_leaves_them_out_and_every_label_fits_its_file(tmp_path):
    """Products made with --label both carry a PDS4 label beside each PDS3 one, and a PDS3 delivery
    of them carries it too: migrate leaves those out (saying why) instead of describing one as a
    document and then writing the bundle's own label of the product over its copy."""
    scene = make_scene(width=30, height=40)
    source = write_geotiff(tmp_path / "dtm.tif", scene.elevation, scene.transform, scene.crs, None)
    dtm = write_dtm(source, tmp_path / "products", profile="hirise", label="both", institution="U",
                    source_product_ids=("PSP_008669_1705", "PSP_009025_1705"))
    assert dtm.pds4_label_path is not None
    volume = tmp_path / "VOL_0001"
    assert run_cli("deliver", tmp_path / "products", "--label", "pds3", "-o", volume,
                   "--volume-id", "VOL_0001").returncode == 0
    carried = sorted(p.relative_to(volume).as_posix() for p in volume.rglob("*.xml"))
    assert carried, "the PDS3 volume carries the products' PDS4 labels"
    bundle = tmp_path / "bundle"
    made = run_cli("migrate", volume, "-o", bundle, "--bundle-lid", "urn:nasa:pds:carried")
    assert made.returncode == 0, made.stderr
    with open(bundle / "crosswalk.csv", newline="") as table:
        rows = {row[1]: row for row in csv.reader(table)}
    for name in carried:
        assert rows[name][2] == "" and rows[name][3].startswith("left out: a PDS4 label the volume carried"), rows[name]
    for label in _labels(bundle):  # every file a label names is the file it describes
        tree = etree.parse(str(label))
        for file_area in tree.iter(f"{PDS}File", f"{PDS}Document_File"):
            name = file_area.findtext(f"{PDS}file_name")
            path = label.parent / (file_area.findtext(f"{PDS}directory_path_name") or "") / name
            checksum = file_area.findtext(f"{PDS}md5_checksum")
            assert path.is_file(), (label, name)
            if checksum:
                assert _md5(path) == checksum, (label, name)
