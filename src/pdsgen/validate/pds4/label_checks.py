"""Validate one PDS4 label offline: XML Schema, Schematron, and the label against its data.

Order: parse -> find the schemas it names in the catalog (shipped + `--schemas`)
-> XML Schema (lxml) -> Schematron (Saxon, when installed) -> content checks
(file size, MD5, array statistics, special constants, cartography against the
georeferencing). Every problem is a hit of a PDS4-nnn rule: these are the checks of
the validator's PDS4 rule family (validate/families/pds4_rules.py declares the rules and
their severities; the runner opens a `Pds4LabelContext` for each PDS4 file). Nothing a label
holds can raise out of here.

The content checks compute independently of the writer: they read the data file
with numpy and project with the validator's own closed-form sphere formulas.
"""

from __future__ import annotations

import copy as copy_module
import os
import re
from collections.abc import Callable, Iterable
from pathlib import Path

from lxml import etree

from ...pds4.model import PDS_NS
from ..model import Finding, Hit
from ..registry import rules
from . import schematron
from .cart_checks import check_cartography, check_encoded_jp2
from .catalog import SchemaCatalog, SchemaFile, schema_references
from .context_registry import check_context_facts, check_context_references
from .data_checks import check_data, check_special_constants
from .document_checks import check_file_names, check_pdf_a
from .label_tree import P, Pds4Hits
from .table_checks import check_members, check_object_layout, check_tables
from .xsd import SchemaImportError, build_schema, xsd_errors

# Checks of the label against its data (skipped by --labels-only), and of the label alone.
CONTENT_CHECKS = (check_data, check_special_constants, check_cartography, check_encoded_jp2, check_tables,
                  check_object_layout, check_members, check_pdf_a, check_file_names, check_context_references,
                  check_context_facts)
LABEL_ONLY_CHECKS = (check_special_constants, check_cartography, check_object_layout, check_members,
                     check_file_names, check_context_references, check_context_facts)


def check_schema_dirs(directories: Iterable[str | os.PathLike[str]]) -> tuple[str, ...]:
    """The `--schemas` directories as strings, refusing one that is not a directory (usage error)."""
    checked = tuple(os.fspath(d) for d in directories)
    SchemaCatalog.build(checked)
    return checked


def catalog_for(schema_dirs: tuple[str, ...] = (), schema_cache: str | None = None,
                download: bool = False) -> SchemaCatalog:
    """The schema catalog of a run, built once per process for each set of sources.
    `schema_cache` is the download cache read (and, with `download`, written); without
    one, neither the cache nor the network is used."""
    key = (schema_dirs, schema_cache, download)
    if key not in _CATALOGS:
        _CATALOGS[key] = SchemaCatalog.build(schema_dirs, schema_cache, download)
    return _CATALOGS[key]


_CATALOGS: dict[tuple[tuple[str, ...], str | None, bool], SchemaCatalog] = {}


class Pds4LabelContext:
    """One PDS4 label as the validator's PDS4 rules see it (their context). Every check
    runs once, when the first rule asks; each rule then takes its own hits."""

    def __init__(self, path: str | Path, catalog: SchemaCatalog, labels_only: bool = False,
                 use_schematron: bool = True, tree: Path | None = None) -> None:
        self.path = Path(path)
        self.tree = tree  # the trusted tree (label/beside.trusted_tree): the label's directory unless told
        self.catalog = catalog
        self.labels_only = labels_only
        self.use_schematron = use_schematron
        self._hits: dict[str, list[Hit]] | None = None

    def hits(self, rule_id: str) -> list[Hit]:
        if self._hits is None:
            found = Pds4Hits(self.path, self.tree)
            self._hits = found.by_rule  # a check that raises out of here is not run again
            _check(found, self.catalog, self.labels_only, self.use_schematron)
        return self._hits.get(rule_id, [])


def validate_label(path: str | Path, schema_dirs: tuple[str, ...] = (), labels_only: bool = False,
                   schema_cache: str | None = None, download: bool = False) -> list[Finding]:
    """Every finding for one PDS4 label, with the catalog a validation run would use."""
    return validate_pds4(path, catalog_for(schema_dirs, schema_cache, download), labels_only)


def validate_pds4(path: str | Path, catalog: SchemaCatalog | None = None, labels_only: bool = False,
                  use_schematron: bool = True) -> list[Finding]:
    """Every finding for one PDS4 label, as the PDS4 family of a validation run reports it
    (before configuration): the registry's severities, in line order."""
    label = Pds4LabelContext(path, catalog or SchemaCatalog.build(), labels_only, use_schematron)
    findings = [Finding(rule.id, hit.severity or rule.severity, hit.file or str(label.path), hit.message,
                        hit.line, hit.keyword)
                for rule in rules().values() if rule.target == "pds4" and rule.check is not None
                for hit in rule.check(label)]
    return sorted(findings, key=lambda f: (f.line or 0, f.rule))


