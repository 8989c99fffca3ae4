"""Hostile schemas (issue 38, items 1, 4 and 5): a label under review must not turn the
validator against its host through the schemas it names, the downloads it asks for, or
a prolog long enough to hide its root.

Every case is made at test time: a canary file outside the delivery holding a unique
string, a secret in an environment variable, a listener on 127.0.0.1 that records every
request (a bounded server that stops by itself). Each asserts the observable: the canary
and the secret nowhere in any report format or stream, no request, no traceback.
"""

from __future__ import annotations

import http.server
import os
import re
import shutil
import subprocess
import sys
import threading
import time
import uuid
from pathlib import Path
from types import SimpleNamespace

import pytest

from pdsgen.validate import validate_paths
from pdsgen.validate.pds4 import download, schematron
from pdsgen.validate.pds4.catalog import SchemaCatalog, shipped_schema_dir
from pdsgen.validate.pds4.label_checks import validate_pds4

from helpers import small_pds4_dtm

pytestmark = pytest.mark.skipif(not schematron.available(), reason="needs saxonche")

SCH_NS = "http://purl.oclc.org/dsdl/schematron"
CORE_URL = "https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.xsd"
FORMATS = ("text", "json", "sarif", "github", "html")


@pytest.fixture(scope="module")
def product(tmp_path_factory):
    return small_pds4_dtm(tmp_path_factory.mktemp("security_schemas"), "SECURITY")


@pytest.fixture
def canary(tmp_path):
    """A file outside every delivery, holding a unique string; and a secret in the environment."""
    secret = f"CANARY{uuid.uuid4().hex}"
    outside = tmp_path / "outside"
    outside.mkdir()
    path = outside / "secret.txt"
    path.write_text(secret + "\n")
    return SimpleNamespace(path=path, text=secret, env_name="PDSGEN_TEST_SECRET", env_value=f"ENV{secret}")


class _Recorder(http.server.BaseHTTPRequestHandler):
    """Records every request; answers a schema (the core one) to any GET, or a redirect."""

    def do_GET(self) -> None:  # noqa: N802 - http.server's name
        self.server.requests.append(self.path)
        if self.server.redirect_to:
            self.send_response(302)
            self.send_header("Location", self.server.redirect_to + self.path)
            self.end_headers()
            return
        body = (shipped_schema_dir() / "1O00" / "PDS4_PDS_1O00.xsd").read_bytes()
        self.send_response(200)
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, *args) -> None:  # noqa: ANN002 - quiet
        pass


def _listener(redirect_to: str = ""):
    """A server on 127.0.0.1 that stops by itself after a minute, whatever the test does."""
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Recorder)
    httpd.requests = []
    httpd.redirect_to = redirect_to
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    stop = threading.Timer(60, httpd.shutdown)
    stop.daemon = True
    stop.start()
    httpd.url = f"http://127.0.0.1:{httpd.server_address[1]}"
    return httpd


@pytest.fixture
def listener():
    httpd = _listener()
    yield httpd
    httpd.shutdown()
    httpd.server_close()


def _place(product, directory: Path, text: str) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    shutil.copy(product.path.with_suffix(".img"), directory / product.path.with_suffix(".img").name)
    label = directory / product.path.name
    label.write_text(text, encoding="utf-8")
    return label


def _with_schematron(text: str, href: str) -> str:
    """The label with one more xml-model instruction naming a Schematron at `href`."""
    model = f'<?xml-model href="{href}" schematypens="{SCH_NS}"?>\n'
    return text.replace("<Product_", model + "<Product_", 1)


def _schematron(expression: str, context: str = "pds:Identification_Area") -> str:
    """A Schematron whose one assertion fails and quotes `expression` in its message."""
    return (f'<sch:schema xmlns:sch="{SCH_NS}" queryBinding="xslt2">'
            '<sch:ns prefix="pds" uri="http://pds.nasa.gov/pds4/pds/v1"/>'
            f'<sch:pattern><sch:rule context="{context}">'
            f'<sch:assert test="false()">QUOTED <sch:value-of select="{expression}"/></sch:assert>'
            '</sch:rule></sch:pattern></sch:schema>')


