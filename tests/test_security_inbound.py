"""Hostile input through every door, round 2 (issue 48, inbound): each case from the command line
as a user would meet it - one line on stderr naming the file or URL, exit 2, nothing written
outside -o, no traceback.

Object keys come from a real S3 server (tests/s3_server.py); structured files are real TOML,
JSON, PVL, FIFOs and /dev/zero; the GeoJP2 box is written by hand, byte by byte, from the
GeoTIFF and JPEG 2000 specifications (not by pdsgen's writer).
"""

from __future__ import annotations

import json
import os
import struct
import uuid
from pathlib import Path

import pytest

from pdsgen.storage.containment import NAME_MAX

from helpers import ORIGINS, elevation_array, run_cli, small_pds4_dtm, write_raster


def _one_line(done, *named: str) -> str:
    """The one stderr line of a refused run (exit 2, no traceback), naming each of NAMED."""
    assert done.returncode == 2, (done.returncode, done.stdout, done.stderr)
    assert "Traceback" not in done.stderr and done.stderr.count("\n") == 1, done.stderr
    for name in named:
        assert name in done.stderr, done.stderr
    return done.stderr


# -- object keys: the s3:// staging takes every key through the containment rule ------------------

def _nothing_named(token: str, *roots: Path) -> None:
    """No file named TOKEN where the keys' climbs land: the file system's root, the temporary
    directory the staging directories are made in, the test's own directory."""
    for root in (Path("/"), Path("/tmp"), *roots):
        assert not (root / token).exists(), f"{token} written in {root}"


_HOSTILE_KEYS = {
    "climb": "set/../../../{token}",
    "absolute": "set//tmp/{token}",
    "climb-in-the-middle": "set/sub/../../../../{token}",
    "long-segment": "set/" + "a" * (NAME_MAX + 45),
    "dot-segment": "set/./{token}",
}


@pytest.mark.parametrize("case", sorted(_HOSTILE_KEYS))
def test_validate_of_a_prefix_refuses_a_key_no_tree_holds(s3_server, tmp_path, case):
    bucket = s3_server.new_bucket()
    token = f"ESCAPED-{uuid.uuid4().hex[:8]}"
    s3_server.put(bucket, "set/X.LBL", b"PDS_VERSION_ID = PDS3\r\nEND\r\n")
    key = _HOSTILE_KEYS[case].format(token=token)
    s3_server.put(bucket, key, b"written by an attacker\n")
    done = run_cli("validate", f"s3://{bucket}/set/")
    _one_line(done, f"s3://{bucket}/")
    _nothing_named(token, tmp_path)


def test_a_key_that_is_both_an_object_and_a_prefix_is_one_line(s3_server):
    bucket = s3_server.new_bucket()
    s3_server.put(bucket, "set/X.LBL", b"PDS_VERSION_ID = PDS3\r\nEND\r\n")
    s3_server.put(bucket, "set/DATA", b"an object\n")
    s3_server.put(bucket, "set/DATA/Y.LBL", b"PDS_VERSION_ID = PDS3\r\nEND\r\n")
    done = run_cli("validate", f"s3://{bucket}/set/")
    assert "is both an object and a prefix" in _one_line(done, f"s3://{bucket}/set/DATA")


