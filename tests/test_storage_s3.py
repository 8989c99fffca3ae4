"""Products from and into an S3 bucket (a real S3 server on 127.0.0.1, tests/s3_server.py).

References outside pdsgen: the bucket's contents are fetched with boto3 (not pdsgen's
storage layer) and compared with the products the same command makes on local disk;
rasters are read back from the bucket through GDAL's own /vsis3/ by the system's
`gdalinfo`, configured only from the AWS variables as pdsgen translates them.
"""

from __future__ import annotations

import functools
import http.server
import io
import json
import os
import re
import socket
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from pdsgen.cli import main
from pdsgen.storage import S3Location, display, display_text, internal
from pdsgen.storage.locations import gdal_options

from helpers import ORIGINS, elevation_array, run_cli, write_raster

# What differs between two runs of the same product: when it was made.
_TIMES = re.compile(rb"(PRODUCT_CREATION_TIME|START_TIME|STOP_TIME|creation_date_time|modification_date|"
                    rb"Date\s*:|date_time)[^\r\n]*")


def _without_times(data: bytes) -> bytes:
    return _TIMES.sub(b"<time>", data)


def _local_tree(root: Path) -> dict[str, bytes]:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


def _same_products(remote: dict[str, bytes], local: dict[str, bytes]) -> None:
    assert sorted(remote) == sorted(local)
    for name in local:
        assert _without_times(remote[name]) == _without_times(local[name]), name


def _invoke(*args: str) -> str:
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return result.output


def _dtm_source(tmp_path: Path, lines: int = 24, samples: int = 20) -> Path:
    crs, transform = ORIGINS["equirectangular"]
    return write_raster(tmp_path / "dtm.tif", elevation_array(lines, samples, seed=5), crs, transform)


def _image_source(tmp_path: Path) -> Path:
    crs, transform = ORIGINS["equirectangular"]
    data = np.random.default_rng(2).integers(1, 255, (24, 32), dtype="uint8")
    return write_raster(tmp_path / "image.tif", data, crs, transform)


def _gdalinfo(path: str) -> dict:
    """The system's gdalinfo (GDAL's own build, not rasterio's) on PATH, with the GDAL
    configuration pdsgen derives from the AWS variables."""
    env = {**os.environ, **gdal_options()}
    result = subprocess.run(["gdalinfo", "-json", "-checksum", path], capture_output=True, text=True, env=env,
                            timeout=60)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def _same_raster(remote: str, local: Path) -> None:
    a, b = _gdalinfo(remote), _gdalinfo(str(local))
    assert a["size"] == b["size"] and a["geoTransform"] == b["geoTransform"]
    assert [band["checksum"] for band in a["bands"]] == [band["checksum"] for band in b["bands"]]


def test_locations_keep_one_internal_form():
    assert internal("s3://b/dir/x.tif") == "/vsis3/b/dir/x.tif" and display("/vsis3/b/dir/x.tif") == "s3://b/dir/x.tif"
    assert S3Location.parse("s3://b/dir/") == S3Location("b", "dir/") and S3Location.parse("/vsis3/b").key == ""
    assert internal("https://h/x.tif") == "/vsicurl/https://h/x.tif" and internal("rel/x.tif") == "rel/x.tif"
    assert display_text("/vsis3/b/k: no such object") == "s3://b/k: no such object"
    options = gdal_options({"AWS_ENDPOINT_URL": "http://127.0.0.1:9000", "AWS_DEFAULT_REGION": "eu-west-1"})
    assert options == {"AWS_S3_ENDPOINT": "127.0.0.1:9000", "AWS_HTTPS": "NO", "AWS_VIRTUAL_HOSTING": "FALSE",
                       "AWS_REGION": "eu-west-1"}
    # GDAL's own variables keep winning; AWS_ENDPOINT_URL_S3 before AWS_ENDPOINT_URL
    assert gdal_options({"AWS_ENDPOINT_URL_S3": "https://s3.example", "AWS_ENDPOINT_URL": "http://x",
                         "AWS_HTTPS": "NO"}) == {"AWS_S3_ENDPOINT": "s3.example", "AWS_VIRTUAL_HOSTING": "FALSE"}


