"""Fetching a schema a label names from its URL into pdsgen's cache.

Only when the user allows it (not `--offline`), and only from PDS's own schema site:
a label naming `http://pds.nasa.gov/...` is fetched over https from that host, a label
naming any other host (loopback included) is fetched from nowhere, and a redirect may not
leave for another host. A download must parse as XML (an HTML error page is not a schema).

The cache is keyed by the full URL, never by file name alone: each download is kept as
`<cache>/<first 16 hex digits of the URL's SHA-256>/<file name>`, written under a temporary
name and renamed when complete, and its SHA-256 is appended to the cache's SHA256SUMS with
its place and the URL it came from. A cached file answers only the URL it was fetched from,
and only while it still has the SHA-256 recorded then.

The catalog (catalog.py) calls this module; this module knows nothing of the catalog
(the cache's SHA256SUMS name and the XML test live here, where downloads are written).
urllib is imported on the first download: most runs never fetch.
"""

from __future__ import annotations

import io
import re
from pathlib import Path
from urllib.parse import unquote, urlsplit, urlunsplit

from lxml import etree

from ... import __version__
from ...errors import PdsgenError
from ...formats.checksum import bytes_sha256
from ...storage.staging import staged_file

SUMS_NAME = "SHA256SUMS"  # in the cache: "<sha256>  <place>  <url>" per downloaded schema
SCHEMA_HOSTS = ("pds.nasa.gov",)  # and their subdomains: PDS's schema site
SCHEME = "https"
_SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*\.(?:xsd|sch)", re.IGNORECASE)
TIMEOUT_SECONDS = 30
MAX_BYTES = 64 * 1024 * 1024  # the largest PDS schema is a few MB


class DownloadError(PdsgenError):
    """A schema could not be fetched (network, HTTP status, not XML)."""


def download_url(url: str) -> str | None:
    """The URL a schema named by `url` may be fetched from: the same host and path over
    https when the host is PDS's schema site, else None (no request is ever made for it).
    The file name must look like a schema's (no `..`, no path hidden by %2F)."""
    try:
        parts = urlsplit(url)
        port = parts.port
    except ValueError:
        return None
    host = (parts.hostname or "").lower()
    trusted = any(host == h or host.endswith("." + h) for h in SCHEMA_HOSTS)
    if parts.scheme not in ("http", "https") or not trusted or parts.username or parts.password or parts.query:
        return None
    if not _SAFE_NAME.fullmatch(unquote(parts.path).rsplit("/", 1)[-1]):
        return None
    netloc = host if port in (None, 80, 443) else f"{host}:{port}"
    return urlunsplit((SCHEME, netloc, parts.path, "", ""))


def cache_place(url: str) -> str:
    """Where, relative to the cache, the download of `url` (a `download_url`) is kept."""
    name = unquote(urlsplit(url).path).rsplit("/", 1)[-1]
    return f"{bytes_sha256(url.encode('utf-8'))[:16]}/{name}"


def fetch_schema(url: str, cache_dir: Path) -> tuple[Path, str]:
    """Download `url` (a `download_url`) into the cache; its path and SHA-256."""
    import urllib.error
    import urllib.request

    if download_url(url) != url:
        raise DownloadError(url, f"not one of PDS's schema hosts over {SCHEME} ({', '.join(SCHEMA_HOSTS)})")
    opener = urllib.request.build_opener(_redirect_handler())
    request = urllib.request.Request(url, headers={"User-Agent": f"pdsgen/{__version__}"})
    try:
        with opener.open(request, timeout=TIMEOUT_SECONDS) as response:
            data = response.read(MAX_BYTES + 1)
    except urllib.error.HTTPError as exc:
        raise DownloadError(url, f"HTTP {exc.code}") from None
    except (urllib.error.URLError, OSError, ValueError) as exc:
        reason = getattr(exc, "reason", None) or exc
        raise DownloadError(url, str(reason)) from None
    if len(data) > MAX_BYTES:
        raise DownloadError(url, f"larger than {MAX_BYTES} bytes")
    if not is_xml(data):
        raise DownloadError(url, "the response is not XML")
    digest = bytes_sha256(data)
    place = cache_place(url)
    try:
        target = cache_dir / place
        target.parent.mkdir(parents=True, exist_ok=True)
        with staged_file(target) as part:  # .NAME.PID.part
            part.write_bytes(data)
        with open(cache_dir / SUMS_NAME, "a", encoding="utf-8") as sums:
            sums.write(f"{digest}  {place}  {url}\n")
    except OSError as exc:
        raise DownloadError(cache_dir, f"cannot write the schema cache: {exc.strerror or exc}") from None
    return target, digest


def _redirect_handler():  # noqa: ANN202 - a urllib handler made on the first download
    """A redirect handler that follows a redirect only to PDS's schema hosts over https."""
    import urllib.error
    import urllib.request

    class StayOnPdsHosts(urllib.request.HTTPRedirectHandler):
        def redirect_request(self, req, fp, code, msg, headers, newurl):  # noqa: ANN001, ANN202, PLR0913
            if download_url(newurl) != newurl:
                raise urllib.error.URLError(f"redirected away from PDS's schema hosts, to {newurl}")
            return super().redirect_request(req, fp, code, msg, headers, newurl)

    return StayOnPdsHosts()


def read_sums(cache_dir: Path) -> dict[str, tuple[str, str]]:
    """URL -> (place in the cache, SHA-256) of every download the cache's SHA256SUMS records
    (`digest  place  url` lines; a later line for a URL wins). A place that is not the one
    `cache_place` gives for its URL (a line of an older cache keyed by name) is not used."""
    sums: dict[str, tuple[str, str]] = {}
    try:
        text = (cache_dir / SUMS_NAME).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return sums
    for line in text.splitlines():
        fields = line.split()
        if len(fields) == 3 and download_url(fields[2]) == fields[2] and fields[1] == cache_place(fields[2]):
            sums[fields[2]] = (fields[1], fields[0])
    return sums


def is_xml(data: bytes) -> bool:
    """Whether bytes parse as XML (a download that is an HTML error page does not)."""
    try:
        etree.parse(io.BytesIO(data), etree.XMLParser(no_network=True, resolve_entities=False))
    except etree.XMLSyntaxError:
        return False
    return True
