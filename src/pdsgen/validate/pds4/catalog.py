"""Where the schema files a PDS4 label names are found, from trusted sources only.

Labels name their schemas by URL (`https://pds.nasa.gov/pds4/cart/v1/PDS4_CART_1O00_1970.xsd`),
or by a path (`PDS4_PDS_1K00.xsd`, `../schemas/x.xsd`, `file:///...`). A schema is code the
validator runs (Schematron is XPath; an XSD's enumerations are quoted in findings), so it
is taken only from where the user's trust goes, never from where a label points:

1. the directories the user gives (`--schemas DIR`, searched recursively): a path or
   `file://` location is loaded only when it resolves (symlinks resolved) inside one;
2. the schemas shipped with pdsgen: `schemas/pds4/<IM>/` as files, and the core schemas
   of every released IM version and every version of the discipline dictionaries as xz archives in
   `schemas/pds4/packed/` (listed by its index.json, read in memory when first needed);
3. any location's file name among 1 and 2 (PDS4 file names carry the namespace, the IM
   version and the dictionary version);
4. pdsgen's download cache (`~/.cache/pdsgen/pds4-schemas`, or `--schema-cache DIR`), by the
   full URL the label names, each file checked against the SHA-256 recorded when fetched;
5. the label's URL, when downloads are allowed and its host is PDS's schema site (fetched
   over https into the cache; download.py).

A location elsewhere (a file beside the label, `../`, `file://` outside `--schemas`, another
host) is not loaded; `why_missing` says so, and the label's finding names the rules not run.
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
from ...storage.containment import contained
from .download import SCHEMA_HOSTS, DownloadError, download_url, fetch_schema, read_sums

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
    trusted_dirs: list[Path] = field(default_factory=list)  # --schemas and shipped, resolved
    _failed: dict[str, str] = field(default_factory=dict)  # URL -> why it could not be fetched or loaded
    _sums: dict[str, tuple[str, str]] | None = None  # cache: URL -> (place, SHA-256)
    _intact: dict[str, Path] = field(default_factory=dict)  # URL -> cached file checked against _sums
    _names: dict[str, str] = field(default_factory=dict)  # URL -> file name

    @classmethod
    def build(cls, extra_dirs: Iterable[str | os.PathLike[str]] = (), cache_dir: str | os.PathLike[str] | None = None,
              download: bool = False) -> SchemaCatalog:
        """Shipped archives, shipped files, then each extra directory (later sources win on
        a name clash); the cache is looked up by URL, not listed here."""
        catalog = cls(cache_dir=Path(cache_dir) if cache_dir is not None else None, download=download)
        for name, entry in packed_index().items():
            catalog.files[name] = PackedSchema(packed_dir() / entry["archive"], name)
        for shipped in sorted(shipped_schema_dir().iterdir()):
            if shipped.is_dir() and shipped.name != "packed":
                catalog.add_dir(shipped)
        for directory in extra_dirs:
            path = Path(directory)
            if not path.is_dir():
                raise PdsgenError(path, f"schema directory not found ({param('schemas')} needs a directory)")
            catalog.add_dir(path)
        return catalog

    def add_dir(self, directory: Path) -> None:
        """Every schema file under a trusted directory, by name; paths inside it may be loaded.
        A symlink leading out of the directory is not taken (a delivery's schema directory
        given with --schemas may link to any file of the host)."""
        real_dir = directory.resolve()
        self.trusted_dirs.append(real_dir)
        for root, dirnames, filenames in os.walk(directory):
            dirnames.sort()
            for name in sorted(filenames):
                path = Path(root) / name
                if name.lower().endswith(SCHEMA_SUFFIXES) and _resolves_inside(path, real_dir):
                    self.files[name] = path
        self.serial = next(_SERIALS)

    def resolve(self, url: str, base: Path | None = None) -> SchemaFile | None:
        """The schema a URL or path names, None when no trusted source has it. A relative
        path is taken relative to `base` (the label's directory), never the working
        directory, and is loaded only inside a trusted directory; else its name is looked up."""
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
            if self._inside_trusted(local):
                return local
            self._failed.setdefault(url, "a location outside the shipped schemas and --schemas is not loaded")
        return self._by_name(local.name, None)

    def _inside_trusted(self, local: Path) -> bool:
        """Whether a file, symlinks resolved, lies inside a --schemas or shipped directory."""
        return any(_resolves_inside(local, directory) for directory in self.trusted_dirs)

    def _by_name(self, name: str, url: str | None) -> SchemaFile | None:
        found = self.files.get(name)
        if found is None and url is not None:
            found = self._cached_or_fetched(url)
        return found

    def _cached_or_fetched(self, url: str) -> SchemaFile | None:
        """The download of a URL of PDS's schema site: from the cache, else fetched when allowed."""
        source = download_url(url)
        if source is None:
            if self.download:
                self._failed.setdefault(url, f"not downloaded: schemas are fetched only over https from "
                                             f"PDS's schema site ({', '.join(SCHEMA_HOSTS)})")
            return None
        cached = self._cached(source)
        if cached is None and self.download and self.cache_dir is not None:
            cached = self._fetch(source, url)
        return cached

    def _cached(self, source: str) -> Path | None:
        """A cached download of `source`, used only while it still has the SHA-256 recorded
        when it was fetched (a truncated or edited file is fetched again, or reported
        missing); hashed once per catalog, not once per label naming it."""
        if self.cache_dir is None:
            return None
        if source in self._intact:
            return self._intact[source]
        if self._sums is None:
            self._sums = read_sums(self.cache_dir)
        entry = self._sums.get(source)
        if entry is None:
            return None
        place, expected = entry
        cached = self.cache_dir / place
        try:
            intact = cached.is_file() and file_sha256(cached) == expected
        except OSError:
            intact = False
        if not intact:
            log.warning("cached schema %s does not match its recorded SHA-256; not used", cached)
            del self._sums[source]
            return None
        self._intact[source] = cached
        return cached

    def _fetch(self, source: str, url: str) -> Path | None:
        if url in self._failed or self.cache_dir is None:
            return None
        try:
            path, digest = fetch_schema(source, self.cache_dir)
        except DownloadError as exc:
            self._failed[url] = f"download failed: {exc}"
            log.info("could not download %s: %s", source, exc)
            return None
        log.info("downloaded %s -> %s (sha256 %s)", source, path, digest)
        self.downloaded.append(source)
        self._intact[source] = path
        return path

    def why_missing(self, url: str) -> str:
        """Why a schema was not found, for the report."""
        if url in self._failed:
            return self._failed[url]
        if urlsplit(url).scheme not in ("http", "https"):
            return "not in --schemas or shipped, and no schema of that name"
        if not self.download:
            return "not shipped, not in --schemas or the cache, and downloads are off (--offline)"
        return "not shipped, not in --schemas or the cache"

    def key(self) -> tuple[int, int]:
        """A hashable identity, for caching compiled schemas per catalog state."""
        return (id(self), self.serial)


def _resolves_inside(path: Path, real_dir: Path) -> bool:
    """Whether a file that exists lies inside a directory, symbolic links resolved (the one
    containment rule, storage/containment.contained)."""
    return path.exists() and contained(path, real_dir) is not None


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

