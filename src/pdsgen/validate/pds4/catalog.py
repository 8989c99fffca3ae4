"""Where the schema files a PDS4 label names are found.

Labels name their schemas by URL (`https://pds.nasa.gov/pds4/cart/v1/PDS4_CART_1O00_1970.xsd`),
or by a path relative to the label (`PDS4_PDS_1K00.xsd`). A URL is matched by its file
name, which in PDS4 carries the namespace, the IM version and the dictionary version.
They are looked up, first found wins:

1. a path relative to the label (never to the working directory), when that file exists;
2. the directories the user gives (`--schemas DIR`, searched recursively);
3. pdsgen's download cache (`~/.cache/pdsgen/pds4-schemas`, or `--schema-cache DIR`);
4. the schemas shipped with pdsgen: `schemas/pds4/<IM>/` as files, and the core schemas
   of every released IM version and every version of the discipline dictionaries as xz archives in
   `schemas/pds4/packed/` (listed by its index.json, read in memory when first needed);
5. the label's URL, when downloads are allowed (the file then goes into the cache, its
   SHA-256 recorded in the cache's SHA256SUMS).
"""

from __future__ import annotations

import itertools
import json
import logging
import os
import tarfile
from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Protocol
from urllib.parse import unquote, urlsplit

from lxml import etree

from ...errors import PdsgenError, param
from ...formats.checksum import file_sha256
from ...pds4.model import SCHEMATRON_NS, XSI_NS
from ...resources import schemas_dir
from .download import SUMS_NAME, DownloadError, fetch_schema

SCHEMA_SUFFIXES = (".xsd", ".sch")
log = logging.getLogger("pdsgen.validate")


class SchemaFile(Protocol):
    """A schema's bytes, wherever they are kept (a file, an archive member)."""

    @property
    def name(self) -> str: ...

    def read_bytes(self) -> bytes: ...


@dataclass(frozen=True)
class PackedSchema:
    """One schema file inside a shipped xz archive."""

    archive: Path
    member: str

    @property
    def name(self) -> str:
        return self.member

    def read_bytes(self) -> bytes:
        return _archive_members(self.archive)[self.member]

    def __str__(self) -> str:
        return f"{self.archive.name}:{self.member}"


@cache
def _archive_members(archive: Path) -> dict[str, bytes]:
    """Every file of an archive, decompressed in memory once per process."""
    members: dict[str, bytes] = {}
    with tarfile.open(archive, "r:xz") as tar:
        for info in tar:
            handle = tar.extractfile(info) if info.isfile() else None
            if handle is not None:
                members[Path(info.name).name] = handle.read()
    return members


def shipped_schema_dir() -> Path:
    return schemas_dir() / "pds4"


def packed_dir() -> Path:
    return shipped_schema_dir() / "packed"


@cache
def packed_index() -> dict[str, dict[str, str]]:
    """File name -> {"archive", "sha256", "source"} of every shipped archived schema."""
    index = packed_dir() / "index.json"
    if not index.is_file():
        return {}
    files: dict[str, dict[str, str]] = json.loads(index.read_text(encoding="utf-8"))["files"]
    return files


_SERIALS = itertools.count()