def test_deliver_into_a_prefix_holding_a_climbing_key_changes_nothing(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    token = f"ESCAPED-{uuid.uuid4().hex[:8]}"
    s3_server.put(bucket, f"out/../../../{token}", b"x")
    products = tmp_path / "products"
    products.mkdir()
    done = run_cli("deliver", products, "-o", f"s3://{bucket}/out", "--label", "pds4",
                   "--bundle-lid", "urn:nasa:pds:demo")
    _one_line(done, f"s3://{bucket}/out/")
    _nothing_named(token, tmp_path)
    assert s3_server.keys(bucket) == [f"out/../../../{token}"]


# -- output directories and a previous delivery's links ----------------------------------------

@pytest.fixture(scope="module")
def pds4_products(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("pds4")
    small_pds4_dtm(root, "HOSTILE_DTM")
    return root / "good"


def test_deliver_to_a_symbolic_link_is_refused_and_the_link_kept(pds4_products, tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "keep.txt").write_text("kept")
    link = tmp_path / "LINK"
    link.symlink_to(elsewhere)
    done = run_cli("deliver", pds4_products, "-o", link, "--label", "pds4", "--bundle-lid", "urn:nasa:pds:demo")
    assert "symbolic link" in _one_line(done, str(link))
    assert link.is_symlink() and os.readlink(link) == str(elsewhere)
    assert sorted(p.name for p in elsewhere.iterdir()) == ["keep.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["LINK", "elsewhere"]  # no work directory left


def test_a_previous_deliverys_link_is_refused_never_copied(pds4_products, tmp_path):
    out = tmp_path / "delivery"
    first = run_cli("deliver", pds4_products, "-o", out, "--label", "pds4", "--bundle-lid", "urn:nasa:pds:demo")
    assert first.returncode == 0, first.stderr
    secret = tmp_path / "secret.txt"
    secret.write_text("SECRET-CONTENT\n")
    (out / ".released").symlink_to(secret)
    before = {p.relative_to(out).as_posix(): (p.read_bytes() if p.is_file() else None)
              for p in sorted(out.rglob("*")) if not p.is_symlink()}
    done = run_cli("deliver", pds4_products, "-o", out, "--label", "pds4")
    assert "symbolic link" in _one_line(done, str(out / ".released"))
    after = {p.relative_to(out).as_posix(): (p.read_bytes() if p.is_file() else None)
             for p in sorted(out.rglob("*")) if not p.is_symlink()}
    assert after == before  # nothing changed
    assert not any(b"SECRET-CONTENT" in (data or b"") for data in after.values())


def test_a_batch_migrate_job_in_place_is_refused(tmp_path):
    _label(tmp_path)
    manifest = tmp_path / "batch.toml"
    manifest.write_text('[[migrate]]\ninputs = ["X.LBL"]\nin_place = true\n')
    done = run_cli("batch", manifest, "-o", tmp_path / "out", "--dry-run")
    assert "in_place = true writes beside the job's input" in _one_line(done, str(manifest))
    assert not (tmp_path / "out").exists()


# -- structured input: one bounded reader ----------------------------------------------------

@pytest.fixture
def fifo(tmp_path) -> Path:
    path = tmp_path / "fifo.toml"
    os.mkfifo(path)
    return path


def _label(tmp_path: Path) -> Path:
    label = tmp_path / "X.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nEND\r\n")
    return label


def test_delivery_text_that_is_a_fifo_or_a_device_is_refused_without_waiting(tmp_path, fifo):
    products = tmp_path / "products"
    products.mkdir()
    for text, kind in ((fifo, "FIFO"), (Path("/dev/zero"), "device")):
        done = run_cli("deliver", products, "-o", tmp_path / "out", "--label", "pds4", "--text", text)
        assert kind in _one_line(done, str(text))
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("body, problem", [
    ("a = " + "[" * 5000 + "]" * 5000 + "\n", "nested deeper than"),
    ("[validate]\nx = " + "9" * 5000 + "\n", "integer longer than"),
    ("[validate\n", "not valid TOML"),
])
def test_a_hostile_configuration_is_one_line(tmp_path, body, problem):
    config = tmp_path / "pdsgen.toml"
    config.write_text(body)
    done = run_cli("validate", "--config", config, _label(tmp_path))
    assert problem in _one_line(done, str(config))


def test_a_baseline_or_manifest_on_a_device_or_fifo_is_refused(tmp_path, fifo):
    label = _label(tmp_path)
    for path in (Path("/dev/zero"), fifo):
        _one_line(run_cli("validate", "--baseline", path, label), str(path))
        _one_line(run_cli("batch", path, "-o", tmp_path / "out", "--dry-run"), str(path))
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name, body, problem", [
    ("deep.toml", "DATA_SET_ID = " + "[" * 3000 + "]" * 3000 + "\n", "nested deeper than"),
    ("big.toml", "DATA_SET_ID = " + "7" * 5000 + "\n", "integer longer than"),
    ("deep.lbl", "DATA_SET_ID = " + "(" * 3000 + ")" * 3000 + "\nEND\n", "nested deeper than"),
])
def test_a_hostile_params_file_is_one_line_and_writes_nothing(tmp_path, name, body, problem):
    params = tmp_path / name
    params.write_text(body)
    crs, transform = ORIGINS["equirectangular"]
    source = write_raster(tmp_path / "dtm.tif", elevation_array(8, 8), crs, transform)
    done = run_cli("dtm", source, "-o", tmp_path / "out", "--params", params)
    assert problem in _one_line(done, str(params))
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_dictionary_with_unterminated_objects_keeps_its_whole_ones(tmp_path):
    """The .full reader takes each object once: the whole one after thousands that never end
    is still read (their expression rescanned the file from each of them)."""
    dictionary = tmp_path / "local.full"
    whole = "OBJECT = ELEMENT_DEFINITION\n  NAME = MY_COUNT\n  GENERAL_DATA_TYPE = INTEGER\n" \
            "END_OBJECT = ELEMENT_DEFINITION\n"
    dictionary.write_text(whole + "OBJECT = GENERIC_OBJECT_DEFINITION\n  NAME = X\n" * 3000)
    label = tmp_path / "X.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nMY_COUNT = 12\r\nEND\r\n")
    done = run_cli("validate", "--dictionary", dictionary, label)
    assert "MY_COUNT" not in done.stdout and done.returncode in (0, 1), done.stdout + done.stderr