def _validate(*args, env_extra: dict | None = None, cwd: Path | None = None) -> list[subprocess.CompletedProcess]:
    """`pdsgen validate ARGS` in a fresh process, once per report format."""
    env = {**os.environ, **(env_extra or {})}
    return [subprocess.run([sys.executable, "-m", "pdsgen", "validate", "--format", fmt, *map(str, args)],
                           capture_output=True, text=True, timeout=120, env=env, cwd=cwd)
            for fmt in FORMATS]


def _assert_nothing_leaked(results, canary) -> None:
    for result in results:
        streams = result.stdout + result.stderr
        assert canary.text not in streams, streams[-2000:]
        assert "Traceback" not in streams, streams[-2000:]
        assert result.returncode in (0, 1), streams[-2000:]


# --- item 1: Schematron from an untrusted location is not loaded ------------------------------

HOSTILE_EXPRESSIONS = {
    "unparsed-text": "unparsed-text('{uri}')",
    "prefixed": "fn:unparsed-text('{uri}')",
    "comment before the parenthesis": "unparsed-text (: x :) ('{uri}')",
    "EQName": "Q{{http://www.w3.org/2005/xpath-functions}}unparsed-text('{uri}')",
    "function reference": "unparsed-text#1('{uri}')",
    "unparsed-text-lines": "string-join(unparsed-text-lines('{uri}'), ' ')",
    "doc of a text": "string(doc('{uri}'))",
    "function-lookup": "function-lookup(xs:QName('fn:unparsed-text'), 1)('{uri}')",
    "after a minus": "string(0 -unparsed-text-available('{uri}'))",
    "environment variable": "environment-variable('PDSGEN_TEST_SECRET')",
    "all environment variables": "string-join(available-environment-variables(), ' ')",
    "nested transform": "transform(map{{'stylesheet-location': '{uri}'}})?output",
    "json-doc": "string(json-doc('{uri}'))",
    "recursion (kills the engine)": "let $f := function($g) {{ $g($g) }} return $f($f)",
    "parse-xml with an entity": ("parse-xml('&lt;!DOCTYPE x [&lt;!ENTITY e SYSTEM \"{uri}\"&gt;]&gt;"
                                 "&lt;x&gt;&amp;e;&lt;/x&gt;')"),
}


@pytest.mark.parametrize("where", ["beside", "parent", "file-url"])
def test_a_schematron_the_label_names_outside_the_trusted_sources_is_not_loaded(product, canary, tmp_path, where):
    """A .sch beside the label, up a `../`, or named by a file:// URL is not compiled, and the
    finding says its rules were not checked; the canary it would read is in no format."""
    delivery = tmp_path / "delivery"
    sch_text = _schematron(f"unparsed-text('{canary.path.as_uri()}')")
    places = {"beside": (delivery / "evil.sch", "evil.sch"),
              "parent": (tmp_path / "evil.sch", "../evil.sch"),
              "file-url": (canary.path.parent / "evil.sch", (canary.path.parent / "evil.sch").as_uri())}
    sch_path, href = places[where]
    sch_path.parent.mkdir(parents=True, exist_ok=True)
    sch_path.write_text(sch_text)
    label = _place(product, delivery, _with_schematron(product.text, href))
    found = validate_pds4(label, labels_only=True)
    notes = [f.message for f in found if f.rule == "PDS4-002"]
    assert any("evil" in note and "not loaded" in note and "rules not checked" in note for note in notes), notes
    assert not any("QUOTED" in f.message for f in found)
    _assert_nothing_leaked(_validate("--labels-only", "--offline", label), canary)


