"""Where the schema files a PDS4 label names are on this machine.

Labels name their schemas by URL (`https://pds.nasa.gov/pds4/cart/v1/PDS4_CART_1O00_1970.xsd`).
Validation is offline, so every such URL is answered from a directory: the
schemas shipped with pdsgen (`schemas/pds4/<IM>/`) and any directories the user
adds (`--schemas DIR`, searched recursively). A URL is matched by its file name,
which in PDS4 carries the namespace, the IM version and the dictionary version.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from ..errors import PdsgenError, param
from ..resources import schemas_dir
from .model import SCHEMATRON_NS, XSI_NS

SCHEMA_SUFFIXES = (".xsd", ".sch")


def shipped_schema_dir() -> Path:
    return schemas_dir() / "pds4"


@dataclass
class SchemaCatalog:
    """File name -> local path of every schema file in the given directories."""

    files: dict[str, Path] = field(default_factory=dict)

    @classmethod
    def build(cls, extra_dirs: Iterable[str | os.PathLike[str]] = ()) -> SchemaCatalog:
        """The shipped schemas, then each extra directory (later ones win on a name clash)."""
        catalog = cls()
        catalog.add_dir(shipped_schema_dir())
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

    def resolve(self, url: str) -> Path | None:
        """The local copy of a schema URL (or file name), None when we have none."""
        return self.files.get(url.rsplit("/", 1)[-1])

    def key(self) -> tuple[tuple[str, str], ...]:
        """A hashable identity, for caching compiled schemas per catalog."""
        return tuple(sorted((k, str(v)) for k, v in self.files.items()))


@dataclass(frozen=True)
class SchemaReferences:
    """The schema URLs a label names: XML Schema per namespace, Schematron files."""

    xsd: tuple[tuple[str, str], ...]  # (namespace, url)
    sch: tuple[str, ...]


def schema_references(tree: etree._ElementTree) -> SchemaReferences:
    """xsi:schemaLocation pairs of the root and the Schematron `xml-model` instructions."""
    root = tree.getroot()
    tokens = (root.get(f"{{{XSI_NS}}}schemaLocation") or "").split()
    pairs = tuple(zip(tokens[0::2], tokens[1::2], strict=False))
    sch: list[str] = []
    node = root.getprevious()
    while node is not None:
        if isinstance(node, etree._ProcessingInstruction) and node.target == "xml-model":
            attrs = node.attrib
            if attrs.get("schematypens", "") == SCHEMATRON_NS and attrs.get("href"):
                sch.append(attrs["href"])
        node = node.getprevious()
    return SchemaReferences(pairs, tuple(reversed(sch)))
