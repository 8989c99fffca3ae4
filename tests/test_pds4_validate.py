"""PDS4 validation: seeded defects in a label pdsgen wrote are caught by the rule that owns
them; a schema import that cannot be resolved fails loudly; a label of an IM version that
is not shipped gets one clear finding; the CLI takes PDS4 labels beside PDS3 ones."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from pdsgen import write_dtm, write_ortho
from pdsgen.validate import validate_paths
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.catalog import SchemaCatalog, shipped_schema_dir
from pdsgen.validate.pds4.data_checks import constant_value
from pdsgen.validate.pds4.label_checks import validate_pds4

from helpers import ORIGINS, elevation_array, run_cli, stated_keywords, write_raster

needs_saxon = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")


@pytest.fixture(scope="module")
def product(tmp_path_factory):
    root = tmp_path_factory.mktemp("pds4_validate")
    crs, transform = ORIGINS["sinusoidal"]
    data = elevation_array(30, 40, seed=9)
    data[2, 2] = -9999.0
    source = write_raster(root / "dtm.tif", data, crs, transform, nodata=-9999.0)
    written = write_dtm(source, root / "good", product_id="SEEDED", label="pds4", params=stated_keywords())
    return SimpleNamespace(path=written.pds4_label_path, text=written.label_text)


def _copy(product, tmp_path, edit=None, data_edit=None):
    """A copy of the product in tmp_path with its label text (and data bytes) edited."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    data = tmp_path / product.path.with_suffix(".img").name
    shutil.copy(product.path.with_suffix(".img"), data)
    text = product.text
    if edit:
        changed = edit(text)
        assert changed != text, "the seeded defect did not change the label"
        text = changed
    if data_edit:
        raw = bytearray(data.read_bytes())
        data_edit(raw)
        data.write_bytes(bytes(raw))
    label = tmp_path / product.path.name
    label.write_text(text, encoding="utf-8")
    return label


def _rules(label, **kwargs) -> set[str]:
    return {f.rule for f in validate_pds4(label, **kwargs)}


def test_label_as_written_has_no_findings(product):
    assert validate_pds4(product.path) == []


def test_wrong_file_size_is_caught(product, tmp_path):
    label = _copy(product, tmp_path, lambda t: re.sub(r'(<file_size unit="byte">)(\d+)', r"\g<1>1\2", t))
    assert _rules(label) == {"PDS4-011"}


def test_wrong_md5_is_caught(product, tmp_path):
    label = _copy(product, tmp_path, data_edit=lambda raw: raw.__setitem__(slice(0, 1), b"\x00"))
    assert "PDS4-012" in _rules(label)


def test_changed_missing_constant_is_caught(product, tmp_path):
    label = _copy(product, tmp_path, lambda t: t.replace("<missing_constant>-3.4028226550889045E+38<",
                                                         "<missing_constant>-9999.0<"))
    found = validate_pds4(label)
    assert {f.rule for f in found} == {"PDS4-022"}  # the NULL samples are no longer declared
    assert "1 samples" in found[0].message


def test_special_constant_outside_the_data_type_is_caught(tmp_path):
    crs, transform = ORIGINS["equirectangular"]
    source = write_raster(tmp_path / "o.tif", np.full((8, 9), 7, dtype="uint8"), crs, transform)
    label = write_ortho(source, tmp_path / "out", product_id="BYTE_ORTHO", bits=8, label="pds4",
                        params=stated_keywords()).pds4_label_path
    label.write_text(label.read_text().replace("<missing_constant>0<", "<missing_constant>-1<"))
    assert _rules(label) == {"PDS4-023"}


def test_removed_cart_field_is_caught_by_the_schema(product, tmp_path):
    label = _copy(product, tmp_path, lambda t: re.sub(r"\s*<cart:longitude_of_central_meridian[^\n]*", "", t))
    found = validate_pds4(label)
    assert {f.rule for f in found} >= {"PDS4-004"}
    assert any("longitude_of_central_meridian" in f.message for f in found)


@pytest.mark.parametrize("axis", ["x", "y"])
def test_upper_left_moved_by_one_pixel_is_caught(product, tmp_path, axis):
    def move(text):
        pattern = rf'(<cart:upperleft_corner_{axis} unit="m">)([-\d.]+)'
        return re.sub(pattern, lambda m: m.group(1) + repr(float(m.group(2)) + 5.0), text)  # 5 m = 1 px

    label = _copy(product, tmp_path, move)
    assert _rules(label) == {"PDS4-031"}


def _moved_maximum(step: float):
    return lambda t: re.sub(r"<maximum>([^<]+)<", lambda m: f"<maximum>{float(m.group(1)) + step!r}<", t)


