"""XML Schema validation of PDS4 labels with lxml, offline.

libxml2 silently skips an `xs:import` it cannot load and builds a schema without
that namespace, which then accepts anything in it. So every URL or path the schema
compiler asks for goes through our resolver, which answers it from the catalog
and records what it could not answer; any such miss fails the build loudly.
Relative locations are taken relative to the label's directory (the driver
document's base), never the working directory.
"""

from __future__ import annotations

import os
from collections import OrderedDict
from functools import lru_cache
from pathlib import Path

from lxml import etree

from ...errors import PdsgenError
from .catalog import SchemaCatalog, SchemaFile

_XS = "http://www.w3.org/2001/XMLSchema"


class SchemaImportError(PdsgenError):
    """A schema (or one it imports) is not available locally."""


class _CatalogResolver(etree.Resolver):
    def __init__(self, catalog: SchemaCatalog) -> None:
        super().__init__()
        self.catalog = catalog
        self.missing: list[str] = []

    def resolve(self, system_url, public_id, context):  # noqa: ANN001 - lxml's signature
        if system_url is None:
            return None
        found = self.catalog.resolve(system_url)
        if found is not None:
            return self.resolve_string(_schema_text(found), context, base_url=system_url)
        self.missing.append(system_url)
        return self.resolve_string(b"", context)  # libxml2 must not look for it on its own


def build_schema(catalog: SchemaCatalog, locations: tuple[tuple[str, str], ...], base: Path | None = None
                 ) -> etree.XMLSchema:
    """One XMLSchema importing every (namespace, schema URL) pair, relative locations taken
    from `base` (the label's directory); raises SchemaImportError naming every location
    that could not be answered."""
    key = (catalog.key(), locations, base if any("://" not in url for _, url in locations) else None)
    if key in _COMPILED:
        _COMPILED.move_to_end(key)
        return _COMPILED[key]
    schema = _COMPILED[key] = _compile(catalog, locations, base)
    while len(_COMPILED) > KEPT_SCHEMAS:  # a run over many IM versions must not hold them all
        _COMPILED.popitem(last=False)
    return schema


# Compiled schemas of this process, by catalog and imports (the PDS core takes ~0.3 s to compile).
# The compiled schema sets of this process, most recently used last (the PDS core takes
# ~0.3 s to compile, and tens of MB to hold: 16 sets are kept, not one per IM version met).
KEPT_SCHEMAS = 16
_COMPILED: OrderedDict[tuple, etree.XMLSchema] = OrderedDict()


def _compile(catalog: SchemaCatalog, locations: tuple[tuple[str, str], ...], base: Path | None
             ) -> etree.XMLSchema:
    missing = [url for _, url in locations if catalog.resolve(url, base) is None]
    if missing:
        raise SchemaImportError(None, "schema not available: " + ", ".join(missing))
    driver = etree.Element(f"{{{_XS}}}schema", nsmap={"xs": _XS})
    for namespace, url in locations:  # every URL goes through the resolver, so misses are seen
        etree.SubElement(driver, f"{{{_XS}}}import", namespace=namespace, schemaLocation=url)
    parser = etree.XMLParser(no_network=True, resolve_entities=False)
    resolver = _CatalogResolver(catalog)
    parser.resolvers.add(resolver)
    anchor = (base or Path(os.sep)).resolve() / "pdsgen-driver.xsd"  # relative locations: beside the label
    document = etree.fromstring(etree.tostring(driver), parser, base_url=anchor.as_uri())
    try:
        schema = etree.XMLSchema(document.getroottree())
    except etree.XMLSchemaParseError as exc:
        raise SchemaImportError(None, _unresolved(resolver) or f"schema does not compile: {exc}") from None
    if resolver.missing:
        raise SchemaImportError(None, _unresolved(resolver))
    return schema


def _unresolved(resolver: _CatalogResolver) -> str:
    if not resolver.missing:
        return ""
    return "schema import did not resolve: " + ", ".join(dict.fromkeys(resolver.missing))


@lru_cache(maxsize=16)
def _schema_text(file: SchemaFile) -> bytes:
    """A schema file as libxml2 should see it. Some published PDS schemas (e.g. PROC 1900)
    hold an empty `<xs:choice minOccurs="1">`: Xerces, which NASA's validate uses, treats it
    as matching nothing, libxml2 as unsatisfiable, which would reject every valid label.
    Empty choices are removed so both agree."""
    tree = etree.ElementTree(etree.fromstring(file.read_bytes(),
                                                 etree.XMLParser(no_network=True, resolve_entities=False)))
    for choice in tree.iter(f"{{{_XS}}}choice"):
        if not any(isinstance(child.tag, str) and child.tag != f"{{{_XS}}}annotation" for child in choice):
            choice.getparent().remove(choice)
    return etree.tostring(tree)


def xsd_errors(schema: etree.XMLSchema, tree: etree._ElementTree) -> list[tuple[int | None, str | None, str]]:
    """(line, element name, message) of every XML Schema violation in the label."""
    if schema.validate(tree):
        return []
    return [(error.line or None, _element_name(error.path), error.message) for error in schema.error_log]


def _element_name(path: str | None) -> str | None:
    """The last named step of libxml2's error path (`/*/*[2]/cart:Planar/cart:Map_Projection`)."""
    name = (path or "").rsplit("/", 1)[-1].split("[")[0]
    return name if name and name != "*" else None