@pytest.mark.parametrize("name", sorted(HOSTILE_EXPRESSIONS))
def test_a_schematron_given_with_schemas_that_reaches_outside_the_label_is_not_run(
        product, canary, tmp_path, listener, name, monkeypatch):
    """A mission dictionary given with --schemas is trusted to be PDS's kind of file, not to
    be harmless: an expression reading a file, the environment, the network or running a
    transform keeps the whole file from running, and says so."""
    monkeypatch.setenv(canary.env_name, canary.env_value)
    schemas = tmp_path / "delivery" / "schemas"
    schemas.mkdir(parents=True)
    for uri in (canary.path.as_uri(), f"{listener.url}/probe"):
        expression = HOSTILE_EXPRESSIONS[name].format(uri=uri)
        (schemas / "mission.sch").write_text(_schematron(expression.replace('"', "&quot;")))
        label = _place(product, tmp_path / "delivery", _with_schematron(product.text, "schemas/mission.sch"))
        found = validate_pds4(label, SchemaCatalog.build([schemas]), labels_only=True)
        notes = [f.message for f in found if f.rule == "PDS4-002" and "mission.sch" in f.message]
        assert len(notes) == 1 and "not run" in notes[0], [f.message for f in found]
        assert not any("QUOTED" in f.message or canary.text in f.message for f in found)
    assert listener.requests == []


def test_a_hostile_schematron_leaks_nothing_in_any_report_format(product, canary, tmp_path, listener):
    """Every hostile expression in one --schemas Schematron, in a context pattern too, run
    by the command in every report format: no canary, no secret, no request, no traceback."""
    schemas = tmp_path / "delivery" / "schemas"
    schemas.mkdir(parents=True)
    asserts = "".join(
        '<sch:assert test="false()">QUOTED <sch:value-of select="'
        + expression.format(uri=uri).replace('"', "&quot;") + '"/></sch:assert>'
        for expression in HOSTILE_EXPRESSIONS.values() for uri in (canary.path.as_uri(), f"{listener.url}/probe"))
    context = f"pds:Identification_Area[unparsed-text-available('{listener.url}/context')]"
    (schemas / "mission.sch").write_text(
        f'<sch:schema xmlns:sch="{SCH_NS}" queryBinding="xslt2"><sch:ns prefix="pds" '
        f'uri="http://pds.nasa.gov/pds4/pds/v1"/><sch:pattern><sch:rule context="{context}">{asserts}'
        "</sch:rule></sch:pattern></sch:schema>")
    label = _place(product, tmp_path / "delivery", _with_schematron(product.text, "schemas/mission.sch"))
    results = _validate("--labels-only", "--schemas", schemas, "--schema-cache", tmp_path / "cache", label,
                        env_extra={canary.env_name: canary.env_value})
    _assert_nothing_leaked(results, canary)
    text_report = next(r for r in results if r.args[5] == "text")
    assert "mission.sch not run" in text_report.stdout, text_report.stdout
    assert listener.requests == []


def test_a_rule_context_reaching_outside_the_label_is_not_run(product, tmp_path, listener):
    """A rule's context (an XSLT pattern, which may start with doc()) is checked too."""
    schemas = tmp_path / "delivery" / "schemas"
    schemas.mkdir(parents=True)
    (schemas / "mission.sch").write_text(_schematron("'x'", context=f"doc('{listener.url}/context')//pds:x"))
    label = _place(product, tmp_path / "delivery", _with_schematron(product.text, "schemas/mission.sch"))
    found = validate_pds4(label, SchemaCatalog.build([schemas]), labels_only=True)
    assert any(f.rule == "PDS4-002" and "mission.sch not run" in f.message for f in found)
    assert listener.requests == []


def test_a_schematron_given_with_schemas_still_runs_when_it_stays_inside_the_label(product, tmp_path):
    """A delivery's own schemas in a subdirectory of its tree, given with --schemas, still
    validate: a relative location inside the --schemas directory is loaded, its rule fires."""
    schemas = tmp_path / "delivery" / "schemas"
    schemas.mkdir(parents=True)
    (schemas / "mission.sch").write_text(_schematron("string(pds:logical_identifier)"))
    label = _place(product, tmp_path / "delivery", _with_schematron(product.text, "schemas/mission.sch"))
    found = validate_pds4(label, SchemaCatalog.build([schemas]), labels_only=True)
    assert any(f.rule == "PDS4-005" and "QUOTED urn:" in f.message for f in found), [f.message for f in found]
    assert not any(f.rule == "PDS4-002" for f in found)