def test_dtm_from_and_into_a_bucket_equals_the_local_product(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    source = _dtm_source(tmp_path)
    url = s3_server.put(bucket, "in/dtm.tif", source.read_bytes())
    output = _invoke("dtm", url, "-o", f"s3://{bucket}/out")
    # (its last line: a product made without a params file is warned about first, issue 44)
    assert output.splitlines()[-1].startswith(f"s3://{bucket}/out/DTM.IMG")
    _invoke("dtm", source, "-o", tmp_path / "local")
    _same_products(s3_server.tree(bucket, "out/"), _local_tree(tmp_path / "local"))
    _same_raster(f"/vsis3/{bucket}/out/DTM.IMG", tmp_path / "local" / "DTM.IMG")
    # GDAL's own form of the input is taken too; an existing product is refused, then replaced
    refused = run_cli("dtm", f"/vsis3/{bucket}/in/dtm.tif", "-o", f"s3://{bucket}/out")
    assert refused.returncode == 2 and refused.stderr.strip() == (
        f"pdsgen: error: s3://{bucket}/out/DTM.IMG: output exists; use --overwrite to replace it")
    _invoke("dtm", f"/vsis3/{bucket}/in/dtm.tif", "-o", f"s3://{bucket}/out", "--overwrite", "--label", "both")
    _invoke("dtm", source, "-o", tmp_path / "both", "--label", "both")
    _same_products(s3_server.tree(bucket, "out/"), _local_tree(tmp_path / "both"))


def test_mosaic_of_strips_in_a_bucket_equals_the_local_mosaic(s3_server, tmp_path):
    """Two overlapping strips read in place from the bucket, the mosaic uploaded when complete:
    the same bytes as the mosaic of the local strips (creation times aside)."""
    bucket = s3_server.new_bucket()
    crs, transform = ORIGINS["equirectangular"]
    strips = [write_raster(tmp_path / f"strip{i}.tif", elevation_array(20, 16, seed=i), crs,
                           transform @ transform.translation(10 * i, 6 * i)) for i in range(2)]
    urls = [s3_server.put(bucket, f"in/{s.name}", s.read_bytes()) for s in strips]
    options = ("--product-id", "SITE_MOSAIC", "--kind", "dtm", "--nodata", "-9999")
    output = _invoke("mosaic", *urls, "-o", f"s3://{bucket}/out", *options)
    assert output.startswith(f"s3://{bucket}/out/")
    _invoke("mosaic", *strips, "-o", tmp_path / "local", *options)
    _same_products(s3_server.tree(bucket, "out/"), _local_tree(tmp_path / "local"))
    _same_raster(f"/vsis3/{bucket}/out/SITE_MOSAIC.IMG", tmp_path / "local" / "SITE_MOSAIC.IMG")


def test_ortho_from_and_into_a_bucket_equals_the_local_product(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    source = _image_source(tmp_path)
    url = s3_server.put(bucket, "in/image.tif", source.read_bytes())
    _invoke("ortho", url, "-o", f"s3://{bucket}/out", "--product-id", "ORTHO_A")
    _invoke("ortho", source, "-o", tmp_path / "local", "--product-id", "ORTHO_A")
    # a second orthoimage adds its entry to the directory's JP2INFO.TXT, as on disk
    _invoke("ortho", url, "-o", f"s3://{bucket}/out", "--product-id", "ORTHO_B")
    _invoke("ortho", source, "-o", tmp_path / "local", "--product-id", "ORTHO_B")
    _same_products(s3_server.tree(bucket, "out/"), _local_tree(tmp_path / "local"))
    _same_raster(f"/vsis3/{bucket}/out/ORTHO_B.JP2", tmp_path / "local" / "ORTHO_B.JP2")


def test_extras_of_products_in_a_bucket_equal_the_local_extras(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    _invoke("dtm", _dtm_source(tmp_path, 48, 40), "-o", tmp_path / "products")
    for name, data in _local_tree(tmp_path / "products").items():
        s3_server.put(bucket, f"products/{name}", data)
    _invoke("extras", f"s3://{bucket}/products/DTM.IMG", "-o", f"s3://{bucket}/extras")
    _invoke("extras", tmp_path / "products" / "DTM.IMG", "-o", tmp_path / "extras")
    remote, local = s3_server.tree(bucket, "extras/"), _local_tree(tmp_path / "extras")
    assert sorted(remote) == sorted(local) and any(name.endswith(".jpg") for name in local)
    for name in local:
        if name.lower().endswith(".jpg"):
            assert remote[name] == local[name], name
    _same_products(remote, local)


def test_validate_a_prefix_as_a_directory(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    _invoke("dtm", _dtm_source(tmp_path), "-o", tmp_path / "products")
    (tmp_path / "products" / "BAD.LBL").write_bytes(b'PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nEND\r\n')
    for name, data in _local_tree(tmp_path / "products").items():
        s3_server.put(bucket, f"set/{name}", data)
    remote = CliRunner().invoke(main, ["validate", "--format", "json", f"s3://{bucket}/set/"])
    local = CliRunner().invoke(main, ["validate", "--format", "json", str(tmp_path / "products")])
    assert remote.exit_code == local.exit_code == 1
    found_remote = json.loads(remote.output)
    found_local = json.loads(local.output.replace(str(tmp_path / "products"), f"s3://{bucket}/set"))
    assert found_remote == found_local and f"s3://{bucket}/set/BAD.LBL" in remote.output
    single = CliRunner().invoke(main, ["validate", f"s3://{bucket}/set/DTM.IMG"])
    assert single.exit_code == 0, single.output


def _one_line(result, needle: str) -> None:
    assert result.returncode == 2, result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdsgen: error: ") and needle in lines[0], result.stderr


def test_bad_inputs_and_credentials_give_one_line_and_leave_no_object(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    source = _dtm_source(tmp_path, 256, 64)
    url = s3_server.put(bucket, "in/dtm.tif", source.read_bytes())
    truncated = s3_server.put(bucket, "in/truncated.tif", source.read_bytes()[: source.stat().st_size // 2])
    out = f"s3://{bucket}/out"
    _one_line(run_cli("dtm", truncated, "-o", out), f"{truncated}: cannot read the raster data")
    _one_line(run_cli("dtm", f"s3://{bucket}/in/missing.tif", "-o", out),
              f"s3://{bucket}/in/missing.tif: no such object")
    _one_line(run_cli("dtm", "s3://no-such-bucket-pdsgen/in/dtm.tif", "-o", out), "no such bucket")
    _one_line(run_cli("dtm", url, "-o", "s3://no-such-bucket-pdsgen/out"), "no such bucket")
    _one_line(run_cli("ortho", f"s3://{bucket}/in/missing.tif", "-o", out), "no such object")
    _one_line(run_cli("extras", f"s3://{bucket}/in/missing.IMG", "-o", out), "no such object")
    env = {**os.environ, "AWS_SECRET_ACCESS_KEY": "not-the-key"}
    wrong_key = subprocess.run([sys.executable, "-m", "pdsgen", "dtm", url, "-o", out],
                               capture_output=True, text=True, env=env, timeout=120)
    _one_line(wrong_key, "access denied")
    with socket.socket() as probe:  # a port nothing listens on
        probe.bind(("127.0.0.1", 0))
        closed = probe.getsockname()[1]
    env = {**os.environ, "AWS_ENDPOINT_URL": f"http://127.0.0.1:{closed}"}
    unreachable = subprocess.run([sys.executable, "-m", "pdsgen", "dtm", url, "-o", out], capture_output=True,
                                 text=True, env=env, timeout=120)
    _one_line(unreachable, f"{out}: cannot reach the S3 endpoint (http://127.0.0.1:{closed})")
    assert s3_server.keys(bucket) == ["in/dtm.tif", "in/truncated.tif"]


def _same_deliveries(remote: dict[str, bytes], url: str, local_root: Path) -> None:
    """The same delivery in the bucket and on disk; the review page names the delivery where
    it is - the bucket's URL, never a local copy of it - and is otherwise the same."""
    local = _local_tree(local_root)
    assert f"from <code>{url}</code>".encode() in remote["REVIEW.html"]
    made = re.compile(rb"Made by pdsgen \S+ at [0-9T:Z-]+")  # when the page was made
    remote["REVIEW.html"] = made.sub(b"", remote["REVIEW.html"].replace(url.encode(), b"ROOT"))
    local["REVIEW.html"] = made.sub(b"", local["REVIEW.html"].replace(str(local_root).encode(), b"ROOT"))
    # INDEX.TAB's PRODUCT_CREATION_TIME of a label that states none is its file's time (issue 44),
    # which a bucket's copy does not keep: the times (in the index and on the review page), and so
    # the index's MD5, are set aside
    for tree in (remote, local):
        tree["INDEX/INDEX.TAB"] = re.sub(rb'"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d"', b"<time>", tree["INDEX/INDEX.TAB"])
        tree["MD5SUMS.TXT"] = re.sub(rb"[0-9a-f]{32}(  INDEX/INDEX.TAB)", rb"<md5>\1", tree["MD5SUMS.TXT"])
        tree["REVIEW.html"] = re.sub(rb"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d", b"<time>", tree["REVIEW.html"])
    _same_products(remote, local)


def test_deliver_from_and_into_a_bucket_equals_the_local_delivery(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    _invoke("dtm", _dtm_source(tmp_path), "-o", tmp_path / "products", "--product-id", "DTM_A")
    _invoke("extras", tmp_path / "products" / "DTM_A.IMG", "-o", tmp_path / "products")
    for name, data in _local_tree(tmp_path / "products").items():
        s3_server.put(bucket, f"products/{name}", data)
    shown = _invoke("deliver", f"s3://{bucket}/products", "-o", f"s3://{bucket}/delivery", "--volume-id", "TEST_0001")
    assert f"CHECK    pdsgen validate s3://{bucket}/delivery" in shown
    _invoke("deliver", tmp_path / "products", "-o", tmp_path / "delivery", "--volume-id", "TEST_0001")
    _same_deliveries(s3_server.tree(bucket, "delivery/"), f"s3://{bucket}/delivery", tmp_path / "delivery")
    # a product added: brought up to date in the bucket as on disk, nothing stale left
    _invoke("dtm", _dtm_source(tmp_path), "-o", f"s3://{bucket}/products", "--product-id", "DTM_B")
    _invoke("dtm", _dtm_source(tmp_path), "-o", tmp_path / "products", "--product-id", "DTM_B")
    _invoke("deliver", f"s3://{bucket}/products", "-o", f"s3://{bucket}/delivery")
    _invoke("deliver", tmp_path / "products", "-o", tmp_path / "delivery")
    _same_deliveries(s3_server.tree(bucket, "delivery/"), f"s3://{bucket}/delivery", tmp_path / "delivery")
    checked = CliRunner().invoke(main, ["validate", f"s3://{bucket}/delivery/"])
    local = CliRunner().invoke(main, ["validate", str(tmp_path / "delivery")])
    assert checked.exit_code == local.exit_code
    assert checked.output.replace(f"s3://{bucket}/delivery", "ROOT") == \
        local.output.replace(str(tmp_path / "delivery"), "ROOT")


def test_a_delivery_publishes_its_index_and_manifest_last():
    from pdsgen.archive.layout import publication_rank

    names = ["MD5SUMS.TXT", "INDEX/INDEX.TAB", "DATA/DTM_A.IMG", "bundle_x.xml", "EXTRAS/DTM_A.browse.jpg",
             "VOLDESC.CAT", "DATA/collection_data_inventory.csv"]
    assert sorted(names, key=lambda name: (publication_rank(name), name)) == [
        "DATA/DTM_A.IMG", "EXTRAS/DTM_A.browse.jpg", "DATA/collection_data_inventory.csv", "INDEX/INDEX.TAB",
        "VOLDESC.CAT", "bundle_x.xml", "MD5SUMS.TXT"]


class _RangeHandler(http.server.SimpleHTTPRequestHandler):
    """A static web server that answers range requests (206), as GDAL's /vsicurl/ asks for."""

    def log_message(self, *args: object) -> None:
        pass

    def send_head(self):  # type: ignore[override]
        match = re.fullmatch(r"bytes=(\d+)-(\d*)", self.headers.get("Range", ""))
        path = Path(self.translate_path(self.path))
        if not match or not path.is_file():
            return super().send_head()
        data = path.read_bytes()
        first = int(match[1])
        last = min(int(match[2]) if match[2] else len(data) - 1, len(data) - 1)
        self.send_response(206)
        self.send_header("Content-Range", f"bytes {first}-{last}/{len(data)}")
        self.send_header("Content-Length", str(last - first + 1))
        self.send_header("Accept-Ranges", "bytes")
        self.end_headers()
        return io.BytesIO(data[first:last + 1])


def test_a_web_url_is_read_through_gdal(tmp_path):
    """An https:// or http:// input goes to GDAL's /vsicurl/ (range requests), here from a
    web server on 127.0.0.1."""
    (tmp_path / "site").mkdir()
    source = _dtm_source(tmp_path / "site")
    handler = functools.partial(_RangeHandler, directory=str(tmp_path / "site"))
    with http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler) as server:
        threading.Thread(target=server.serve_forever, daemon=True).start()
        try:  # pdsgen in its own process: GDAL holds this one's interpreter lock while it reads
            made = run_cli("dtm", f"http://127.0.0.1:{server.server_port}/dtm.tif", "-o", tmp_path / "web")
            missing = run_cli("dtm", f"http://127.0.0.1:{server.server_port}/no.tif", "-o", tmp_path / "none")
        finally:
            server.shutdown()
    assert made.returncode == 0, made.stderr
    _one_line(missing, f"http://127.0.0.1:{server.server_port}/no.tif: ")
    _invoke("dtm", source, "-o", tmp_path / "local")
    _same_products(_local_tree(tmp_path / "web"), _local_tree(tmp_path / "local"))


def test_a_large_product_is_uploaded_in_parts(s3_server, tmp_path, monkeypatch):
    """Above the multipart threshold (lowered to S3's smallest part, 5 MiB) the upload goes in
    parts: S3 gives such an object an ETag ending in -<number of parts>."""
    from pdsgen.storage import objects

    monkeypatch.setattr(objects, "MULTIPART_BYTES", 5 * 1024 * 1024)
    bucket = s3_server.new_bucket()
    source = _dtm_source(tmp_path, 1400, 1200)  # 6.7 MB of float32
    _invoke("dtm", source, "-o", f"s3://{bucket}/big")
    _invoke("dtm", source, "-o", tmp_path / "local")
    etag = s3_server.client.head_object(Bucket=bucket, Key="big/DTM.IMG")["ETag"]
    assert etag.strip('"').endswith("-2")
    assert s3_server.get(bucket, "big/DTM.IMG") == (tmp_path / "local" / "DTM.IMG").read_bytes()


@pytest.mark.parametrize("blocked", [("boto3",), ("boto3", "botocore")], ids=["boto3", "boto3+botocore"])
def test_without_the_s3_extra_one_line_says_what_to_install(tmp_path, blocked):
    """boto3 (and botocore, as in a plain `pip install pdsgen`) made unimportable in a fresh
    process: an s3:// OUTDIR or input needs it, and says so in one line."""
    for name in blocked:
        blocker = tmp_path / "blocker" / name
        blocker.mkdir(parents=True)
        (blocker / "__init__.py").write_text("raise ImportError('blocked for this test')\n")
    env = {**os.environ, "PYTHONPATH": str(tmp_path / "blocker")}
    def dtm(*args: object) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "pdsgen", "dtm", *map(str, args)],
                              capture_output=True, text=True, env=env, timeout=120)

    written = dtm(_dtm_source(tmp_path), "-o", "s3://b/out")
    assert written.returncode == 2
    assert written.stderr == "pdsgen: error: reading and writing s3:// needs boto3: pip install 'pdsgen[s3]'\n"
    # an input is still read through GDAL's /vsis3/ alone, which says in one line why it cannot be
    read = dtm("s3://b/in/dtm.tif", "-o", tmp_path / "out")  # (no credentials in this environment)
    assert read.returncode == 2 and read.stderr.startswith("pdsgen: error: s3://b/in/dtm.tif: ")
    assert read.stderr.count("\n") == 1 and not (tmp_path / "out").exists()
