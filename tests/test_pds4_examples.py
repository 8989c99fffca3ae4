"""Real PDS4 map labels (tests/data/corpus/pds4_examples, older IM versions) through the validator.

With their own schemas (tests/data/pds4_schemas/*.tar.xz, see SOURCES.md there) the schema
and Schematron checks find nothing; the content checks report only what is really wrong
in these labels. With the shipped schemas alone (the core schema of every IM version and
every version of the discipline dictionaries, but no mission dictionary) each missing
dictionary gets one finding, everything else is still checked, and nothing crashes. The
data files are not in the examples, so --labels-only.
"""

from __future__ import annotations

import tarfile
from pathlib import Path

import pytest

from conftest import PDS4_EXAMPLES_DIR
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.catalog import SchemaCatalog
from pdsgen.validate.pds4.label_checks import validate_pds4

EXAMPLES = PDS4_EXAMPLES_DIR
ARCHIVES = Path(__file__).parent / "data" / "pds4_schemas"

# Findings that are true of these labels (checked by hand against the label text):
KNOWN = {
    # a comment precedes the XML declaration (the stored copy's note): not well-formed XML
    "M044416018S_map_raw.xml": {("PDS4-001", None)},
    # pixel_scale 0.1 pixel/deg, but 139 km/pixel on Jupiter's 71492 km radius is 8.98 pixel/deg
    # (and 3601 samples over 360 degrees is 10 pixel/deg): the label contradicts itself
    "Cassini_ISS_CB2_Jupiter_global_map_2.xml": {("PDS4-030", "pixel_scale_x")},
    # Geo_Transformation (-3396.746 m, 4600.123 m) for a global 8492 x 879 m map of Pluto: a
    # placeholder, far from the -3.73e6 m a 0..360 degree map starts at
    "pluto_albedo_hof22.xml": {("PDS4-031", f"{side}_bounding_coordinate")
                               for side in ("west", "east", "north", "south")}
                              # a note (info): No Specific Investigation beside the New Horizons host
                              | {("PDS4-066", "Investigation_Area")},
    "BILQH07S314_D065_T008S02_V02.xml": set(),
}


@pytest.fixture(scope="module")
def examples() -> Path:
    return EXAMPLES


@pytest.fixture(scope="module")
def old_schemas(tmp_path_factory) -> SchemaCatalog:
    root = tmp_path_factory.mktemp("pds4_old_schemas")
    for archive in sorted(ARCHIVES.glob("*.tar.xz")):
        with tarfile.open(archive) as tar:
            tar.extractall(root, filter="data")
    return SchemaCatalog.build([root])


@pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")
@pytest.mark.parametrize("name", sorted(KNOWN))
def test_examples_with_their_own_schemas_have_no_false_errors(examples, old_schemas, name):
    found = validate_pds4(examples / name, old_schemas, labels_only=True)
    assert {(f.rule, f.keyword) for f in found} == KNOWN[name], [f.message for f in found]


@pytest.mark.parametrize("name", sorted(KNOWN))
def test_examples_without_their_dictionaries_get_one_finding_per_missing_one(examples, name):
    found = validate_pds4(examples / name, labels_only=True)
    not_shipped = [f.message.split()[1] for f in found if f.rule == "PDS4-002"]
    assert len(not_shipped) == len(set(not_shipped))
    # every core version and every discipline dictionary is shipped: only Cassini's mission one is not
    assert not_shipped == (["PDS4_CASSINI_1D00_1500"] if name.startswith("Cassini") else []), not_shipped
    assert {(f.rule, f.keyword) for f in found if f.rule != "PDS4-002"} == KNOWN[name]
