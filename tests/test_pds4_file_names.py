"""PDS4 file names are read from the parsed label, and `--root` reaches Document_File paths.

NASA's validate regression suite (NASA-PDS/validate @ df054fd, copied with provenance to
tests/data/nasa_validate, SOURCES.md):
- github1408: two valid products whose labels keep the same File_Area (naming vl0axrat.lbl)
  inside an XML comment - no file is described twice (NASA: no message);
- github349/valid/datasetgood.xml: a Document_File whose directory_path_name climbs to the sibling "01" folder, valid
  for NASA when the suite's tree is given.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from pdsgen.validate import validate_paths

CASES = Path(__file__).parent / "data" / "nasa_validate"


def _rules(paths: list[Path], rule: str, **options) -> list[tuple[str, str]]:
    report = validate_paths(paths, **{"labels_only": True, **options})
    return [(f.rule, Path(f.file).name) for f in report.findings if f.rule == rule]


def test_a_file_name_inside_a_comment_is_not_described(tmp_path):
    assert _rules([CASES / "github1408"], "PDS4-060") == []


def test_a_file_name_in_cdata_is_read(tmp_path):
    """The same data file named twice, once as CDATA: two labels describe it."""
    case = Path(shutil.copytree(CASES / "github1408", tmp_path / "github1408"))
    label = case / "tc_vl0axrat_table_delimited_valid.xml"
    text = label.read_text(encoding="utf-8")
    label.write_text(text.replace("<file_name>vl0axrat_delim_valid.tab</file_name>",
                                  "<file_name><![CDATA[vl0axrat_char_valid.tab]]></file_name>"), encoding="utf-8")
    assert _rules([case], "PDS4-060") == [("PDS4-060", label.name)]


def test_root_reaches_a_document_file_directory_path():
    label = CASES / "github349" / "valid" / "datasetgood.xml"
    assert _rules([label], "PDS4-064", labels_only=False) == [("PDS4-064", "datasetgood.xml")]  # outside its directory
    assert _rules([label], "PDS4-064", labels_only=False, root=CASES / "github349") == []
