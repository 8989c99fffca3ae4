"""migrate and validate of one mind: every finding `pdsgen validate` makes on a bundle `pdsgen
migrate` wrote was told by migrate when it wrote it, in the same words.

Each genuine volume of the tests (tests/data/volume_*, PROVENANCE.md in each) is migrated, and the
bundle is validated by `pdsgen validate` in a process of its own; the two sets of finding lines
must be equal. Every table and array of every migrated label is then opened by pds4_tools (a
reader that shares none of pdsgen's code): a label a PDS4 reader cannot open is never written.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from lxml import etree

from pdsgen.migrate.volume import migrate_volume
from pdsgen.validate.report import finding_line

from helpers import run_cli

pds4_tools = pytest.importorskip("pds4_tools")

DATA = Path(__file__).parent / "data"
GENUINE_VOLUMES = sorted(p.name for p in DATA.glob("volume_*") if (p / "PROVENANCE.md").is_file())
PDS = "{http://pds.nasa.gov/pds4/pds/v1}"
DATA_OBJECTS = ("Table_Binary", "Table_Character", "Table_Delimited", "Array", "Array_1D", "Array_2D", "Array_3D",
                "Array_2D_Image", "Array_3D_Image")


def _findings_of_validate(bundle: Path) -> set[str]:
    result = run_cli("validate", bundle, "--no-config")
    assert "Traceback" not in result.stderr
    return {line for line in result.stdout.splitlines() if " [" in line and line.startswith(str(bundle))}


@pytest.fixture(scope="module", params=GENUINE_VOLUMES)
def migrated(request, tmp_path_factory):
    out = tmp_path_factory.mktemp(request.param) / "bundle"
    result = migrate_volume(DATA / request.param, out, bundle_lid=f"urn:nasa:pds:{request.param}")
    return out, result


def test_there_are_genuine_volumes_of_several_nodes():
    assert {"volume_fbirtfspec", "volume_gp0001"} <= set(GENUINE_VOLUMES)


def test_migrate_told_every_finding_validate_makes_on_the_bundle(migrated):
    out, result = migrated
    told = {finding_line(finding) for finding in result.validation}
    assert told == _findings_of_validate(out)
    assert set(result.warnings) >= told  # told to the user among migrate's warnings


def test_every_table_and_array_migrate_wrote_opens_in_pds4_tools(migrated):
    out, _ = migrated
    opened = 0
    for label in sorted(out.rglob("*.xml")):
        root = etree.parse(str(label)).getroot()
        if not any(True for name in DATA_OBJECTS for _ in root.iter(f"{PDS}{name}")):
            continue
        for structure in pds4_tools.read(str(label), quiet=True, lazy_load=True).structures:
            if structure.is_header():
                continue
            assert structure.data is not None and len(structure.data) > 0, (label, structure.id)
            opened += 1
    assert opened >= 3


def test_a_plain_pdf_document_is_told_by_migrate_as_validate_tells_it(tmp_path):
    """A PDF that is not PDF/A (the volume's own bytes): labelled 'PDF' as the bytes justify, and
    PDS4-061 told by migrate in validate's words, not first learned from validate."""
    volume = tmp_path / "volume"
    shutil.copytree(DATA / "volume_fbirtfspec", volume)
    (volume / "document" / "plain.pdf").write_bytes(
        b"%PDF-1.4\n1 0 obj << /Type /Catalog /Pages 2 0 R >> endobj\n"
        b"2 0 obj << /Type /Pages /Kids [] /Count 0 >> endobj\ntrailer << /Root 1 0 R >>\n%%EOF\n")
    out = tmp_path / "bundle"
    result = migrate_volume(volume, out, bundle_lid="urn:nasa:pds:fbirtfspec")
    label = etree.parse(str(out / "document" / "plain.xml")).getroot()
    assert label.findtext(f".//{PDS}document_standard_id") == "PDF"
    told = {finding_line(finding) for finding in result.validation}
    pdf = [line for line in told if "[PDS4-061]" in line]
    assert pdf == [f"{out / 'document' / 'plain.xml'}:{pdf[0].split(':')[1]}: error [PDS4-061] file_name: plain.pdf "
                   "is a PDF without PDF/A identification (no pdfaid:part in its XMP metadata): PDS archives "
                   "documents as PDF/A"]
    assert told == _findings_of_validate(out)


def test_a_volume_tells_what_each_product_description_overrode(tmp_path):
    """The products' own warnings (a keyword the bytes overrode) are told by the volume run too."""
    result = migrate_volume(DATA / "volume_gp0001", tmp_path / "bundle", bundle_lid="urn:nasa:pds:gp0001")
    descent = DATA / "volume_gp0001" / "data" / "asi" / "descent.lbl"
    assert f"{descent}: OBJECT = TABLE (line 23): column ALTITUDE DATA_TYPE overridden by the bytes: '17.2910' in " \
           "record 1 is no ASCII_Integer, and every value of the column is a number: described as ASCII_Real" \
           in result.warnings
    assert len(result.refused) == 2 and all("does not end so" in refusal for refusal in result.refused)