@dataclass
class SchemaCatalog:
    """File name -> schema file, from every source but the network; and the network
    (into the cache) when `download` is set and a cache directory is given."""

    files: dict[str, SchemaFile] = field(default_factory=dict)
    cache_dir: Path | None = None
    download: bool = False
    serial: int = field(default_factory=lambda: next(_SERIALS))
    downloaded: list[str] = field(default_factory=list)  # URLs fetched by this catalog
    _failed: dict[str, str] = field(default_factory=dict)  # URL -> why it could not be fetched
    _sums: dict[str, str] | None = None
    _intact: set[str] = field(default_factory=set)  # cached files already checked against _sums
    _names: dict[str, str] = field(default_factory=dict)  # URL -> file name

    @classmethod
    def build(cls, extra_dirs: Iterable[str | os.PathLike[str]] = (), cache_dir: str | os.PathLike[str] | None = None,
              download: bool = False) -> SchemaCatalog:
        """Shipped archives, shipped files, the cache, then each extra directory (later
        sources win on a name clash)."""
        catalog = cls(cache_dir=Path(cache_dir) if cache_dir is not None else None, download=download)
        for name, entry in packed_index().items():
            catalog.files[name] = PackedSchema(packed_dir() / entry["archive"], name)
        for shipped in sorted(shipped_schema_dir().iterdir()):
            if shipped.is_dir() and shipped.name != "packed":
                catalog.add_dir(shipped)
        if catalog.cache_dir is not None and catalog.cache_dir.is_dir():
            catalog.add_dir(catalog.cache_dir)
        for directory in extra_dirs:
            path = Path(directory)
            if not path.is_dir():
                raise PdsgenError(path, f"schema directory not found ({param('schemas')} needs a directory)")
            catalog.add_dir(path)
        return catalog

    def add_dir(self, directory: Path) -> None:
        for root, dirnames, filenames in os.walk(directory):
            dirnames.sort()
            for name in sorted(filenames):
                if name.lower().endswith(SCHEMA_SUFFIXES):
                    self.files[name] = Path(root) / name
        self.serial = next(_SERIALS)

    def resolve(self, url: str, base: Path | None = None) -> SchemaFile | None:
        """The schema a URL or path names, None when no source has it. A relative path is
        taken relative to `base` (the label's directory), never the working directory."""
        if url.startswith(("http://", "https://")):  # the common case: by file name
            name = self._names.get(url)
            if name is None:
                name = self._names.setdefault(url, Path(unquote(urlsplit(url).path)).name)
            return self._by_name(name, url)
        parts = urlsplit(url)
        local = Path(unquote(parts.path)) if parts.scheme == "file" else Path(url)
        if not local.is_absolute() and base is not None:
            local = base / local
        if local.is_absolute() and local.is_file():
            return local
        return self._by_name(local.name, None)

    def _by_name(self, name: str, url: str | None) -> SchemaFile | None:
        found = self.files.get(name)
        if found is not None and not self._cache_intact(found):
            found = None
        if found is None and url is not None and self.download and self.cache_dir is not None:
            found = self._fetch(url, name)
        return found

    def _cache_intact(self, found: SchemaFile) -> bool:
        """A cached download is used only while it still has the SHA-256 recorded when it
        was fetched (a truncated or edited file is fetched again, or reported missing)."""
        if self.cache_dir is None or not isinstance(found, Path) or found.parent != self.cache_dir:
            return True
        if found.name in self._intact:  # hashed once per catalog, not once per label naming it
            return True
        if self._sums is None:
            self._sums = read_sums(self.cache_dir)
        expected = self._sums.get(found.name)
        if expected is None or file_sha256(found) == expected:
            self._intact.add(found.name)
            return True
        log.warning("cached schema %s does not match its recorded SHA-256; not used", found)
        del self.files[found.name]
        return False

    def _fetch(self, url: str, name: str) -> SchemaFile | None:
        if url in self._failed or self.cache_dir is None:
            return None
        try:
            path, digest = fetch_schema(url, self.cache_dir, name)
        except DownloadError as exc:
            self._failed[url] = str(exc)
            log.info("could not download %s: %s", url, exc)
            return None
        log.info("downloaded %s -> %s (sha256 %s)", url, path, digest)
        self.downloaded.append(url)
        self.files[name] = path
        if self._sums is not None:
            self._sums[name] = digest
        return path

    def why_missing(self, url: str) -> str:
        """Why a schema was not found, for the report."""
        if url in self._failed:
            return f"download failed: {self._failed[url]}"
        if urlsplit(url).scheme not in ("http", "https"):
            return "no such file beside the label, and no schema of that name"
        if not self.download:
            return "not shipped, not in --schemas or the cache, and downloads are off (--offline)"
        return "not shipped, not in --schemas or the cache"

    def key(self) -> tuple[int, int]:
        """A hashable identity, for caching compiled schemas per catalog state."""
        return (id(self), self.serial)


def read_sums(cache_dir: Path) -> dict[str, str]:
    """File name -> SHA-256 recorded in a cache's SHA256SUMS (`digest  name  url` lines)."""
    sums: dict[str, str] = {}
    try:
        text = (cache_dir / SUMS_NAME).read_text(encoding="utf-8")
    except OSError:
        return sums
    for line in text.splitlines():
        fields = line.split()
        if len(fields) >= 2:
            sums[fields[1]] = fields[0]
    return sums


@dataclass(frozen=True)
class SchemaReferences:
    """The schema URLs a label names: XML Schema per namespace, Schematron files, and the
    xml-model instructions that name something other than a usable Schematron."""

    xsd: tuple[tuple[str, str], ...]  # (namespace, url)
    sch: tuple[str, ...]
    unusable: tuple[str, ...] = ()


def schema_references(tree: etree._ElementTree) -> SchemaReferences:
    """xsi:schemaLocation pairs of the root and the Schematron `xml-model` instructions."""
    root = tree.getroot()
    tokens = (root.get(f"{{{XSI_NS}}}schemaLocation") or "").split()
    pairs = tuple(zip(tokens[0::2], tokens[1::2], strict=False))
    sch: list[str] = []
    unusable: list[str] = []
    node = root.getprevious()
    while node is not None:
        if isinstance(node, etree._ProcessingInstruction) and node.target == "xml-model":
            attrs = node.attrib
            if attrs.get("schematypens", "") == SCHEMATRON_NS and attrs.get("href"):
                sch.append(attrs["href"])
            else:
                unusable.append(node.text or "")
        node = node.getprevious()
    return SchemaReferences(pairs, tuple(reversed(sch)), tuple(reversed(unusable)))