# -- counts checked against the bytes there -----------------------------------------------------

def _geotiff_claiming(count: int) -> bytes:
    """A little-endian classic TIFF whose one tag (ModelPixelScale, DOUBLE) claims COUNT values."""
    header = b"II" + struct.pack("<HI", 42, 8)
    entry = struct.pack("<HHII", 33550, 12, count, 26)
    return header + struct.pack("<H", 1) + entry + struct.pack("<I", 0) + struct.pack("<3d", 1.0, 1.0, 0.0)


def test_a_geotiff_tag_claiming_more_values_than_its_bytes_is_refused():
    from pdsgen.errors import InputError
    from pdsgen.formats.geojp2 import tiff_tags

    assert tiff_tags(_geotiff_claiming(3))[33550] == (1.0, 1.0, 0.0)  # the same bytes, honest
    with pytest.raises(InputError, match="TIFF tag 33550 declares 4294967295 x 8 bytes"):
        tiff_tags(_geotiff_claiming(2**32 - 1), "x.jp2")


def test_validate_of_a_jp2_whose_geotiff_tag_claims_2_to_the_32_values(tmp_path):
    """The GeoJP2 box of a small ortho, its ModelTiepoint count set to 2^32 - 1 in place (the
    TIFF directory read by hand, as the GeoTIFF specification lays it out): validate reads the
    box with its own walk, refuses the count against the box's bytes and reports the malformed
    box (GEO-007, an error of its own since issue 48's follow-up: not "no GeoJP2 box") - the
    general JP2 reader it used allocated the count while opening the file (12.6 GB for a 10 kB
    file)."""
    from pdsgen import write_ortho
    from pdsgen.validate.geojp2 import GEOJP2_UUID

    crs, transform = ORIGINS["equirectangular"]
    data = (elevation_array(45, 61) % 200 + 5).astype("uint8")
    product = write_ortho(write_raster(tmp_path / "in.tif", data, crs, transform), tmp_path / "out", bits=8)
    jp2 = bytearray(product.jp2_path.read_bytes())
    at = jp2.index(GEOJP2_UUID.bytes) + 16
    order = "<" if jp2[at:at + 2] == b"II" else ">"
    (ifd,) = struct.unpack_from(order + "I", jp2, at + 4)
    (count,) = struct.unpack_from(order + "H", jp2, at + ifd)
    entries = [at + ifd + 2 + 12 * i for i in range(count)]
    tiepoint = next(e for e in entries if struct.unpack_from(order + "H", jp2, e)[0] == 33922)
    struct.pack_into(order + "I", jp2, tiepoint + 4, 2**32 - 1)
    product.jp2_path.write_bytes(bytes(jp2))
    done = run_cli("validate", product.label_path)
    assert done.returncode == 1 and done.stderr == "", done.stderr  # no traceback, no warning of a reader
    assert "[GEO-007]" in done.stdout and "TIFF tag 33922 declares 4294967295 x 8 bytes" in done.stdout


