"""Catalogue facts of a migrated label from their sources (issue 39): the target's type and LID and
the investigation, host and instrument from PDS's registry of context products, the radii from the
label's own A/B/C_AXIS_RADIUS, and a warning where the label's bounds disagree with its grid.

References that do not share the code's assumptions: the registry facts are read here, by the
test, from the shipped snapshot file (its lines, not pdsgen's lookup); the radii from the label
by pvl; the grid's extent from GDAL's geotransform (through rasterio) of the PDS3 product; XML Schema validity by
the shipped schemas. Labels: genuine (tests/data/facts_catalogue/SOURCES.md).
"""

from __future__ import annotations

import lzma
import math
import shutil
from pathlib import Path

import pvl
import pytest
import rasterio
from lxml import etree

from conftest import CORPUS_DIR, REPO_ROOT
from pdsgen.migrate import migrate_product
from pdsgen.migrate.identity import observation, target_identification
from pdsgen.migrate.product import migrate_products
from pdsgen.validate.context import FileContext
from pdsgen.validate.pds4.label_checks import validate_pds4

DATA = Path(__file__).parent / "data" / "facts_catalogue"
SNAPSHOT = REPO_ROOT / "schemas" / "pds4" / "context_products.txt.xz"
NS = {"pds": "http://pds.nasa.gov/pds4/pds/v1", "cart": "http://pds.nasa.gov/pds4/cart/v1"}
BUNDLE = "urn:nasa:pds:facts_test"


def snapshot() -> dict[str, tuple[list[str], list[str]]]:
    """The registry snapshot as its lines say: LID -> (types, names)."""
    products: dict[str, tuple[list[str], list[str]]] = {}
    for line in lzma.decompress(SNAPSHOT.read_bytes()).decode("utf-8").splitlines()[1:]:
        lid_version, types, names = line.split("\t")
        lid = lid_version.split(" ")[0]
        have = products.setdefault(lid, ([], []))
        have[0].extend(t for t in types.split("|") if t)
        have[1].extend(n for n in names.split("|") if n)
    return products


REGISTRY = snapshot()


def registered(kind: str, name: str) -> str:
    """The one LID of `kind` (target, investigation ...) among whose names `name` is (case aside)."""
    found = {lid for lid, (_, names) in REGISTRY.items()
             if f":context:{kind}:" in lid and name.upper() in (n.upper() for n in names)}
    assert len(found) == 1, (name, found)
    return found.pop()


def facts(label: Path) -> dict:
    return observation(FileContext(label).root, label.name)


# -- targets and investigations of genuine labels ---------------------------------------------------------

@pytest.mark.parametrize(("label", "target_name", "registered_type"), [
    ("m0126865998f4_2p_iof.lbl", "EROS", "Asteroid"),
    ("gaspra_nims_hires_radiance_cropped.lbl", "951 GASPRA", "Asteroid"),
    ("N1727539187_1.LBL", "TITAN", "Satellite"),
])
def test_a_registered_target_gets_its_registered_type_and_lid(label, target_name, registered_type):
    lid = registered("target", target_name)
    assert REGISTRY[lid][0] == [registered_type]
    found = facts(DATA / label)
    assert [(t["lid"], t["types"]) for t in found["targets"]] == [(lid, [registered_type])]
    assert found["warnings"] == []


@pytest.mark.parametrize(("label", "mission", "host", "instrument_lid"), [
    ("m0126865998f4_2p_iof.lbl", "NEAR EARTH ASTEROID RENDEZVOUS", "NEAR EARTH ASTEROID RENDEZVOUS",
     "urn:nasa:pds:context:instrument:msi.near"),
    ("gaspra_nims_hires_radiance_cropped.lbl", "GALILEO", "GALILEO ORBITER", "urn:nasa:pds:context:instrument:go.nims"),
    ("N1727539187_1.LBL", "CASSINI-HUYGENS", "CASSINI ORBITER", "urn:nasa:pds:context:instrument:issna.co"),
])
def test_the_investigation_host_and_instrument_are_the_registered_ones(label, mission, host, instrument_lid):
    found = facts(DATA / label)
    assert found["investigation"]["lid"] == registered("investigation", mission)
    assert found["investigation"]["reference_type"] == "data_to_investigation"
    components = [(c["type"], c["lid"], c["reference_type"]) for c in found["components"]]
    assert components == [("Host", registered("instrument_host", host), "is_instrument_host"),
                          ("Instrument", instrument_lid, "is_instrument")]
    assert instrument_lid in REGISTRY