__all__ = ["Pds4LabelContext", "catalog_for", "check_schema_dirs", "validate_label", "validate_pds4"]


def _check(report: Pds4Hits, catalog: SchemaCatalog, labels_only: bool, use_schematron: bool) -> None:
    """Parse -> schemas -> content checks, each problem added to `report` under its rule."""
    tree = _parse(report)
    if tree is None:
        return
    root = tree.getroot()
    if not (root.tag.startswith(P) and root.tag[len(P):].startswith("Product_")):
        report.add("PDS4-001", f"root element {root.tag} is not a PDS4 Product_*", root.sourceline)
        return
    for check in _schema_checks(tree, catalog, use_schematron, report.path.absolute().parent):
        check(report)
    for content_check in CONTENT_CHECKS:
        if labels_only and content_check not in LABEL_ONLY_CHECKS:
            continue
        try:
            content_check(report, tree)
        except Exception as exc:  # a check must never turn odd input into a traceback
            report.add("PDS4-001", f"check {content_check.__name__} could not run ({type(exc).__name__}: {exc})",
                       severity="error")


_DECLARATION = re.compile(rb"<\?xml\s[^>]*\?>")
# Genuine labels declare a few dozen namespaces; tens of thousands make copying the tree
# for Schematron quadratic (80,000 took 40 s), so more than this are not checked.
MAX_NAMESPACES = 1000
_NAMESPACE_DECLARATION = re.compile(rb"\sxmlns(?::[^\s=<>/]+)?\s*=")


def _parse(report: Pds4Hits) -> etree._ElementTree | None:
    """The label's tree (_parse_xml), or None after a PDS4-001 finding - also when it refers to
    an entity its own document type declares: entities are never expanded (an external one
    reads a file, nested ones grow without bound), and an unexpanded reference stops libxml2's
    XML Schema check with an internal error (every check 'could not run')."""
    tree = _parse_xml(report)
    if tree is None:
        return None
    entity = next(tree.getroot().iter(etree.Entity), None)
    if entity is not None:
        report.add("PDS4-001", f"the label refers to the entity {entity.text}, declared in its own document "
                               "type; pdsgen expands no entity, so the label is not checked", entity.sourceline)
        return None
    return tree


def _parse_xml(report: Pds4Hits) -> etree._ElementTree | None:
    """The label's tree, or None after a PDS4-001 finding. A label whose XML declaration
    follows a comment (not well-formed, but readers such as GDAL accept it) is reported
    and then checked without the misplaced declaration, keeping its line numbers."""
    from ...bounded import read_bytes
    from ...errors import InputError

    parser = etree.XMLParser(no_network=True, resolve_entities=False)
    try:
        data = read_bytes(report.path, what="label")
    except InputError as exc:
        report.add("PDS4-001", f"cannot read the label: {exc.problem}")
        return None
    declared = sum(1 for _ in zip(_NAMESPACE_DECLARATION.finditer(data), range(MAX_NAMESPACES + 1), strict=False))
    if declared > MAX_NAMESPACES:
        report.add("PDS4-001", f"the label declares more than {MAX_NAMESPACES} XML namespaces; it is not checked")
        return None
    try:
        return etree.ElementTree(etree.fromstring(data, parser))
    except etree.XMLSyntaxError as exc:
        declaration = _DECLARATION.search(data)
        if declaration is None or declaration.start() == 0:
            report.add("PDS4-001", f"not well-formed XML: {exc}", exc.lineno)
            return None
        line = data.count(b"\n", 0, declaration.start()) + 1
        report.add("PDS4-001", "the XML declaration is not at the start of the file (not well-formed XML)", line)
        blanked = data[:declaration.start()] + b" " * len(declaration.group()) + data[declaration.end():]
        try:
            return etree.ElementTree(etree.fromstring(blanked, parser))
        except etree.XMLSyntaxError as again:
            report.add("PDS4-001", f"not well-formed XML: {again}", again.lineno)
            return None


