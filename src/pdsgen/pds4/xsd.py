"""XML Schema validation of PDS4 labels with lxml, offline.

libxml2 silently skips an `xs:import` it cannot load and builds a schema without
that namespace, which then accepts anything in it. So every URL the schema
compiler asks for goes through our resolver, which answers it from the catalog
and records what it could not answer; any such miss fails the build loudly.
"""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from ..errors import PdsgenError
from .catalog import SchemaCatalog

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
        local = self.catalog.resolve(system_url) if "://" in system_url else None
        if local is not None:
            return self.resolve_filename(str(local), context)
        if "://" in system_url and not system_url.startswith("file:"):
            self.missing.append(system_url)
        return None


def build_schema(catalog: SchemaCatalog, locations: tuple[tuple[str, str], ...]) -> etree.XMLSchema:
    """One XMLSchema importing every (namespace, schema URL) pair; raises SchemaImportError
    naming every URL that could not be answered locally."""
    key = (catalog.key(), locations)
    if key not in _COMPILED:
        _COMPILED[key] = _compile(catalog, locations)
    return _COMPILED[key]


# Compiled schemas of this process, by catalog and imports (the PDS core takes ~0.3 s to compile).
_COMPILED: dict[tuple, etree.XMLSchema] = {}


def _compile(catalog: SchemaCatalog, locations: tuple[tuple[str, str], ...]) -> etree.XMLSchema:
    missing = [url for _, url in locations if catalog.resolve(url) is None]
    if missing:
        raise SchemaImportError(None, "schema not available offline: " + ", ".join(missing))
    driver = etree.Element(f"{{{_XS}}}schema", nsmap={"xs": _XS})
    for namespace, url in locations:
        local = catalog.resolve(url)
        assert local is not None
        etree.SubElement(driver, f"{{{_XS}}}import", namespace=namespace, schemaLocation=local.as_uri())
    parser = etree.XMLParser(no_network=True)
    resolver = _CatalogResolver(catalog)
    parser.resolvers.add(resolver)
    document = etree.fromstring(etree.tostring(driver), parser, base_url=str(Path.cwd() / "driver.xsd"))
    try:
        schema = etree.XMLSchema(document.getroottree())
    except etree.XMLSchemaParseError as exc:
        raise SchemaImportError(None, f"schema does not compile: {exc}") from None
    if resolver.missing:
        raise SchemaImportError(
            None, "schema import did not resolve offline: " + ", ".join(dict.fromkeys(resolver.missing))
        )
    return schema


def xsd_errors(schema: etree.XMLSchema, tree: etree._ElementTree) -> list[tuple[int | None, str]]:
    """(line, message) of every XML Schema violation in the label."""
    if schema.validate(tree):
        return []
    return [(error.line or None, error.message) for error in schema.error_log]
