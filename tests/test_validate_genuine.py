"""The validator on the genuine PDS3 labels of many missions in tests/data/genuine_pds3.

Every ERROR it reports there is listed and judged in FINDINGS.md (a genuine defect of the
label, or an artefact of the copy); a new error - a false one, or a real one no longer
caught - fails `test_errors_are_exactly_the_judged_ones`.
"""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

from pdsgen.validate import validate_paths

CORPUS = Path(__file__).parent / "data" / "genuine_pds3"
VERDICTS = {"genuine defect", "artefact of the copy"}
DATA_RULES = {"IMG-007", "IMG-008", "REC-002", "REC-006", "PTR-006", "PTR-005"}


@cache
def _report():
    return validate_paths([CORPUS])


def _rows(name: str) -> list[list[str]]:
    rows = []
    for line in (CORPUS / name).read_text().splitlines():
        if line.startswith("| `"):
            rows.append([cell.strip().strip("`") for cell in line.strip("|").split("|")])
    return rows


def _relative(path: str) -> str:
    return Path(path).relative_to(CORPUS).as_posix()


def test_corpus_is_genuine_labels_of_many_missions_with_provenance():
    rows = _rows("PROVENANCE.md")
    files = {p.relative_to(CORPUS).as_posix() for p in CORPUS.rglob("*") if p.is_file() and p.suffix != ".md"}
    assert len(rows) >= 195 and {r[0] for r in rows} == files
    assert all(re.fullmatch(r"[0-9a-f]{40}", r[3]) and "/" in r[2] and r[4] for r in rows)
    hosts = {r[1].upper().replace("_", " ") for r in rows} - {"-"}
    assert len(hosts) >= 45, hosts  # as the labels name them (several names for some missions)
    assert sum(p.stat().st_size for p in CORPUS.rglob("*")) < 3_000_000


# The keywords that name a label's mission or host; a value is a quoted string, a symbol or a set
_IDENTITY = re.compile(r"^[ \t]*(?:MISSION_NAME|INSTRUMENT_HOST_NAME|SPACECRAFT_NAME|INSTRUMENT_HOST_ID)"
                       r"[ \t]*=[ \t]*(\{[^}]*\}|\"[^\"]*\"|'[^']*'|\S+)", re.M)


def _identities(path: Path) -> set[str]:
    """The mission and host names a label gives, read with a regular expression of its own
    (not pdsgen's label reader, which the corpus is there to check)."""
    text = path.read_bytes()[:300_000].decode("latin-1")
    names = set()
    for value in _IDENTITY.findall(text):
        for quoted, single, bare in re.findall(r'"([^"]*)"|\'([^\']*)\'|([^\s{},"\']+)', value):
            names.add(" ".join((quoted or single or bare).split()).upper())
    return names - {""}


def test_the_mission_column_says_what_the_labels_say():
    """PROVENANCE's mission / host column is the label's own MISSION_NAME, INSTRUMENT_HOST_NAME,
    SPACECRAFT_NAME or INSTRUMENT_HOST_ID (each name of a set), or `-` for a label naming none;
    missions are counted by these names, not by the projects the files came from."""
    wrong = {}
    for row in _rows("PROVENANCE.md"):
        names = _identities(CORPUS / row[0])
        listed = {name.strip().upper().replace("_", " ") for name in row[1].split(",")}
        given = {name.replace("_", " ") for name in names}
        if (row[1] == "-" and names) or (row[1] != "-" and not listed <= given):
            wrong[row[0]] = (row[1], sorted(names))
    assert not wrong, wrong
    missions = set().union(*(_identities(CORPUS / row[0]) for row in _rows("PROVENANCE.md")))
    # missions none of the earlier corpora had, each named by a label of its own
    assert {"LUNAR PROSPECTOR", "PHOENIX", "ULYSSES", "INFRARED ASTRONOMICAL SATELLITE", "PHOBOS 2"} <= missions


def test_errors_are_exactly_the_judged_ones():
    judged = {(r[0], r[1]): r[2] for r in _rows("FINDINGS.md")}
    assert set(judged.values()) <= VERDICTS
    found = {(_relative(f.file), f.rule) for f in _report().findings if f.severity == "error"}
    assert found == set(judged), {"new (not in FINDINGS.md)": sorted(found - set(judged)),
                                  "gone (listed but not reported)": sorted(set(judged) - found)}