def test_saxon_itself_opens_no_uri_should_an_expression_get_past_the_check(canary):
    """The second wall: the processor every Schematron runs in refuses file and http URIs."""
    processor = schematron._processor()
    sheet = ('<xsl:stylesheet xmlns:xsl="http://www.w3.org/1999/XSL/Transform" version="3.0">'
             f'<xsl:template match="/"><r><xsl:value-of select="unparsed-text(\'{canary.path.as_uri()}\')"/></r>'
             '</xsl:template></xsl:stylesheet>')
    executable = processor.new_xslt30_processor().compile_stylesheet(stylesheet_text=sheet)
    with pytest.raises(Exception) as raised:  # noqa: PT011 - saxonche's own error class
        executable.transform_to_string(xdm_node=processor.parse_xml(xml_text="<a/>"))
    assert canary.text not in str(raised.value)


def test_no_shipped_schematron_is_taken_for_a_hostile_one():
    """The check finds nothing to refuse in any Schematron pdsgen ships (every IM version,
    every discipline dictionary): genuine labels lose no rule."""
    catalog = SchemaCatalog.build()
    refused = {name: schematron.forbidden_calls(file) for name, file in catalog.files.items() if name.endswith(".sch")}
    assert len(refused) > 300
    assert {name: calls for name, calls in refused.items() if calls} == {}


# --- item 4: XML Schema from an untrusted location ------------------------------------------

def _hostile_xsd(canary_text: str) -> str:
    return ('<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema" '
            'targetNamespace="http://pds.nasa.gov/pds4/pds/v1" elementFormDefault="qualified">'
            '<xs:element name="Product_Observational"><xs:simpleType><xs:restriction base="xs:string">'
            f'<xs:enumeration value="{canary_text}"/></xs:restriction></xs:simpleType></xs:element></xs:schema>')


@pytest.mark.parametrize("where", ["beside", "parent", "file-url"])
def test_an_xml_schema_the_label_names_outside_the_trusted_sources_is_not_compiled(product, canary, tmp_path, where):
    delivery = tmp_path / "delivery"
    outside = canary.path.parent / "evil.xsd"
    outside.write_text(_hostile_xsd(canary.text))
    hrefs = {"beside": "evil.xsd", "parent": "../outside/evil.xsd", "file-url": outside.as_uri()}
    if where == "beside":
        delivery.mkdir(parents=True, exist_ok=True)
        shutil.copy(outside, delivery / "evil.xsd")
    label = _place(product, delivery, product.text.replace(CORE_URL, hrefs[where]))
    found = validate_pds4(label, labels_only=True, use_schematron=False)
    notes = [f.message for f in found if f.rule == "PDS4-002"]
    assert len(notes) == 1 and "evil" in notes[0] and "not loaded" in notes[0], [f.message for f in found]
    _assert_nothing_leaked(_validate("--labels-only", "--offline", label), canary)


def test_an_xml_schema_given_with_schemas_does_not_read_an_outside_entity(product, canary, tmp_path):
    """An XSD in a --schemas directory declaring an external entity on the canary: the
    entity is not read, and the canary is not quoted."""
    schemas = tmp_path / "delivery" / "schemas"
    schemas.mkdir(parents=True)
    xsd = _hostile_xsd("&e;").replace(
        "<xs:schema", f'<!DOCTYPE xs:schema [<!ENTITY e SYSTEM "{canary.path.as_uri()}">]>\n<xs:schema', 1)
    (schemas / "PDS4_PDS_9Z00.xsd").write_text(xsd)
    label = _place(product, tmp_path / "delivery", product.text.replace(CORE_URL, "schemas/PDS4_PDS_9Z00.xsd"))
    found = validate_pds4(label, SchemaCatalog.build([schemas]), labels_only=True, use_schematron=False)
    assert not any(canary.text in f.message for f in found)
    _assert_nothing_leaked(_validate("--labels-only", "--offline", "--schemas", schemas, label), canary)


