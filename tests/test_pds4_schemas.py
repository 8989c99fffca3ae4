"""Where PDS4 schemas come from: --schemas directories (a path a label names, taken from its
directory, never the working directory), the shipped files and archives, the download
cache, and the label's URL (a local HTTP server on 127.0.0.1 stands in for pds.nasa.gov);
and what is said when one cannot be found. Hostile locations: test_security_schemas.py."""

from __future__ import annotations

import functools
import hashlib
import http.server
import json
import re
import shutil
import tarfile
import threading
from pathlib import Path
from types import SimpleNamespace

import pytest

from pdsgen.validate import validate_paths
from pdsgen.validate.pds4 import download, schematron
from pdsgen.validate.pds4.catalog import SchemaCatalog, packed_dir, packed_index, shipped_schema_dir
from pdsgen.validate.pds4.label_checks import validate_pds4

from helpers import small_pds4_dtm

CORE_URL = "https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.xsd"
CORE_SCH = "https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.sch"


@pytest.fixture(scope="module")
def product(tmp_path_factory):
    return small_pds4_dtm(tmp_path_factory.mktemp("pds4_schemas"), "SCHEMAS")


def _place(product, directory: Path, text: str) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    shutil.copy(product.path.with_suffix(".img"), directory / product.path.with_suffix(".img").name)
    label = directory / product.path.name
    label.write_text(text, encoding="utf-8")
    return label


def test_bare_schema_name_is_resolved_beside_the_label_not_in_the_working_directory(product, tmp_path,
                                                                                    monkeypatch):
    """xsi:schemaLocation names the core schema by a bare file name that no catalog knows
    (core.xsd beside the label, in a directory given with --schemas). A working directory
    holding a different core.xsd (one that declares nothing) must change nothing, and the
    schema must really be used: a 33-character md5 breaks its pattern."""
    text = product.text.replace(CORE_URL, "core.xsd").replace("<md5_checksum>", "<md5_checksum>0")
    label = _place(product, tmp_path / "label", text)
    shutil.copy(shipped_schema_dir() / "1O00" / "PDS4_PDS_1O00.xsd", label.parent / "core.xsd")
    decoy = tmp_path / "elsewhere"
    decoy.mkdir()
    (decoy / "core.xsd").write_text('<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema" '
                                    'targetNamespace="http://pds.nasa.gov/pds4/pds/v1"/>')
    results = []
    for cwd in (decoy, label.parent, tmp_path):
        monkeypatch.chdir(cwd)
        catalog = SchemaCatalog.build([label.parent])
        results.append([(f.rule, f.line, f.message) for f in validate_pds4(label, catalog, use_schematron=False)
                        if f.rule != "PDS4-012"])
    assert results[0] == results[1] == results[2]
    assert {rule for rule, _, _ in results[0]} == {"PDS4-004"}
    assert "md5_checksum" in results[0][0][2]


def test_bare_schema_name_missing_beside_the_label_is_reported_not_taken_from_the_working_directory(
        product, tmp_path, monkeypatch):
    label = _place(product, tmp_path / "label", product.text.replace(CORE_URL, "core.xsd"))
    shutil.copy(shipped_schema_dir() / "1O00" / "PDS4_PDS_1O00.xsd", tmp_path / "core.xsd")
    monkeypatch.chdir(tmp_path)
    found = validate_pds4(label, use_schematron=False)
    assert [f.rule for f in found] == ["PDS4-002"]
    assert "core" in found[0].message and "no schema of that name" in found[0].message


def test_a_schema_beside_the_label_is_not_loaded_without_schemas(product, tmp_path):
    """A schema file beside the label is the delivery's, not the user's: without --schemas
    naming its directory it is not loaded, and the finding says so."""
    label = _place(product, tmp_path / "label", product.text.replace(CORE_URL, "core.xsd"))
    shutil.copy(shipped_schema_dir() / "1O00" / "PDS4_PDS_1O00.xsd", label.parent / "core.xsd")
    found = validate_pds4(label, use_schematron=False)
    assert [f.rule for f in found] == ["PDS4-002"]
    assert "core" in found[0].message and "not loaded" in found[0].message