@pytest.mark.parametrize(("mission", "host"), [
    ("INTERNATIONAL ROSETTA MISSION", "ROSETTA-ORBITER"),  # as Rosetta's PDS3 labels name them
    ("ULYSSES", "ULYSSES"),
])
def test_rosetta_and_ulysses_are_their_registered_investigations(tmp_path, mission, host):
    label = tmp_path / "x.lbl"
    label.write_text(f'PDS_VERSION_ID = PDS3\nMISSION_NAME = "{mission}"\nINSTRUMENT_HOST_NAME = "{host}"\n'
                     'TARGET_NAME = "SOLAR WIND"\nEND\n')
    found = facts(label)
    assert found["investigation"]["lid"] == registered("investigation", mission)
    assert found["investigation"]["name"] != "No Specific Investigation"
    assert found["components"][0]["lid"] == registered("instrument_host", host)
    assert [(t["lid"], t["types"]) for t in found["targets"]] == [
        (registered("target", "SOLAR WIND"), REGISTRY[registered("target", "SOLAR WIND")][0])]


@pytest.mark.parametrize(("target_name", "registered_name"), [
    ("67P/CHURYUMOV-GERASIMENKO 1 (1969 R1)", "67P/Churyumov-Gerasimenko"),  # Rosetta's TARGET_NAME: a comet
    ("DARK SKY", "DARK SKY"),  # the dark sky: a calibration field
    ("CALIBRATION", "CALIBRATION"),  # a calibrator
    ("SKY", "SKY"),
    ("PHOBOS", "PHOBOS"),
])
def test_comets_calibration_targets_and_the_sky_are_not_planets(target_name, registered_name):
    lid = registered("target", registered_name)
    warnings: list[str] = []
    found = target_identification(target_name, None, warnings)
    assert (found["lid"], found["types"]) == (lid, REGISTRY[lid][0])
    assert "Planet" not in found["types"] and warnings == []


@pytest.mark.parametrize(("target_name", "stated", "kind", "why"), [
    ("C/2099 Z9 (NOBODY)", None, "Comet", "its IAU designation"),
    ("S/2099 S 99", None, "Satellite", "its IAU designation"),
    ("NOT A BODY PDS KNOWS", "ASTEROID", "Asteroid", "the label's TARGET_TYPE = ASTEROID"),
])
def test_an_unregistered_target_gets_the_type_that_is_certain_and_a_warning(target_name, stated, kind, why):
    warnings: list[str] = []
    found = target_identification(target_name, stated, warnings)
    assert (found["lid"], found["types"]) == (None, [kind])
    assert warnings == [f"TARGET_NAME {target_name!r} is not one target in PDS's registry of context products: "
                        f"typed {kind} ({why}), without a context reference"]


def test_an_unregistered_target_of_unknown_type_is_said_so():
    warnings: list[str] = []
    found = target_identification("NOT A BODY PDS KNOWS", None, warnings)
    unknown = registered("target", "Unknown")  # the registry's own unknown target
    assert found["types"] == REGISTRY[unknown][0] and found["lid"] is None
    assert warnings == [f"TARGET_NAME 'NOT A BODY PDS KNOWS' is not in PDS's registry of context products and "
                        f"nothing in the label states its type: Target_Identification/type written as "
                        f"{REGISTRY[unknown][0][0]}, the type PDS registers its unknown target with; "
                        "state the true type"]


# -- migrated products: the label written, its radii and bounds ---------------------------------------------

@pytest.fixture(scope="module")
def mc02(tmp_path_factory) -> tuple[Path, Path]:
    """GDAL's one-line MOC mosaic MC02: the genuine label, its record padded to RECORD_BYTES, and one
    line of zero bytes (the data GDAL's copy holds are not needed for the label's facts)."""
    directory = tmp_path_factory.mktemp("mc02")
    label_text = (CORPUS_DIR / "real" / "MC02_truncated.img.lbl").read_bytes()
    record = 3840
    product = directory / "mc02_truncated.img"
    product.write_bytes(label_text.ljust(record, b" ") + bytes(record))
    out = directory / "out"
    run = migrate_products([product], out, bundle_lid=BUNDLE)
    assert not run.refused, run.refused
    return product, out / "mc02_truncated.xml", run


def _cart(label: Path, name: str) -> float:
    return float(etree.parse(str(label)).findtext(f".//cart:{name}", namespaces=NS))


def test_radii_are_the_labels_own(mc02):
    product, label, _ = mc02
    projection = pvl.loads(product.read_bytes()[:3840].decode("latin-1").rstrip())["IMAGE_MAP_PROJECTION"]
    for axis in ("A", "B", "C"):
        assert _cart(label, f"{axis.lower()}_axis_radius") == pytest.approx(
            float(projection[f"{axis}_AXIS_RADIUS"]) * 1000.0, rel=1e-12)
    assert _cart(label, "c_axis_radius") == pytest.approx(3376800.0)  # not the sphere's 3396 km