def test_an_index_row_bytes_of_ten_to_the_fifteen_is_refused_before_reading(tmp_path):
    """migrate's reader of a volume's index read one row of ROW_BYTES at once (a MemoryError)."""
    from pdsgen.errors import InputError
    from pdsgen.migrate.volume_index import find_index

    index = tmp_path / "INDEX"
    index.mkdir()
    (index / "INDEX.TAB").write_bytes(b'"DATA/X.LBL                    "\r\n' * 4)
    (index / "INDEX.LBL").write_bytes(
        b"PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 34\r\nFILE_RECORDS = 4\r\n"
        b"^INDEX_TABLE = \"INDEX.TAB\"\r\nOBJECT = INDEX_TABLE\r\n  INTERCHANGE_FORMAT = ASCII\r\n  ROWS = 4\r\n"
        b"  COLUMNS = 1\r\n  ROW_BYTES = 1000000000000000\r\n  OBJECT = COLUMN\r\n"
        b"    NAME = FILE_SPECIFICATION_NAME\r\n    DATA_TYPE = CHARACTER\r\n    START_BYTE = 2\r\n    BYTES = 30\r\n"
        b"  END_OBJECT = COLUMN\r\nEND_OBJECT = INDEX_TABLE\r\nEND\r\n")
    with pytest.raises(InputError, match="ROW_BYTES declares 1 x 1000000000000000 bytes.* only 136 bytes"):
        find_index(tmp_path, index)


def test_a_degenerate_pixel_is_one_line_in_extras(tmp_path):
    crs, _ = ORIGINS["equirectangular"]
    from rasterio.transform import Affine

    source = write_raster(tmp_path / "dtm.tif", elevation_array(8, 8), crs, Affine(1e-300, 0, 0, 0, -1e-300, 0))
    done = run_cli("extras", source, "-o", tmp_path / "out")
    assert "no usable size" in _one_line(done)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_manifest_naming_files_outside_the_delivery_is_reported_not_read(pds4_products, tmp_path):
    """MD5SUMS.TXT lines are names from the delivery: one climbing out, an absolute device (reading
    /dev/zero never ends) and one through a link leading out are findings, never opened."""
    out = tmp_path / "delivery"
    made = run_cli("deliver", pds4_products, "-o", out, "--label", "pds4", "--bundle-lid", "urn:nasa:pds:demo")
    assert made.returncode == 0, made.stderr
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "secret.txt").write_text("SECRET\n")
    (out / "away").symlink_to(tmp_path / "outside")
    with open(out / "MD5SUMS.TXT", "a", encoding="utf-8") as manifest:
        for name in ("../outside/secret.txt", "/dev/zero", "away/secret.txt"):
            manifest.write(f"{'0' * 32}  {name}\r\n")
    done = run_cli("validate", "--format", "json", out)
    assert done.returncode == 1 and done.stderr == "", done.stderr
    messages = [f["message"] for report in json.loads(done.stdout)["files"]
                for f in report["findings"] if f["rule"] == "DLV-020"]
    for name in ("../outside/secret.txt", "/dev/zero", "away/secret.txt"):
        assert any(m.startswith(f"{name!r} is not a file inside the delivery") for m in messages), messages