def test_label_without_a_usable_schematron_reference_is_warned(product, tmp_path):
    text = re.sub(r"<\?xml-model [^?]*\?>\n", "", product.text)
    assert "xml-model" not in text
    found = validate_pds4(_place(product, tmp_path / "none", text))
    assert [(f.rule, f.severity) for f in found] == [("PDS4-008", "warning")]
    # an xml-model that names the Schematron file with the wrong schematypens is no better
    wrong = product.text.replace('schematypens="http://purl.oclc.org/dsdl/schematron"',
                                 'schematypens="http://www.w3.org/2001/XMLSchema"')
    found = validate_pds4(_place(product, tmp_path / "wrong", wrong))
    assert [f.rule for f in found] == ["PDS4-008"] and "XMLSchema" in found[0].message


def test_packed_archives_hold_what_the_index_says():
    """Every packed schema decompresses to the SHA-256 recorded with its provenance, and
    the core schema of every IM version from 1.0.0.0 to 1.23 is among them."""
    index = packed_index()
    seen = {}
    for archive in sorted(packed_dir().glob("*.tar.xz")):
        with tarfile.open(archive, "r:xz") as tar:
            for info in tar:
                seen[info.name] = (archive.name, hashlib.sha256(tar.extractfile(info).read()).hexdigest())
    assert seen == {name: (entry["archive"], entry["sha256"]) for name, entry in index.items()}
    cores = {name[len("PDS4_PDS_"):-4] for name in index if re.fullmatch(r"PDS4_PDS_1\w{3}\.xsd", name)}
    assert {"1000", "1100", "1900", "1A00", "1B10", "1N00"} <= cores and len(cores) == 29
    assert all(f"PDS4_PDS_{code}.sch" in index for code in cores)
    assert sum(p.stat().st_size for p in packed_dir().glob("*.tar.xz")) < 1_800_000
    provenance = json.loads((packed_dir() / "index.json").read_text())
    assert provenance["repository"] == "sbn-psi/pds4-schema-files" and len(provenance["commit"]) == 40


NASA_CASES = Path(__file__).parent / "data" / "nasa_validate"


def test_every_version_of_the_discipline_dictionaries_is_shipped():
    """Not only IM 1.24's: labels name the dictionary version they were written with, from
    disp 1.3.0.1 (IM 1.3) onwards; the mission dictionaries are not shipped."""
    index = packed_index()
    for name in ("PDS4_DISP_1301.xsd", "PDS4_GEOM_1A10.sch", "PDS4_IMG_1E00_1800.xsd", "PDS4_PROC_1900.xsd",
                 "PDS4_PARTICLE_1O00_2020.xsd", "PDS4_NUCSPEC_1B00_1000.sch", "PDS4_RINGS_1G00_1B00.xsd",
                 "PDS4_CART_1B10_1931.xsd", "PDS4_MSN_SURFACE_1G00_1220.sch", "PDS4_SP_1A00.xsd"):
        assert name in index, name
        assert index[name]["path"].startswith("pds4/" + name.split("_")[1].lower()), index[name]
    assert not any(entry["path"].startswith("pds4/mission/") for entry in index.values())


@pytest.mark.parametrize("label", ["github1158/980226_046.xml", "github831/kplo.xml"])
def test_suite_labels_on_older_dictionaries_find_every_schema_offline(label):
    """Labels of NASA's validator suite (disp 1I00; disp, geom and img 1L00) are checked
    against every schema they name, with no download: no PDS4-002."""
    found = validate_pds4(NASA_CASES / label, labels_only=True)  # the default catalog never downloads
    assert "PDS4-002" not in {f.rule for f in found}, [f.message for f in found if f.rule == "PDS4-002"]


@pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")
def test_an_old_core_version_is_validated_from_the_shipped_archive(product, tmp_path):
    """A label on IM 1.11 (1B00) with only core classes: XML Schema and Schematron of 1B00
    run from the archive, and 1B00's own rule on information_model_version speaks."""
    text = re.sub(r'<\?xml-model href="https://pds.nasa.gov/pds4/(cart|disp)[^?]*\?>\n', "", product.text)
    text = text.replace("PDS4_PDS_1O00", "PDS4_PDS_1B00")
    found = validate_pds4(_place(product, tmp_path / "old", text), labels_only=True)
    assert "PDS4-002" not in {f.rule for f in found}
    assert any(f.rule == "PDS4-005" and "1.11.0.0" in f.message for f in found), [f.message for f in found]


# --- downloads ------------------------------------------------------------------------------


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args) -> None:  # noqa: ANN002 - keep the test output clean
        pass


@pytest.fixture
def server(tmp_path, monkeypatch):
    """A static HTTP server on 127.0.0.1 over tmp_path/www, as pds.nasa.gov/pds4/ is laid out
    (for these tests 127.0.0.1 over http stands in for PDS's schema site)."""
    monkeypatch.setattr(download, "SCHEMA_HOSTS", ("127.0.0.1",))
    monkeypatch.setattr(download, "SCHEME", "http")
    www = tmp_path / "www"
    (www / "pds4" / "pds" / "v1").mkdir(parents=True)
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(www)))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield SimpleNamespace(www=www, url=f"http://127.0.0.1:{httpd.server_address[1]}/pds4/pds/v1/")
    httpd.shutdown()
    httpd.server_close()


def _served_label(product, server, tmp_path) -> Path:
    """The product with its core schema named as PDS4_PDS_9Z00.xsd on the local server (a
    copy of 1O00's under a name no shipped catalog holds)."""
    shutil.copy(shipped_schema_dir() / "1O00" / "PDS4_PDS_1O00.xsd", server.www / "pds4/pds/v1/PDS4_PDS_9Z00.xsd")
    text = product.text.replace(CORE_URL, server.url + "PDS4_PDS_9Z00.xsd")
    return _place(product, tmp_path / "label", text)


def test_schema_is_downloaded_once_cached_hashed_and_listed(product, server, tmp_path, caplog):
    label = _served_label(product, server, tmp_path)
    cache = tmp_path / "cache"
    url = f"{server.url}PDS4_PDS_9Z00.xsd"
    with caplog.at_level("INFO", logger="pdsgen.validate"):
        assert validate_paths([label], schema_cache=cache, download_schemas=True).exit_code == 0
    assert f"downloaded {url}" in caplog.text
    place = f"{hashlib.sha256(url.encode()).hexdigest()[:16]}/PDS4_PDS_9Z00.xsd"  # keyed by the full URL
    cached = cache / place
    digest = hashlib.sha256(cached.read_bytes()).hexdigest()
    assert cached.read_bytes() == (shipped_schema_dir() / "1O00" / "PDS4_PDS_1O00.xsd").read_bytes()
    assert (cache / "SHA256SUMS").read_text() == f"{digest}  {place}  {url}\n"
    (server.www / "pds4/pds/v1/PDS4_PDS_9Z00.xsd").unlink()  # the server no longer has it: the cache answers
    caplog.clear()
    with caplog.at_level("INFO", logger="pdsgen.validate"):
        assert validate_paths([label], schema_cache=cache, download_schemas=False).exit_code == 0
    assert "downloaded http" not in caplog.text
    kept = sorted(p.relative_to(cache).as_posix() for p in cache.rglob("*") if p.is_file())
    assert kept == sorted([place, "SHA256SUMS"])