def test_statistics_are_checked_against_the_data(product, tmp_path):
    """Valid samples beyond the stated maximum: an error; a maximum merely above the data
    (a rounded or generous bound, which NASA's validator does not check): a warning."""
    assert _rules(_copy(product, tmp_path / "below", _moved_maximum(-10.0))) == {"PDS4-020"}
    assert _rules(_copy(product, tmp_path / "above", _moved_maximum(+10.0))) == {"PDS4-024"}


def test_data_file_missing_and_truncated(product, tmp_path):
    label = _copy(product, tmp_path, data_edit=lambda raw: raw.__delitem__(slice(len(raw) - 8, None)))
    assert {"PDS4-011", "PDS4-012", "PDS4-013"} <= _rules(label)
    label.with_suffix(".img").unlink()
    assert _rules(label) == {"PDS4-010"}
    assert _rules(label, labels_only=True) == set()


@needs_saxon
def test_schematron_only_rule_is_caught(product, tmp_path):
    """The IM version value is free text to the XML Schema; only Schematron pins it."""
    label = _copy(product, tmp_path, lambda t: t.replace("<information_model_version>1.24.0.0<",
                                                         "<information_model_version>1.24.0.1<"))
    found = validate_pds4(label)
    assert {f.rule for f in found} == {"PDS4-005"}
    assert found[0].line is not None and "1.24.0.0" in found[0].message


def test_an_import_that_does_not_resolve_fails_loudly(product, tmp_path):
    """cart imports geom: without geom's schema, lxml would silently build a partial schema."""
    partial = tmp_path / "schemas"
    shutil.copytree(shipped_schema_dir() / "1O00", partial)
    (partial / "PDS4_GEOM_1O00_19A0.xsd").unlink()
    catalog = SchemaCatalog()
    catalog.add_dir(partial)
    found = validate_pds4(product.path, catalog, use_schematron=False)
    assert [f.rule for f in found] == ["PDS4-003"]
    assert "PDS4_GEOM_1O00_19A0.xsd" in found[0].message


@needs_saxon
def test_missing_dictionaries_are_reported_once_each_and_the_rest_is_checked(product, tmp_path):
    """IM 1.21 (1L00): its core schema is shipped, cart 1.9.9.9 and disp 1.5.9.9 (versions
    never released) are not. Each missing dictionary is one finding; the core XML Schema and
    Schematron still run (and find that information_model_version 1.24.0.0 is not 1L00's)."""
    label = _copy(product, tmp_path, lambda t: t.replace("1O00", "1L00").replace("_1970", "_1999")
                  .replace("_1510", "_1599"))
    found = validate_pds4(label, labels_only=True)
    missing = sorted(f.message.split()[1] for f in found if f.rule == "PDS4-002")
    assert missing == ["PDS4_CART_1L00_1999", "PDS4_DISP_1L00_1599"]
    assert all("--offline" in f.message and "--schemas" in f.message for f in found if f.rule == "PDS4-002")
    assert {f.rule for f in found} == {"PDS4-002", "PDS4-005"}
    assert any("1.21.0.0" in f.message for f in found if f.rule == "PDS4-005")


def test_unknown_version_is_one_finding_per_schema_file_stem(product, tmp_path):
    label = _copy(product, tmp_path, lambda t: t.replace("1O00", "1Z00"))
    found = validate_pds4(label, labels_only=True)
    assert [f.rule for f in found] == ["PDS4-002"] * 3
    assert any("PDS4_PDS_1Z00" in f.message and "XML Schema checks skipped" in f.message for f in found)


def test_without_saxon_one_warning_for_the_run(product, tmp_path, monkeypatch):
    for name in ("a", "b"):
        shutil.copytree(product.path.parent, tmp_path / name)
    monkeypatch.setattr(schematron, "available", lambda: False)
    report = validate_paths([tmp_path])
    notes = [f for r in report.files for f in r.findings if f.rule == "PDS4-007"]
    assert len(notes) == 1 and notes[0].severity == "warning"
    assert report.exit_code == 0


def test_cli_validates_pds4_labels_and_lists_their_rules(product, tmp_path):
    broken = _copy(product, tmp_path, lambda t: t.replace("<md5_checksum>", "<md5_checksum>0"))
    result = run_cli("validate", "--format", "json", str(broken))
    assert result.returncode == 1, result.stderr
    assert '"PDS4-004"' in result.stdout  # a 33-character md5 breaks its XML Schema pattern
    listing = run_cli("validate", "--list-rules").stdout
    assert "PDS4-031" in listing and "PDS4-002" in listing
    missing = run_cli("validate", "--schemas", str(tmp_path / "nope"), str(product.path))
    assert missing.returncode == 2 and "schema directory not found" in missing.stderr




