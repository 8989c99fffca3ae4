"""Fetching a schema a label names from its URL into pdsgen's cache.

Only http(s), only when the user allows it (not `--offline`). A download must parse
as XML (an HTML error page is not a schema); it is written under a temporary name and
renamed when complete, and its SHA-256 is appended to the cache's SHA256SUMS with the
URL it came from, so that a later run can tell a cached file was not altered.

The catalog (catalog.py) calls this module; this module knows nothing of the catalog
(the cache's SHA256SUMS name and the XML test live here, where downloads are written).
urllib is imported on the first download: most runs never fetch.
"""

from __future__ import annotations

import io
from pathlib import Path

from lxml import etree

from ... import __version__
from ...errors import PdsgenError
from ...formats.checksum import bytes_sha256
from ...storage.staging import staged_file

SUMS_NAME = "SHA256SUMS"  # in the cache: "<sha256>  <name>  <url>" per downloaded schema
TIMEOUT_SECONDS = 30
MAX_BYTES = 64 * 1024 * 1024  # the largest PDS schema is a few MB


class DownloadError(PdsgenError):
    """A schema could not be fetched (network, HTTP status, not XML)."""


def fetch_schema(url: str, cache_dir: Path, name: str) -> tuple[Path, str]:
    """Download `url` into `cache_dir/name`; its path and SHA-256."""
    import urllib.error
    import urllib.request

    request = urllib.request.Request(url, headers={"User-Agent": f"pdsgen/{__version__}"})
    try:
        with urllib.request.urlopen(request, timeout=TIMEOUT_SECONDS) as response:  # noqa: S310 - http(s) only
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
    try:
        cache_dir.mkdir(parents=True, exist_ok=True)
        target = cache_dir / name
        with staged_file(target) as part:  # .NAME.PID.part
            part.write_bytes(data)
        with open(cache_dir / SUMS_NAME, "a", encoding="utf-8") as sums:
            sums.write(f"{digest}  {name}  {url}\n")
    except OSError as exc:
        raise DownloadError(cache_dir, f"cannot write the schema cache: {exc.strerror or exc}") from None
    return target, digest


def is_xml(data: bytes) -> bool:
    """Whether bytes parse as XML (a download that is an HTML error page does not)."""
    try:
        etree.parse(io.BytesIO(data), etree.XMLParser(no_network=True, resolve_entities=False))
    except etree.XMLSyntaxError:
        return False
    return True
