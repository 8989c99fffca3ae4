"""SET rules: products in one directory agree with each other and come with their Extras."""

from __future__ import annotations

from pdsgen import write_dtm
from pdsgen.validate import validate_paths
from test_validate_support import make_dtm, resize_label_text

from helpers import ORIGINS, elevation_array, stated_keywords, write_raster


def _two_products(tmp_path, second_kind, related=True):
    """Two products in one directory; when related, the second names the first as its source
    (as an orthoimage names the DTM it was made on)."""
    out = tmp_path / "set"
    paths = []
    for i, kind in enumerate(("equirectangular", second_kind)):
        crs, transform = ORIGINS[kind]
        source = write_raster(tmp_path / f"in{i}.tif", elevation_array(20, 30, seed=i), crs, transform)
        sources = ["PRODUCT_0"] if related and i == 1 else ()
        paths.append(write_dtm(source, out, product_id=f"PRODUCT_{i}", source_product_ids=sources,
                               params=stated_keywords()).path)
    return out, paths


def _rules(report, severity=None):
    return {(f.rule, f.file.rsplit("/", 1)[-1]) for f in report.findings
            if severity is None or f.severity == severity}


def test_products_of_one_set_must_share_the_projection(tmp_path):
    out, paths = _two_products(tmp_path, "sinusoidal")
    report = validate_paths([out])
    assert ("SET-001", "PRODUCT_1.IMG") in _rules(report, "error")
    message = next(f.message for f in report.findings if f.rule == "SET-001")
    assert "MAP_PROJECTION_TYPE SINUSOIDAL vs EQUIRECTANGULAR" in message


def test_unrelated_products_of_one_directory_are_not_compared(tmp_path):
    """Real DATA/ folders keep unrelated products together (HRSC DT4s, each sinusoidal about
    its own longitude): only products that name each other are compared."""
    out, paths = _two_products(tmp_path, "sinusoidal", related=False)
    assert "SET-001" not in validate_paths([out]).rule_ids()


def test_a_set_needs_readme_and_browse_images(tmp_path):
    out, paths = _two_products(tmp_path, "equirectangular")
    report = validate_paths([out])
    assert "SET-001" not in report.rule_ids()
    warnings = _rules(report, "warning")
    assert ("SET-004", "PRODUCT_0.IMG") in warnings and ("SET-004", "PRODUCT_1.IMG") in warnings
    extras = out / "EXTRAS"
    extras.mkdir()
    (extras / "README.TXT").write_bytes(b"Extras\r\n")
    for pid in ("PRODUCT_0", "PRODUCT_1"):
        (extras / f"{pid}.browse.jpg").write_bytes(b"\xff\xd8\xff")
    assert validate_paths([out], strict=True).exit_code == 0


def test_source_product_reference_must_resolve(tmp_path):
    path = make_dtm(tmp_path, profile="hirise")
    (path.parent / "README.TXT").write_bytes(b"a delivery set\r\n")
    assert validate_paths([path.parent]).exit_code == 0
    resize_label_text(path, b"(PSP_008669_1705, PSP_009025_1705)", b"DTEEC_001234_1705_005678_1705_U01")
    errors = {f.rule: f.message for f in validate_paths([path.parent]).findings if f.severity == "error"}
    assert set(errors) == {"SET-003"} and "DTEEC_001234_1705_005678_1705_U01" in errors["SET-003"]
    (path.parent / "README.TXT").unlink()  # a lone product is no set: its sources may be elsewhere
    assert "SET-003" not in validate_paths([path.parent]).rule_ids()


def test_product_id_matches_file_name(tmp_path):
    path = make_dtm(tmp_path)
    renamed = path.with_name("SOMETHING_ELSE.IMG")
    path.rename(renamed)
    errors = {f.rule for f in validate_paths([renamed]).findings if f.severity == "error"}
    assert errors == {"SET-002"}