def test_offline_or_unreachable_schema_is_reported_and_the_rest_still_checked(product, server, tmp_path):
    label = _served_label(product, server, tmp_path)
    offline = validate_paths([label], schema_cache=tmp_path / "cache", download_schemas=False)
    found = [(f.rule, f.message) for f in offline.findings if f.rule != "PDS4-007"]
    assert [rule for rule, _ in found] == ["PDS4-002"] and "--offline" in found[0][1]
    assert not (tmp_path / "cache").exists()
    (server.www / "pds4/pds/v1/PDS4_PDS_9Z00.xsd").unlink()
    gone = validate_paths([label], schema_cache=tmp_path / "cache", download_schemas=True)
    found = [f.message for f in gone.findings if f.rule == "PDS4-002"]
    assert len(found) == 1 and "HTTP 404" in found[0]


def test_an_altered_cached_schema_is_not_used(product, server, tmp_path):
    label = _served_label(product, server, tmp_path)
    cache = tmp_path / "cache"
    assert validate_paths([label], schema_cache=cache, download_schemas=True).exit_code == 0
    next(cache.rglob("PDS4_PDS_9Z00.xsd")).write_text('<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema"/>')
    (server.www / "pds4/pds/v1/PDS4_PDS_9Z00.xsd").unlink()
    found = validate_paths([label], schema_cache=cache, download_schemas=False).findings
    assert [f.rule for f in found if f.rule != "PDS4-007"] == ["PDS4-002"]


def test_a_cached_schema_is_hashed_once_per_run_not_once_per_label(product, server, tmp_path, monkeypatch):
    label = _served_label(product, server, tmp_path)
    copies = []
    for number in range(3):
        copies.append(label.with_name(f"copy{number}.xml"))
        copies[-1].write_bytes(label.read_bytes())
    cache = tmp_path / "cache"
    assert validate_paths([label], schema_cache=cache, download_schemas=True).exit_code == 0
    from pdsgen.validate.pds4 import catalog

    hashed = []
    real = catalog.file_sha256
    monkeypatch.setattr(catalog, "file_sha256", lambda path: hashed.append(path) or real(path))
    report = validate_paths(copies, schema_cache=cache, download_schemas=False)
    assert len(report.files) == 3 and "PDS4-002" not in report.rule_ids()  # found in the cache, for each
    assert len(hashed) == 1


def test_a_download_that_is_not_xml_is_refused(product, server, tmp_path):
    label = _served_label(product, server, tmp_path)
    (server.www / "pds4/pds/v1/PDS4_PDS_9Z00.xsd").write_text("<html><body>Not found</p></html>")
    found = validate_paths([label], schema_cache=tmp_path / "cache", download_schemas=True).findings
    messages = [f.message for f in found if f.rule == "PDS4-002"]
    assert len(messages) == 1 and "not XML" in messages[0]
    assert not list((tmp_path / "cache").rglob("PDS4_PDS_9Z00.xsd"))


def test_readme_validating_pds4_examples_run_as_written(product, tmp_path):
    """README 'Validating PDS4': each command, on a delivery of pdsgen's own PDS4 products."""
    import os
    import shlex
    import subprocess
    import sys

    import docs_text
    body = docs_text.section("Validating PDS4")
    blocks = re.findall(r"```sh\n(.*?)```", body, re.S)
    examples = [line.split("#")[0] for block in blocks for line in block.splitlines() if line.startswith("pdsgen ")]
    assert len(examples) == 4
    for directory in ("delivery", "labels"):
        _place(product, tmp_path / directory, product.text)
    (tmp_path / "my_ldds").mkdir()
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "home-cache")}
    for example in examples:
        result = subprocess.run([sys.executable, "-m", "pdsgen", *shlex.split(example)[1:]], cwd=tmp_path,
                                capture_output=True, text=True, env=env, timeout=300)
        assert result.returncode == 0, (example, result.stdout, result.stderr)
        assert "1 file(s) checked: 0 error(s)" in result.stdout, example
