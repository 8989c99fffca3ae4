"""PDS4-063: context references against PDS's registry of context products, the snapshot
NASA's validator ships (NASA-PDS/validate @ df054fd, registered_context_products.json),
on the suite's own cases (copied with provenance to tests/data/nasa_validate)."""

from __future__ import annotations

import lzma
from pathlib import Path

import pytest

from pdsgen.missions import hirise, hrsc
from pdsgen.resources import schemas_dir
from pdsgen.validate.pds4.context_registry import is_registered
from pdsgen.validate.pds4.label_checks import validate_pds4

CASES = Path(__file__).parent / "data" / "nasa_validate"


def _context(label: Path) -> list[str]:
    return [f.message.split()[0] for f in validate_pds4(label, labels_only=True) if f.rule == "PDS4-063"]


def test_unregistered_context_products_of_the_suite():
    """47-2: spacecraft.FOO among four registered references (NASA: 1 context_ref_not_found);
    62-2: mission.FOO (NASA: 1)."""
    assert _context(CASES / "github47/test_context_products.xml") == [
        "urn:nasa:pds:context:instrument_host:spacecraft.FOO"]
    assert _context(CASES / "github62/spacecraft.orex_1.1.xml") == ["urn:nasa:pds:context:investigation:mission.FOO"]


@pytest.mark.parametrize(("reference", "known"), [
    ("urn:nasa:pds:context:target:planet.mars", True),
    ("URN:NASA:PDS:CONTEXT:TARGET:PLANET.MARS", True),  # LIDs compare case aside, as NASA's validator does
    ("urn:nasa:pds:context:instrument_host:spacecraft.mro::1.0", True),  # an older version than registered
    ("urn:nasa:pds:context:instrument_host:spacecraft.mro::99.0", False),  # a version not yet registered
    ("urn:nasa:pds:context:instrument:mro.hirise", False),  # HiRISE is registered as hirise.mro
    ("urn:esa:psa:context:investigation:mission.mex", False),  # Mars Express as mission.mars_express
])
def test_lid_and_lidvid_references(reference, known):
    assert is_registered(reference) is known


def test_pdsgen_names_registered_context_products():
    """The HiRISE and HRSC profiles' PDS4 labels reference only registered products."""
    for facts in (hirise.PDS4, hrsc.PDS4):
        for reference in (facts.investigation, *facts.observing_system):
            assert is_registered(reference.lid), reference


def test_snapshot_provenance():
    first = lzma.decompress((schemas_dir() / "pds4" / "context_products.txt.xz").read_bytes()).split(b"\n", 1)[0]
    assert first == (b"# NASA-PDS/validate @ df054fd182e4c211af3940e3b570fa020384c7c3 "
                     b"src/main/resources/util/registered_context_products.json")