def test_demo_delivery_set_is_clean_and_complete(tmp_path):
    from pdsgen.demo import run_demo

    run_demo(tmp_path / "demo")
    report = validate_paths([tmp_path / "demo"], strict=True)
    names = sorted(r.path.rsplit("/", 1)[-1] for r in report.files)
    assert names == ["DTEEC_008669_1705_009025_1705_U01.IMG", "PSP_008669_1705_RED_C_01_ORTHO.LBL"]
    assert [f"{f.rule} {f.message}" for f in report.findings if f.severity != "info"] == []
    (tmp_path / "demo" / "extras" / "README.TXT").unlink()
    assert "SET-004" in validate_paths([tmp_path / "demo"]).rule_ids("warning")
    (tmp_path / "demo" / "DTEEC_008669_1705_009025_1705_U01.IMG").unlink()  # the ortho's source DTM
    finding = next(f for f in validate_paths([tmp_path / "demo"]).findings if f.rule == "SET-003")
    assert finding.severity == "error" and "DTEEC_008669_1705_009025_1705_U01" in finding.message


def _write(path, *lines: str):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(("\r\n".join(lines) + "\r\nEND\r\n").encode())
    return path


def _describes_nothing(report) -> set[str]:
    return {f.file.rsplit("/", 1)[-1] for f in report.findings if f.rule == "SET-005"}


def test_a_label_that_describes_nothing_is_reported(tmp_path):
    bare = _write(tmp_path / "BARE.LBL", "PDS_VERSION_ID = PDS3")
    report = validate_paths([bare])
    finding = next(f for f in report.findings if f.rule == "SET-005")
    assert finding.severity == "warning" and finding.line == 1
    assert "no data pointer" in finding.message
    assert report.exit_code == 0 and validate_paths([bare], strict=True).exit_code == 1
    # keywords and groups alone still describe no data; a catalog pointer is not a data pointer
    _write(tmp_path / "GROUPS.LBL", "PDS_VERSION_ID = PDS3", "PRODUCT_ID = GROUPS",
           "GROUP = TIME_PARAMETERS", "  START_TIME = 2020-01-01T00:00:00", "END_GROUP = TIME_PARAMETERS")
    _write(tmp_path / "CATPTR.LBL", "PDS_VERSION_ID = PDS3", '^DATA_SET_CATALOG = "DATASET.CAT"')
    # each of these describes something
    _write(tmp_path / "DETACHED.LBL", "PDS_VERSION_ID = PDS3", '^IMAGE = "DETACHED.IMG"')
    _write(tmp_path / "TABLE.LBL", "PDS_VERSION_ID = PDS3", "OBJECT = TABLE", "  ROWS = 1",
           "END_OBJECT = TABLE")
    _write(tmp_path / "JP2.LBL", "PDS_VERSION_ID = PDS3", "OBJECT = COMPRESSED_FILE",
           '  FILE_NAME = "X.JP2"', "END_OBJECT = COMPRESSED_FILE")
    _write(tmp_path / "INCLUDES.LBL", "PDS_VERSION_ID = PDS3", '^STRUCTURE = "OBJECTS.FMT"')
    report = validate_paths([tmp_path], labels_only=True)
    assert _describes_nothing(report) == {"BARE.LBL", "GROUPS.LBL", "CATPTR.LBL"}


def test_include_and_catalog_fragments_are_not_products(tmp_path):
    # named as format/catalog files, or included by another label of the run: fragments
    _write(tmp_path / "LABEL" / "COLUMNS.FMT", "PDS_VERSION_ID = PDS3", "ROW_BYTES = 8")
    _write(tmp_path / "CATALOG" / "DATASET.CAT", "PDS_VERSION_ID = PDS3", "DATA_SET_ID = X")
    _write(tmp_path / "LABEL" / "HEADER.LBL", "PDS_VERSION_ID = PDS3", "ROW_BYTES = 8")
    _write(tmp_path / "DATA" / "T.LBL", "PDS_VERSION_ID = PDS3", '^TABLE = "T.TAB"', "OBJECT = TABLE",
           '  ^STRUCTURE = "HEADER.LBL"', "END_OBJECT = TABLE")
    _write(tmp_path / "LABEL" / "ORPHAN.LBL", "PDS_VERSION_ID = PDS3", "ROW_BYTES = 8")
    assert _describes_nothing(validate_paths([tmp_path], labels_only=True)) == {"ORPHAN.LBL"}
    # alone, a .LBL fragment cannot be told from an empty product
    assert _describes_nothing(validate_paths([tmp_path / "LABEL"], labels_only=True)) == {
        "HEADER.LBL", "ORPHAN.LBL"}


def test_generated_products_describe_their_data(tmp_path):
    report = validate_paths([make_dtm(tmp_path)])
    assert "SET-005" not in report.rule_ids()