def test_a_symlink_in_a_schemas_directory_leading_out_of_it_is_not_taken(product, canary, tmp_path):
    """A delivery's schema directory given with --schemas linking mission.sch to a file of
    the host: the link is not followed, the Schematron is reported not found."""
    schemas = tmp_path / "delivery" / "schemas"
    schemas.mkdir(parents=True)
    outside_sch = canary.path.parent / "real.sch"
    outside_sch.write_text(_schematron("'QUOTED-OUTSIDE'"))
    (schemas / "mission.sch").symlink_to(outside_sch)
    label = _place(product, tmp_path / "delivery", _with_schematron(product.text, "schemas/mission.sch"))
    found = validate_pds4(label, SchemaCatalog.build([schemas]), labels_only=True)
    assert any(f.rule == "PDS4-002" and "mission" in f.message and "not loaded" in f.message for f in found)
    assert not any("QUOTED" in f.message for f in found)


def test_an_xml_schema_given_with_schemas_imports_nothing_from_outside(product, canary, tmp_path, listener):
    """An XSD in --schemas importing a file:// outside the trusted directories, or a schema
    at 127.0.0.1: neither is read nor requested; the import is reported unresolved."""
    schemas = tmp_path / "delivery" / "schemas"
    schemas.mkdir(parents=True)
    outside = canary.path.parent / "evil.xsd"
    outside.write_text(_hostile_xsd(canary.text).replace("http://pds.nasa.gov/pds4/pds/v1", "urn:evil"))
    core = (shipped_schema_dir() / "1O00" / "PDS4_PDS_1O00.xsd").read_text()
    imports = (f'<xs:import namespace="urn:evil" schemaLocation="{outside.as_uri()}"/>'
               f'<xs:import namespace="urn:net" schemaLocation="{listener.url}/PDS4_NET_1O00.xsd"/>')
    core = re.sub(r"(<xs:schema\b[^>]*>)", lambda m: m[1] + imports, core, count=1)
    (schemas / "PDS4_PDS_9Z00.xsd").write_text(core)
    label = _place(product, tmp_path / "delivery", product.text.replace(CORE_URL, "schemas/PDS4_PDS_9Z00.xsd"))
    found = validate_pds4(label, SchemaCatalog.build([schemas], tmp_path / "cache", download=True),
                          labels_only=True, use_schematron=False)
    assert any(f.rule == "PDS4-003" and "evil.xsd" in f.message for f in found), [f.message for f in found]
    assert not any(canary.text in f.message for f in found)
    assert listener.requests == []


# --- item 4: downloads only from PDS's schema site over https, the cache keyed by URL -------

@pytest.mark.parametrize("url, expected", [
    ("http://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.xsd", "https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.xsd"),
    ("https://PDS.nasa.gov/pds4/mission/x/v1/PDS4_X_1O00_1000.sch",
     "https://pds.nasa.gov/pds4/mission/x/v1/PDS4_X_1O00_1000.sch"),
    ("http://127.0.0.1:8000/pds4/pds/v1/PDS4_PDS_1O00.xsd", None),
    ("http://localhost/PDS4_PDS_1O00.xsd", None),
    ("https://pds.nasa.gov.example.com/PDS4_PDS_1O00.xsd", None),
    ("https://evilpds.nasa.gov/PDS4_PDS_1O00.xsd", None),
    ("https://pds.nasa.gov@127.0.0.1/PDS4_PDS_1O00.xsd", None),
    ("https://user@pds.nasa.gov/PDS4_PDS_1O00.xsd", None),
    ("ftp://pds.nasa.gov/PDS4_PDS_1O00.xsd", None),
    ("https://pds.nasa.gov/pds4/%2E%2E", None),
    ("https://pds.nasa.gov/pds4/x%2F..", None),
    ("https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.xsd?x=1", None),
    ("https://pds.nasa.gov/pds4/pds/v1/..", None),
    ("https://[::1/PDS4_PDS_1O00.xsd", None),
])
def test_only_pds_schema_hosts_are_downloaded_from_and_over_https(url, expected):
    assert download.download_url(url) == expected


def _loopback_label(product, tmp_path, base_url: str) -> Path:
    text = product.text.replace(CORE_URL, f"{base_url}/pds4/pds/v1/PDS4_PDS_9Z00.xsd")
    return _place(product, tmp_path / "delivery", text)