def test_bounds_disagreeing_with_the_grid_are_a_warning_and_the_cart_follows_the_grid(mc02):
    product, label, run = mc02
    # The grid as GDAL places it: one line of MAP_SCALE km on a sphere of A_AXIS_RADIUS.
    with rasterio.open(product) as dataset:  # GDAL's PDS driver
        uly, yres = dataset.transform.f, dataset.transform.e
    radius = 3396000.0
    degrees = 180.0 / (math.pi * radius)
    # The label's 30..65 degrees are the whole mosaic's; GDAL's copy keeps one line of it. The
    # label's MAXIMUM_LATITUDE is within half a pixel of the grid's edge, MINIMUM_LATITUDE is not.
    assert run.warnings == (
        f"{product}: OBJECT = IMAGE_MAP_PROJECTION: the label's bounds disagree with the grid's extent by more "
        f"than half a pixel (MINIMUM_LATITUDE = 30.0000000 (grid: {(uly + yres) * degrees:.6g})): "
        "cart:Bounding_Coordinates follows the grid",)
    assert _cart(label, "north_bounding_coordinate") == pytest.approx(uly * degrees, abs=1e-6)
    assert _cart(label, "south_bounding_coordinate") == pytest.approx((uly + yres) * degrees, abs=1e-6)
    assert 65.0 - 1 / 64 <= _cart(label, "south_bounding_coordinate") < 65.0  # one pixel of 1/64 degree


def test_the_migrated_label_is_xml_schema_valid_and_names_registered_context(mc02):
    _, label, _ = mc02
    findings = validate_pds4(label, labels_only=True)
    assert [f for f in findings if f.severity == "error"] == []
    root = etree.parse(str(label)).getroot()
    target = root.find(".//pds:Target_Identification", NS)
    assert (target.findtext("pds:type", namespaces=NS),
            target.findtext("pds:Internal_Reference/pds:lid_reference", namespaces=NS)) == \
        (REGISTRY[registered("target", "MARS")][0][0], registered("target", "MARS"))
    assert root.findtext(".//pds:Investigation_Area/pds:Internal_Reference/pds:lid_reference", namespaces=NS) == \
        registered("investigation", "MARS GLOBAL SURVEYOR")


def test_a_satellite_product_is_typed_as_registered(tmp_path):
    source = CORPUS_DIR / "products" / "MPF_IMP_i985135l" / "i985135l.img"
    shutil.copy(source, tmp_path / source.name)
    product = migrate_product(tmp_path / source.name, tmp_path / "out", bundle_lid=BUNDLE)
    target = etree.parse(str(product.label_path)).getroot().find(".//pds:Target_Identification", NS)
    lid = registered("target", "DEIMOS")
    assert (target.findtext("pds:type", namespaces=NS),
            target.findtext("pds:Internal_Reference/pds:lid_reference", namespaces=NS)) == (REGISTRY[lid][0][0], lid)
    assert validate_pds4(product.label_path, labels_only=True) == []


# -- pdsgen validate on PDS4 labels --------------------------------------------------------------------------

def test_validate_warns_of_a_target_type_the_registry_contradicts(mc02, tmp_path):
    _, label, _ = mc02
    wrong = tmp_path / "wrong.xml"
    wrong.write_text(label.read_text(encoding="utf-8").replace("<type>Planet</type>", "<type>Satellite</type>", 1),
                     encoding="utf-8")
    found = [(f.rule, f.severity, f.message) for f in validate_pds4(wrong, labels_only=True) if f.rule == "PDS4-065"]
    assert found == [("PDS4-065", "warning", "target 'Mars' is typed Satellite but PDS registers its context "
                                             "reference urn:nasa:pds:context:target:planet.mars as Planet")]
    assert [f for f in validate_pds4(label, labels_only=True) if f.rule == "PDS4-065"] == []


def test_validate_notes_no_specific_investigation_beside_a_registered_mission_host(mc02, tmp_path):
    _, label, _ = mc02
    text = label.read_text(encoding="utf-8")
    mission = registered("investigation", "MARS GLOBAL SURVEYOR")
    none = tmp_path / "none.xml"
    none.write_text(text.replace(mission, "urn:nasa:pds:context:investigation:individual.none")
                    .replace("<type>Mission</type>", "<type>Individual Investigation</type>", 1), encoding="utf-8")
    found = [(f.rule, f.severity) for f in validate_pds4(none, labels_only=True) if f.rule == "PDS4-066"]
    assert found == [("PDS4-066", "info")]


def test_each_target_of_a_target_sequence_is_identified(tmp_path):
    label = tmp_path / "x.lbl"
    label.write_text('PDS_VERSION_ID = PDS3\nTARGET_NAME = ("MARS", "PHOBOS", "DEIMOS")\nEND\n')
    assert [(t["lid"], t["types"]) for t in facts(label)["targets"]] == [
        (registered("target", name), REGISTRY[registered("target", name)][0]) for name in ("MARS", "PHOBOS", "DEIMOS")]
