"""`pdsgen deliver` around every profile's products as the commands write them: by default
(PDS3 labels only) and with `--label both`, in each dialect the products have labels for.
Every file a label names travels with it (pointers, the FILE_NAME of COMPRESSED_FILE and
UNCOMPRESSED_FILE, description/structure/catalog files), and the delivery validates clean
with `pdsgen validate`; a file nothing claims is reported in one line, never placed silently."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from affine import Affine
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.synthetic import make_scene, write_geotiff

from helpers import elevation_array, write_raster
from hrsc_ax_tiles import dtm_group, map_group, tile_name, write_vicar

HRSC_SINUSOIDAL = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"
HRSC_GRID = Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0)
LAYOUT = {"AAREADME.TXT", "VOLDESC.CAT", "MD5SUMS.TXT", "DATA", "EXTRAS", "INDEX", "DOCUMENT", "CATALOG",
          "REVIEW.html",  # the review page (not in the manifest)
          "MD5SUMS.xml", "MISCELLANEOUS"}  # a bundle's manifest label and its collection


def _pdsgen(*args: object) -> tuple[int, str, str]:
    """A pdsgen command run in this process as the installed command runs it."""
    result = CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)
    return result.exit_code, result.stdout, result.stderr


def _ok(*args: object) -> str:
    code, out, err = _pdsgen(*args)
    assert code == 0, f"pdsgen {' '.join(map(str, args))}: {err}"
    return out


def _hirise(inputs: Path, out: Path, label: list[str]) -> None:
    scene = make_scene(width=120, height=160)
    dtm = write_geotiff(inputs / "dtm.tif", scene.elevation, scene.transform, scene.crs, None)
    ortho = write_geotiff(inputs / "ortho.tif", scene.reflectance, scene.transform, scene.crs, None)
    _ok("dtm", dtm, "-o", out, "--profile", "hirise", "--source-product-id", "PSP_008669_1705",
        "--source-product-id", "PSP_009025_1705", "--institution", "U", *label)
    _ok("ortho", ortho, "-o", out, "--profile", "hirise", "--observation-id", "PSP_008669_1705",
        "--source-dtm-id", "DTEEC_008669_1705_009025_1705_U01", *label)
    _ok("extras", *sorted(out.glob("*.IMG")), *sorted(out.glob("*.LBL")), "-o", out / "extras")


def _generic(inputs: Path, out: Path, label: list[str]) -> None:
    scene = make_scene(width=100, height=120)
    dtm = write_geotiff(inputs / "terrain.tif", scene.elevation, scene.transform, scene.crs, None)
    ortho = write_geotiff(inputs / "image.tif", scene.reflectance, scene.transform, scene.crs, None)
    _ok("dtm", dtm, "-o", out, *label)
    _ok("ortho", ortho, "-o", out, *label)


def _hrsc(inputs: Path, out: Path, label: list[str]) -> None:
    heights = write_raster(inputs / "h.tif", elevation_array(30, 40, seed=12), HRSC_SINUSOIDAL, HRSC_GRID)
    nadir = write_raster(inputs / "nadir.tif", np.linspace(0.02, 0.3, 30 * 40, dtype=np.float32).reshape(30, 40),
                         HRSC_SINUSOIDAL, HRSC_GRID)
    _ok("dtm", heights, "-o", out, "--profile", "hrsc", "--product-id", "h1234_0000", "--precision", "0.5", *label)
    _ok("ortho", nadir, "-o", out, "--profile", "hrsc", "--source-product-id", "H1234_0000_ND3", *label)


def _hrsc_ax(inputs: Path, out: Path, label: list[str]) -> None:
    pixel = 0.5
    name = tile_name(430, 8765, 40, pixel)
    rng = np.random.default_rng(3)
    group = map_group(430000.0, 8765000.0, pixel)
    dsm = write_vicar(inputs / f"{name}.dsm", rng.uniform(0, 50, (40, 40)).astype(np.float32),
                      {"MAP": group, "DIGITAL_TERRAIN_MODEL": dtm_group(0.0, 1.0, -500, 2000)})
    channels = [write_vicar(inputs / f"{name}.{c}", rng.integers(1, 256, (40, 40)).astype(np.uint8), {"MAP": group})
                for c in ("pan", "re", "gr", "bl")]
    _ok("dtm", dsm, "-o", out, "--profile", "hrsc-ax", *label)
    _ok("ortho", channels[0], "-o", out, "--profile", "hrsc-ax", *label)
    _ok("ortho", *channels[1:], "-o", out, "--profile", "hrsc-ax", *label)


PROFILES = {"hirise": _hirise, "generic": _generic, "hrsc": _hrsc, "hrsc-ax": _hrsc_ax}
# What each profile's products are, by the files a delivery's DATA/ must hold (PDS3 side).
DATA_FILES = {
    "hirise": {"DTEEC_008669_1705_009025_1705_U01.IMG", "PSP_008669_1705_RED_C_01_ORTHO.LBL",
               "PSP_008669_1705_RED_C_01_ORTHO.JP2", "JP2INFO.TXT"},
    "generic": {"TERRAIN.IMG", "IMAGE.LBL", "IMAGE.JP2"},
    "hrsc": {"h1234_0000_dt4.img", "h1234_0000_nd4.img"},
    "hrsc-ax": {"HRSCAX_430_8765_0_0X0_0KM_DEM.IMG", "HRSCAX_430_8765_0_0X0_0KM_PAN.LBL",
                "HRSCAX_430_8765_0_0X0_0KM_PAN.JP2", "HRSCAX_430_8765_0_0X0_0KM_RGB.LBL",
                "HRSCAX_430_8765_0_0X0_0KM_RGB.JP2", "JP2INFO.TXT"},
}


@pytest.fixture(scope="module", params=[[], ["--label", "both"]], ids=["default", "label-both"])
def label_form(request) -> list[str]:
    return request.param


@pytest.fixture(scope="module", params=list(PROFILES))
def products(request, label_form, tmp_path_factory) -> tuple[str, list[str], Path]:
    root = tmp_path_factory.mktemp(f"{request.param}-{'both' if label_form else 'pds3'}")
    (root / "in").mkdir()
    PROFILES[request.param](root / "in", root / "products", label_form)
    return request.param, label_form, root / "products"


def _validate_clean(delivery: Path) -> None:
    code, out, _ = _pdsgen("validate", delivery)
    assert code == 0, out
    assert " 0 error(s)" in out, out


def _delivered(delivery: Path) -> set[str]:
    return {p.name for p in (delivery / "DATA").iterdir()}


@pytest.mark.parametrize("dialect", ["--pds3", "--pds4", "--both"])
def test_every_profile_delivered_with_every_file_its_labels_name(products, dialect, tmp_path):
    profile, label_form, source = products
    out = tmp_path / "delivery"
    args = ("deliver", source, "-o", out, dialect, "--volume-id", "TEST_0001", "--bundle-lid", "urn:nasa:pds:test")
    # PDS3-only products in a bundle are migrated: a PDS4 label describes their unchanged files
    code, stdout, stderr = _pdsgen(*args)
    assert code == 0, stderr
    assert stderr == ""  # every file of the products is claimed: nothing to report
    if dialect != "--pds4":
        assert DATA_FILES[profile] <= _delivered(out)
    assert {p.name for p in out.iterdir()} <= LAYOUT | {p.name for p in out.glob("bundle_*.xml")}
    _validate_clean(out)


def test_demo_like_delivery_in_place_moves_the_orthoimage_with_its_label(tmp_path):
    """The products as `pdsgen demo` leaves them, delivered in place as a PDS3 volume: the JP2
    named only by COMPRESSED_FILE's FILE_NAME goes into DATA/ with its .LBL; the inputs, which
    no label names, stay where they are and are reported, one line each."""
    source = tmp_path / "demo"
    (source / "input").mkdir(parents=True)
    _hirise(source / "input", source, [])
    code, _, stderr = _pdsgen("deliver", source, "--pds3", "--volume-id", "X")
    assert code == 0, stderr
    assert not list(source.glob("*.JP2")) and (source / "DATA" / "PSP_008669_1705_RED_C_01_ORTHO.JP2").is_file()
    lines = stderr.splitlines()
    assert sorted(lines) == [f"warning: {source / 'input' / name}: no label names it and no Extras rule claims "
                             "it; left where it is, outside the layout" for name in ("dtm.tif", "ortho.tif")]
    _validate_clean(source)


def test_an_unclaimed_file_is_reported_and_not_delivered(tmp_path):
    source = tmp_path / "products"
    (tmp_path / "in").mkdir()
    _generic(tmp_path / "in", source, [])
    (source / "notes.txt").write_text("mine\n")
    code, stdout, stderr = _pdsgen("deliver", source, "-o", tmp_path / "out", "--pds3", "--volume-id", "X")
    assert code == 0
    assert stderr == f"warning: {source / 'notes.txt'}: no label names it and no Extras rule claims it; " \
                     "not delivered\n"
    assert not list((tmp_path / "out").rglob("notes.txt"))
    code, stdout, stderr = _pdsgen("deliver", source, "-o", tmp_path / "quiet", "--pds3", "--volume-id", "X", "-q")
    assert stdout == "" and "notes.txt" in stderr  # said even with --quiet


def _support_label(name: str, catalog: bool) -> str:
    lines = ["PDS_VERSION_ID = PDS3", "RECORD_TYPE = FIXED_LENGTH", "RECORD_BYTES = 8", "FILE_RECORDS = 2",
             f'PRODUCT_ID = "{name}"', f'^TABLE = "{name}.TAB"', '^DESCRIPTION = "TABLE_DESC.TXT"',
             *(['^DATA_SET_MAP_PROJECTION = "DSMAP.CAT"'] if catalog else []),
             "OBJECT = TABLE", "  INTERCHANGE_FORMAT = ASCII", "  ROWS = 2", "  ROW_BYTES = 8", "  COLUMNS = 1",
             '  ^STRUCTURE = "ROW.FMT"', "END_OBJECT = TABLE", "END"]
    return "\r\n".join(lines) + "\r\n"


def test_description_structure_and_catalog_files_travel_once_however_many_labels_share_them(tmp_path):
    source = tmp_path / "products"
    source.mkdir()
    for name in ("ONE", "TWO"):
        (source / f"{name}.LBL").write_text(_support_label(name, catalog=name == "ONE"), newline="")
        (source / f"{name}.TAB").write_bytes(b"     1\r\n     2\r\n")
    (source / "TABLE_DESC.TXT").write_text("What the tables hold.\r\n", newline="")
    (source / "ROW.FMT").write_text('OBJECT = COLUMN\r\n  NAME = "N"\r\n  DATA_TYPE = ASCII_INTEGER\r\n'
                                    "  START_BYTE = 1\r\n  BYTES = 6\r\nEND_OBJECT = COLUMN\r\nEND\r\n", newline="")
    (source / "DSMAP.CAT").write_text("PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\n"
                                      "OBJECT = DATA_SET_MAP_PROJECTION\r\n  DATA_SET_ID = \"X\"\r\n"
                                      "END_OBJECT = DATA_SET_MAP_PROJECTION\r\nEND\r\n", newline="")
    code, stdout, stderr = _pdsgen("deliver", source, "-o", tmp_path / "out", "--pds3", "--volume-id", "X")
    assert code == 0, stderr
    assert stderr == ""
    assert _delivered(tmp_path / "out") == {"ONE.LBL", "ONE.TAB", "TWO.LBL", "TWO.TAB", "TABLE_DESC.TXT", "ROW.FMT"}
    # a catalog file with a label of its own: in CATALOG/, where a reader looks for a catalog pointer's file
    assert [p.name for p in (tmp_path / "out" / "CATALOG").iterdir()] == ["DSMAP.CAT"]
    assert "2 data product(s)" in stdout  # DSMAP.CAT is the labels' catalog file, not a product
    rows = (tmp_path / "out" / "INDEX" / "INDEX.TAB").read_text().splitlines()
    assert [row.split(",")[1] for row in rows] == ['"DATA/ONE.LBL"', '"DATA/TWO.LBL"']
    _validate_clean(tmp_path / "out")
    code, stdout, stderr = _pdsgen("deliver", tmp_path / "out", "--pds3")  # again, on the delivery itself
    assert code == 0 and stderr == "" and "2 data product(s)" in stdout
    assert [p.name for p in (tmp_path / "out" / "CATALOG").iterdir()] == ["DSMAP.CAT"]
    _validate_clean(tmp_path / "out")


def test_a_directory_of_many_products_is_listed_once_not_once_per_label(tmp_path, monkeypatch):
    """Finding the files each label names lists the products' directory once for the whole scan:
    once per label made a delivery of N products in one directory take N^2 steps (4,000 tables:
    44 s instead of 3 s)."""
    import pdsgen.archive.scan as scan_module

    listed: list[Path] = []
    real = scan_module.directory_listing

    def counting(directory: Path) -> list[str]:
        listed.append(directory)
        return real(directory)

    monkeypatch.setattr(scan_module, "directory_listing", counting)
    source = tmp_path / "products"
    source.mkdir()
    for n in range(40):
        text = _support_label(f"T{n:02d}", catalog=False)
        (source / f"T{n:02d}.LBL").write_text(text.replace('^DESCRIPTION = "TABLE_DESC.TXT"\r\n', ""), newline="")
        (source / f"T{n:02d}.TAB").write_bytes(b"     1\r\n     2\r\n")
    (source / "ROW.FMT").write_text("END\r\n", newline="")
    found = scan_module.scan(source)
    assert len(found.products) == 40 and all(len(p.files) == 2 and p.support for p in found.products)
    assert listed.count(source) == 1, len(listed)