def test_jp2_georeferencing_is_checked_against_cart(tmp_path):
    crs, transform = ORIGINS["equirectangular"]
    data = np.random.default_rng(2).integers(3, 250, (20, 24)).astype("uint8")
    source = write_raster(tmp_path / "o.tif", data, crs, transform)
    label = write_ortho(source, tmp_path / "out", product_id="GEO_ORTHO", bits=8, label="pds4",
                        params=stated_keywords()).pds4_label_path
    assert validate_pds4(label) == []
    moved = re.sub(r'(<cart:upperleft_corner_x unit="m">)([-\d.]+)',
                   lambda m: m.group(1) + repr(float(m.group(2)) - 1.0), label.read_text())
    label.write_text(moved)
    found = validate_pds4(label)
    assert {f.rule for f in found} == {"PDS4-031", "PDS4-040"}
    assert any("GeoJP2" in f.message and f.keyword == "upperleft_corner_x" for f in found)


def test_parallel_workers_give_the_same_findings(product, tmp_path):
    """Each worker process compiles its own schemas (Saxon is not shared across a fork)."""
    _copy(product, tmp_path, lambda t: t.replace("<md5_checksum>", "<md5_checksum>f"))
    shutil.copytree(product.path.parent, tmp_path / "good")
    one, two = validate_paths([tmp_path], jobs=1), validate_paths([tmp_path], jobs=2)
    assert [f.as_dict() for f in one.findings] == [f.as_dict() for f in two.findings]
    assert {f.rule for f in one.findings} - {"PDS4-007"} == {"PDS4-004", "PDS4-012"}  # 007: no Saxon here


@needs_saxon
def test_deprecated_element_is_a_warning_not_an_error(product, tmp_path):
    """PDS4_PDS_1O00.sch puts role="warning" on the rule for Axis_Array/unit (deprecated),
    not on its assert: the finding is a PDS4-006 warning, never a PDS4-005 error."""
    label = _copy(product, tmp_path, lambda t: re.sub(r"(<Axis_Array>\s*<axis_name>Line</axis_name>\s*"
                                                      r"<elements>\d+</elements>)", r"\1<unit>pixel</unit>", t))
    found = validate_pds4(label)
    assert [(f.rule, f.severity) for f in found] == [("PDS4-006", "warning")], [f.message for f in found]
    assert "deprecated" in found[0].message


def test_hexadecimal_special_constant_is_honoured(product, tmp_path):
    """0xFF7FFFFB is the float32 bit pattern of ISIS NULL (-3.4028226550889045E+38), the
    value the product declares in decimal: written in hex it flags the same samples."""
    label = _copy(product, tmp_path, lambda t: t.replace("<missing_constant>-3.4028226550889045E+38<",
                                                         "<missing_constant>0xFF7FFFFB<"))
    assert validate_pds4(label) == []
    assert constant_value("0xFF7FFFFB", np.dtype(">f4")) == float(np.float32(-3.4028226550889045e38))
    assert constant_value("0xFFFF", np.dtype("<i2")) == -1.0 and constant_value("0xFFFF", np.dtype(">u2")) == 65535
    assert np.isnan(constant_value("0x1FFFF", np.dtype("<i2")))  # too wide for the type: never storable


def test_hexadecimal_constant_too_wide_for_the_type_is_caught(tmp_path, product):
    label = _copy(product, tmp_path, lambda t: t.replace("<missing_constant>-3.4028226550889045E+38<",
                                                         "<missing_constant>0x1FF7FFFFB<"))
    assert "PDS4-023" in _rules(label, labels_only=True)


def test_lblx_labels_are_pds4_by_content(product, tmp_path):
    """.lblx (the PDS4 label extension) and any other name: recognised by content, so a
    directory of them validates as PDS4 (it was 'no PDS3 labels found')."""
    for name in ("a.lblx", "b.label"):
        _copy(product, tmp_path).rename(tmp_path / name)
    broken = tmp_path / "c.lblx"
    broken.write_text(product.text.replace("<md5_checksum>", "<md5_checksum>f"), encoding="utf-8")
    result = run_cli("validate", "--offline", "--format", "json", str(tmp_path))
    assert result.returncode == 1, result.stderr
    reports = {Path(r["path"]).name: {f["rule"] for f in r["findings"]} - {"PDS4-007"}
               for r in json.loads(result.stdout)["files"]}
    # the three labels describe one data file: the second and third say so (PDS4-060)
    assert reports == {"a.lblx": set(), "b.label": {"PDS4-060"}, "c.lblx": {"PDS4-004", "PDS4-012", "PDS4-060"}}