def _schema_checks(tree: etree._ElementTree, catalog: SchemaCatalog, use_schematron: bool, base: Path
                   ) -> list[Callable[[Pds4Hits], None]]:
    """XML Schema and Schematron checks with whatever schemas can be found: a namespace
    whose schema is missing is reported once and left unchecked, everything else is
    still checked (the core PDS schema missing leaves no XML Schema check to make)."""
    refs = schema_references(tree)
    version = tree.findtext(f"{P}Identification_Area/{P}information_model_version") or "unknown"
    line = tree.getroot().sourceline
    found = {url: catalog.resolve(url, base) for url in {*(u for _, u in refs.xsd), *refs.sch}}
    available = tuple((ns, url) for ns, url in refs.xsd if found[url] is not None)
    missing = [url for _, url in refs.xsd if found[url] is None] + [url for url in refs.sch if found[url] is None]
    sch_files = [file for file in (found[url] for url in refs.sch) if file is not None]
    has_core = any(ns == PDS_NS for ns, _ in available)

    def not_found(report: Pds4Hits) -> None:
        for stem, urls in _by_stem(missing).items():
            namespace = next((ns for ns, url in refs.xsd if url in urls), None)
            what = ("XML Schema checks skipped" if namespace == PDS_NS else
                    f"elements of {namespace} not checked" if namespace else "its rules not checked")
            kinds = ", ".join(Path(u).suffix for u in urls)
            report.add("PDS4-002", f"schema {stem} ({kinds}; IM {version}) not found: {catalog.why_missing(urls[0])}; "
                                   f"{what} (supply it with --schemas DIR)", line, "information_model_version")

    def xml_schema(report: Pds4Hits) -> None:
        if not refs.xsd:
            report.add("PDS4-004", "the label names no XML Schema (xsi:schemaLocation)", line)
            return
        if not has_core:
            return
        try:
            schema = build_schema(catalog, available, base)
        except SchemaImportError as exc:
            report.add("PDS4-003", exc.problem)
            return
        known = tuple(f"Element '{{{ns}}}" for ns, _ in available)
        for error_line, element, message in xsd_errors(schema, tree):
            if missing and "No matching global element declaration" in message and not message.startswith(known):
                continue  # an element of a namespace whose schema is missing, which is reported once
            report.add("PDS4-004", message, error_line, element)

    def rules(report: Pds4Hits) -> None:
        if not refs.sch:
            named = "; ".join(f"xml-model {text.strip()}" for text in refs.unusable) or "no xml-model instruction"
            report.add("PDS4-008", f"the label names no usable Schematron ({named}): no rule checks made", line)
        if not sch_files or not schematron.available():
            return  # a missing Saxon is reported once per run (run check PDS4-007), not per label
        safe = [file for file in sch_files if _runnable(file, report, line)]
        if not safe:
            return
        text = etree.tostring(_collapsed(tree), encoding="unicode")
        try:
            failures, stopped = schematron.bounded_each(safe, text)
        except Exception as exc:  # a Schematron that fails to compile or stops: said, never a traceback
            names = ", ".join(file.name for file in safe)
            report.add("PDS4-002", f"Schematron {names} could not run ({schematron.first_line(exc)}); "
                                   "its rules not checked", line)
            return
        for file, why in stopped:  # an endless or memory-hungry expression: stopped at a limit
            report.add("PDS4-002", f"Schematron {file.name} stopped: {why}; its rules not checked for this label", line)
        for failure in failures:
            rule = "PDS4-006" if failure.role in ("warning", "warn", "info") else "PDS4-005"
            report.add(rule, failure.message, schematron.location_line(tree, failure.location),
                       failure.rule_context)

    return [not_found, xml_schema, rules] if use_schematron else [not_found, xml_schema]


def _runnable(file: SchemaFile, report: Pds4Hits, line: int | None) -> bool:
    """Whether a Schematron file may run: one whose XPath reaches outside the label (files,
    environment variables, the network, nested transforms) is reported and not run."""
    calls = schematron.forbidden_calls(file)
    if calls:
        report.add("PDS4-002", f"Schematron {file.name} not run: it calls {', '.join(calls)}, which reach outside "
                               "the label (files, environment variables, network or nested transforms); "
                               "its rules not checked", line)
    return not calls


def _collapsed(tree: etree._ElementTree) -> etree._Element:
    """The label as a schema-validating parser presents it to Schematron: the text of each
    element without children whitespace-collapsed (PDS4 values are xs:token-like; Xerces,
    under NASA's validator, hands Schematron these normalised values, so a value written
    over two lines still equals its enumeration)."""
    copy = copy_module.deepcopy(tree.getroot())
    for element in copy.iter():
        if isinstance(element.tag, str) and len(element) == 0 and element.text:
            element.text = " ".join(element.text.split())
    return copy


def _by_stem(urls: list[str]) -> dict[str, list[str]]:
    """Schema locations grouped by file stem (PDS4_CART_1F00_1950: its .xsd and .sch together)."""
    groups: dict[str, list[str]] = {}
    for url in dict.fromkeys(urls):
        groups.setdefault(Path(url).stem, []).append(url)
    return groups


# --- content checks -------------------------------------------------------------------------