def test_a_label_naming_another_host_makes_no_request(product, tmp_path, listener):
    """Without --offline, a schema at 127.0.0.1 (or any host but PDS's) is not fetched: the
    listener sees nothing, the finding says why."""
    label = _loopback_label(product, tmp_path, listener.url)
    for result in _validate("--labels-only", "--schema-cache", tmp_path / "cache", label):
        assert "Traceback" not in result.stderr and result.returncode in (0, 1)
    assert listener.requests == []
    found = validate_paths([label], schema_cache=tmp_path / "cache", download_schemas=True).findings
    notes = [f.message for f in found if f.rule == "PDS4-002"]
    assert len(notes) == 1 and "only over https from PDS's schema site" in notes[0]
    assert listener.requests == [] and not (tmp_path / "cache").exists()


@pytest.fixture
def loopback_is_pds(monkeypatch):
    """For the cache tests: the listener's host stands in for PDS's (over http)."""
    monkeypatch.setattr(download, "SCHEMA_HOSTS", ("127.0.0.1",))
    monkeypatch.setattr(download, "SCHEME", "http")


def test_the_cache_answers_only_the_url_it_was_fetched_from(product, tmp_path, listener, loopback_is_pds):
    """One host's file never answers for another's of the same name: after a download from
    one URL, a label naming the same file name elsewhere is not answered from the cache."""
    cache = tmp_path / "cache"
    label = _loopback_label(product, tmp_path, listener.url)
    assert validate_paths([label], schema_cache=cache, download_schemas=True).exit_code == 0
    assert len(listener.requests) == 1
    cached = [p for p in cache.rglob("PDS4_PDS_9Z00.xsd")]
    assert len(cached) == 1 and cached[0].parent != cache  # kept under its URL's key, not by name
    again = validate_paths([label], schema_cache=cache, download_schemas=False)  # the same URL: cached
    assert "PDS4-002" not in again.rule_ids()
    other = _place(product, tmp_path / "other", product.text.replace(
        CORE_URL, "http://127.0.0.2:1/pds4/pds/v1/PDS4_PDS_9Z00.xsd"))
    found = validate_paths([other], schema_cache=cache, download_schemas=False).findings
    assert [f.rule for f in found if f.rule.startswith("PDS4-00") and f.rule != "PDS4-007"] == ["PDS4-002"]


def test_a_cache_of_the_old_layout_keyed_by_name_is_not_trusted(product, tmp_path):
    """A file in the cache with a SHA256SUMS line from another host (the layout before this
    change, keyed by name) does not answer a label naming pds.nasa.gov."""
    cache = tmp_path / "cache"
    cache.mkdir()
    evil = _hostile_xsd("OLDCACHE").encode()
    (cache / "PDS4_PDS_9Z00.xsd").write_bytes(evil)
    import hashlib

    digest = hashlib.sha256(evil).hexdigest()
    (cache / "SHA256SUMS").write_text(f"{digest}  PDS4_PDS_9Z00.xsd  http://127.0.0.1:9/PDS4_PDS_9Z00.xsd\n"
                                      f"{digest}  PDS4_PDS_9Z00.xsd  https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_9Z00.xsd\n")
    label = _place(product, tmp_path / "delivery", product.text.replace(
        CORE_URL, "https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_9Z00.xsd"))
    found = validate_paths([label], schema_cache=cache, download_schemas=False).findings
    assert "PDS4-002" in {f.rule for f in found} and not any("OLDCACHE" in f.message for f in found)


def test_a_cached_file_without_its_recorded_digest_is_not_used(product, tmp_path, listener, loopback_is_pds):
    cache = tmp_path / "cache"
    label = _loopback_label(product, tmp_path, listener.url)
    assert validate_paths([label], schema_cache=cache, download_schemas=True).exit_code == 0
    (cache / "SHA256SUMS").write_text("")
    found = validate_paths([label], schema_cache=cache, download_schemas=False).findings
    assert "PDS4-002" in {f.rule for f in found}