def test_no_check_fails_on_a_genuine_label():
    assert len(_report().files) == len(_rows("PROVENANCE.md"))
    assert not [f for f in _report().findings if "could not run" in f.message]


def test_label_only_copies_say_so_once_and_nothing_about_their_data():
    copies = {r[0] for r in _rows("PROVENANCE.md") if r[5].startswith("label part only")}
    by_file = {_relative(r.path): r.findings for r in _report().files}
    said = {name for name in copies if [f.rule for f in by_file[name]].count("PTR-008") == 1}
    assert len(said) >= 25  # attached labels cut from their data (the rest point to other files)
    # the source projects' own label-only copies (ALE's *_pds3.lbl) are recognised alike
    for name, findings in by_file.items():
        rules = [f.rule for f in findings]
        assert rules.count("PTR-008") <= 1 and not (set(rules) & DATA_RULES and "PTR-008" in rules), name


def test_mission_conventions_are_not_errors():
    """The issue's classes of false errors, each on a real label of the corpus."""
    by_file = {_relative(r.path): {f.rule: f for f in r.findings} for r in _report().files}
    dawn = by_file["ale/FC21A0038582_15170161546F6F_pds3.lbl"]
    assert "SET-002" not in dawn and dawn["SYNTAX-013"].severity == "warning"  # DESCRIPTION = "", ()
    assert by_file["isis3/MI_MAP_03_N51E124N50E125SC_cropped.lbl"]["SYNTAX-014"].severity == "warning"
    selene = by_file["ale/TC1S2B0_01_06691S820E0465_pds3.lbl"]["DICT-013"]
    assert selene.severity == "warning" and "pdscat1r102" in selene.message
    cassini = by_file["rms_data_projects/N1454725799_1.LBL"]  # -89.2 <DEGC> is inside 0..inf K
    assert "DICT-003" not in cassini
    voyager = by_file["pdsparser/C052079-2800R.LBL"]["FILE-006"]  # an SFDU-wrapped PDS2 label
    assert voyager.severity == "warning"
    viking = by_file["ale/f004a47_pds3.lbl"]  # nested SFDU segments, each closed by END
    assert not {"SYNTAX-005", "PTR-005"} & set(viking)
    magellan = by_file["arael/shgj180u_README.txt"]  # CCSD Z-class + marker-delimited K-class SFDU
    assert "FILE-006" not in magellan
    ctx = by_file["mwaldstein_pds3/P01_001330_1221_XN_57S223W.LBL"]  # HiROC CTX map, Mars ellipsoid
    assert "MAP-003" not in ctx and ctx["MAP-002"].severity == "warning"
    assert "local radius at CENTER_LATITUDE -55" in ctx["MAP-002"].message
    assert "local radius at CENTER_LATITUDE -55" in ctx["MAP-005"].message  # offsets fit on it too
    kaguya_mi = by_file["isis3/vis_cropped.img"]
    assert kaguya_mi["IMG-006"].severity == "warning"  # BAND SEQUENTIAL
    probe_software = by_file["galileo_probe/nfredr.lbl"]  # ^ASCII_DOCUMENT = {"NFREDR4.H", "NFREDR41.C"}
    assert not {"PTR-001", "PTR-008"} & set(probe_software)
    assert "PTR-001" not in by_file["deep_impact/sclk_correlation.lbl"]  # ^JPG_DOCUMENT = {two figures}
    phobos = by_file["phobos2/PAN1IRED.LBL"]  # SFDU-wrapped, PDS_VERSION_ID = PDS2 (Phobos 2, 1992)
    assert phobos["FILE-010"].severity == "warning" and "version 2" in phobos["FILE-010"].message


def test_a_version_other_than_pds2_or_pds3_stays_an_error(tmp_path):
    """Only PDS version 2 labels, which genuine archives hold, are let off with a warning."""
    for version, severity in (("PDS2", "warning"), ("PDS4", "error"), ("PDS", "error")):
        label = tmp_path / f"{version}.LBL"
        label.write_bytes(f"PDS_VERSION_ID = {version}\r\nRECORD_TYPE = STREAM\r\nEND\r\n".encode())
        found = [f for f in validate_paths([label]).findings if f.rule == "FILE-010"]
        assert [f.severity for f in found] == [severity], (version, found)