def test_a_redirect_away_from_pds_hosts_is_not_followed(product, tmp_path, loopback_is_pds):
    """PDS's host (the listener, standing in) redirecting elsewhere: the other host gets no request."""
    elsewhere = _listener()
    try:
        monkey_other = elsewhere.url.replace("127.0.0.1", "127.0.0.3")
        redirecting = _listener(redirect_to=monkey_other)
        try:
            label = _loopback_label(product, tmp_path, redirecting.url)
            found = validate_paths([label], schema_cache=tmp_path / "cache", download_schemas=True).findings
            notes = [f.message for f in found if f.rule == "PDS4-002"]
            assert len(redirecting.requests) == 1 and elsewhere.requests == []
            assert len(notes) == 1 and "redirected away" in notes[0], notes
        finally:
            redirecting.shutdown()
            redirecting.server_close()
    finally:
        elsewhere.shutdown()
        elsewhere.server_close()


# --- item 5: detection reads the whole prolog -----------------------------------------------

def _broken_label(product) -> str:
    """The label with a 33-character md5 (an XML Schema error)."""
    return product.text.replace("<md5_checksum>", "<md5_checksum>0")


@pytest.mark.parametrize("name", ["label.xml", "label.lblx", "label.dat"])
def test_a_long_leading_comment_does_not_hide_a_label(product, tmp_path, name):
    """A PDS4 label whose root starts after 100 kB of comments is still found by a directory
    run and its errors reported: exit 1, not 0."""
    comment = "<!-- " + "padding " * 12_000 + "-->\n"
    text = re.sub(r"^(<\?xml[^>]*\?>\n)", lambda m: m[1] + comment * 2, _broken_label(product))
    assert text.index("<Product_") > 100_000
    delivery = tmp_path / "delivery"
    label = _place(product, delivery, text)
    label.rename(delivery / name)
    report = validate_paths([delivery], labels_only=True)
    assert report.exit_code == 1
    assert any(f.rule == "PDS4-004" and name in f.file for f in report.findings), report.findings
    result = subprocess.run([sys.executable, "-m", "pdsgen", "validate", "--labels-only", "--offline", delivery],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 1 and "PDS4-004" in result.stdout


@pytest.mark.parametrize("text", [
    '<?xml version="1.0"?>\n<!-- a comment never closed\n' + "x" * 200_000,
    '<?xml version="1.0"?>\n<?xml-model href="x.sch" never closed\n',
    '<!-- ' + "x" * 100 + "\n",
])
def test_an_xml_file_whose_root_cannot_be_found_is_reported(tmp_path, text):
    delivery = tmp_path / "delivery"
    delivery.mkdir()
    (delivery / "hidden.xml").write_text(text)
    report = validate_paths([delivery], labels_only=True)
    assert report.exit_code == 1
    assert [f.rule for f in report.findings if "hidden.xml" in f.file] == ["PDS4-001"]


def test_a_prolog_that_never_ends_is_decided_in_bounded_time(tmp_path):
    """A document type declaration of 100,000 comments that is never closed: detection
    stays linear (no regular-expression blow-up) and the file is reported."""
    delivery = tmp_path / "delivery"
    delivery.mkdir()
    (delivery / "hidden.xml").write_bytes(b'<?xml version="1.0"?>\n<!DOCTYPE x [' + b"<!--c-->" * 100_000)
    started = time.monotonic()
    report = validate_paths([delivery], labels_only=True)
    assert time.monotonic() - started < 30
    assert [f.rule for f in report.findings] == ["PDS4-001"]


def test_ordinary_xml_and_binary_files_in_a_delivery_are_still_passed_over(product, tmp_path):
    """Not every XML file is a label: one with another root, and binary data starting with
    '<', are not reported."""
    delivery = tmp_path / "delivery"
    _place(product, delivery, product.text)
    (delivery / "notes.xml").write_text('<?xml version="1.0"?>\n<!-- c -->\n<notes><n>x</n></notes>\n')
    (delivery / "data.img").write_bytes(b"<\x00\x01\x02" + bytes(range(256)) * 10)
    report = validate_paths([delivery], labels_only=True)
    assert len(report.files) == 1 and not [f for f in report.findings if "notes" in f.file or "data" in f.file]
