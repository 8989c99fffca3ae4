"""Context references against PDS's registry of context products (PDS4-063).

A label's investigation, observing system, target, facility ... are context products that
PDS registers; a reference to an unregistered LID is one no archive user can follow. NASA's
validator checks them against a snapshot of the registry it ships
(registered_context_products.json, refreshed weekly); pdsgen ships the same snapshot's
LIDVIDs with the types and names the registry gives them (schemas/pds4/context_products.txt.xz,
provenance in its first line and in schemas/pds4/SOURCES.md) and checks the same references
the same way, offline:

- the references are the Internal_References whose reference_type starts with `is_` or
  ends with one of CONTEXT_SUFFIXES (data_to_investigation, is_instrument_host ...);
- a LID reference is registered when its LID is (case aside); a LIDVID reference when the
  LID is registered with that version or a later one.

A context product registered after the snapshot is reported until the snapshot is renewed
(tools/pack_context_products.py); ignoring the rule, or configuring its severity, sets it
aside as NASA's option to skip context validation does.

The same snapshot is where a migrated label's catalogue facts come from (`lookup`): the
registered product a PDS3 name denotes (TARGET_NAME, MISSION_NAME, INSTRUMENT_HOST_NAME),
its LID and its registered type - one home for them, which the PDS4 check of a target's
type (PDS4-064) reads too.
"""

from __future__ import annotations

import lzma
import re
from collections.abc import Iterable
from dataclasses import dataclass
from functools import cache

from lxml import etree

from ...resources import schemas_dir
from .label_tree import P, Pds4Hits

CONTEXT_SUFFIXES = ("_to_target", "_to_investigation", "_to_instrument", "_to_instrument_host", "_to_other",
                    "_to_facility", "_to_telescope", "_to_airborne", "_to_laboratory")


@dataclass(frozen=True)
class ContextProduct:
    """One registered context product: its LID (lower case), the types and names PDS gives it."""

    lid: str
    types: tuple[str, ...]
    names: tuple[str, ...]

    @property
    def kind(self) -> str:
        """The LID's kind: target, investigation, instrument_host, instrument, ..."""
        parts = self.lid.split(":")
        return parts[4] if len(parts) > 4 else ""

    @property
    def label_name(self) -> str:
        """The name a PDS4 label gives it: the registry's first name that is not a NAIF ID or a LID."""
        usable = [n for n in self.names if not n.upper().startswith(("NAIF ID", "URN:"))]
        return (usable or [self.lid.rsplit(".", 1)[-1]])[0]


@cache
def _snapshot() -> tuple[dict[str, tuple[float, ...]], dict[str, ContextProduct]]:
    """Lower-case LID -> registered versions, and -> the product (types and names)."""
    path = schemas_dir() / "pds4" / "context_products.txt.xz"
    versions: dict[str, tuple[float, ...]] = {}
    products: dict[str, ContextProduct] = {}
    for line in lzma.decompress(path.read_bytes()).decode("utf-8").splitlines():
        if not line or line.startswith("#"):
            continue
        lid_version, _, facts = line.partition("\t")
        lid, _, version = lid_version.partition(" ")
        lid = lid.lower()
        kinds, _, names = facts.partition("\t")
        have = versions.setdefault(lid, ())
        if version:
            versions[lid] = (*have, float(version))
        known = products.get(lid)
        products[lid] = ContextProduct(lid, _merged(known.types if known else (), kinds.split("|")),
                                       _merged(known.names if known else (), names.split("|")))
    return versions, products


def _merged(have: tuple[str, ...], more: Iterable[str]) -> tuple[str, ...]:
    return tuple(dict.fromkeys((*have, *(m for m in more if m))))


def registered() -> dict[str, tuple[float, ...]]:
    """Lower-case LID -> the versions registered for it (empty when none is given)."""
    return _snapshot()[0]


def product(lid: str) -> ContextProduct | None:
    """The registered context product of a LID (or LIDVID), None when PDS has not registered it."""
    return _snapshot()[1].get(lid.strip().partition("::")[0].lower())


def normal_name(name: str) -> str:
    """A name as names are compared: upper case, quotes dropped, blanks folded."""
    return " ".join(name.replace('"', " ").upper().split())


@cache
def _by_name(kind: str) -> dict[str, tuple[ContextProduct, ...]]:
    """Registered products of one kind (target, investigation ...) by each of their names."""
    found: dict[str, tuple[ContextProduct, ...]] = {}
    for item in _snapshot()[1].values():
        if item.kind == kind:
            for name in {normal_name(n) for n in item.names}:
                found[name] = (*found.get(name, ()), item)
    return found


def named(kind: str, name: str) -> tuple[ContextProduct, ...]:
    """The registered products of `kind` that carry `name` among their names (case and blanks aside)."""
    return _by_name(kind).get(normal_name(name), ())


_PERIODIC_COMET = re.compile(r"(\d+)P/")


def numbered_comet(name: str) -> tuple[ContextProduct, ...]:
    """The registered comet of a periodic-comet number ("67P/CHURYUMOV-GERASIMENKO 1 (1969 R1)":
    67P): the IAU numbers periodic comets uniquely, so the number alone names one."""
    m = _PERIODIC_COMET.match(normal_name(name))
    if m is None:
        return ()
    prefix = f"comet.{m.group(1)}p_"
    return tuple(item for item in _snapshot()[1].values()
                 if item.kind == "target" and item.lid.rsplit(":", 1)[-1].startswith(prefix))


# The IM the enumeration is read from: the core schema pdsgen ships (schemas/pds4/SOURCES.md).
CORE_SCHEMATRON = ("1O00", "PDS4_PDS_1O00.sch")
_QUOTED = re.compile(r"'([^']*)'")


@cache
def target_types() -> tuple[frozenset[str], frozenset[str]]:
    """The IM's Target_Identification/type values and those of them it deprecates, as the shipped
    core Schematron states them (the rule on pds:Target_Identification/pds:type; the warnings
    `pds:type != '...'` on pds:Target_Identification)."""
    root = etree.parse(str(schemas_dir() / "pds4" / CORE_SCHEMATRON[0] / CORE_SCHEMATRON[1])).getroot()
    allowed: set[str] = set()
    deprecated: set[str] = set()
    for rule in root.iter("{http://purl.oclc.org/dsdl/schematron}rule"):
        context = rule.get("context", "")
        for test in (a.get("test", "") for a in rule.iter("{http://purl.oclc.org/dsdl/schematron}assert")):
            if context == "pds:Target_Identification/pds:type" and test.startswith(". = ("):
                allowed.update(_QUOTED.findall(test))
            elif context == "pds:Target_Identification" and test.startswith("pds:type != "):
                deprecated.update(_QUOTED.findall(test))
    return frozenset(allowed), frozenset(deprecated)


def is_registered(reference: str) -> bool:
    lid, _, version = reference.strip().partition("::")
    versions = registered().get(lid.lower())
    if versions is None:
        return False
    if not version:
        return True
    try:
        wanted = float(version)
    except ValueError:
        return False
    return any(have >= wanted for have in versions)


def _is_context(reference_type: str) -> bool:
    return reference_type.startswith("is_") or reference_type.endswith(CONTEXT_SUFFIXES)


def check_context_references(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """Every context reference names a registered context product (label only)."""
    for internal in tree.getroot().iter(f"{P}Internal_Reference"):
        if not _is_context((internal.findtext(f"{P}reference_type") or "").strip()):
            continue
        for element in internal:
            if element.tag in (f"{P}lid_reference", f"{P}lidvid_reference"):
                reference = (element.text or "").strip()
                if reference and not is_registered(reference):
                    report.add("PDS4-063", f"{reference} is not a registered context product (PDS's registry "
                                           "as NASA's validator ships it)", element.sourceline,
                               element.tag[len(P):])


# -- catalogue facts against the registry (PDS4-065, PDS4-066) ------------------------------------------

NO_INVESTIGATION = "urn:nasa:pds:context:investigation:individual.none"  # "No Specific Investigation"


def check_context_facts(report: Pds4Hits, tree: etree._ElementTree) -> None:
    """A target typed otherwise than PDS registers it (PDS4-065, a warning: registry searches by
    type miss it), and "No Specific Investigation" beside a registered instrument host whose name
    is a registered investigation's (PDS4-066, a note: an inference from names)."""
    root = tree.getroot()
    for target in root.iter(f"{P}Target_Identification"):
        _check_target_type(report, target)
    _check_investigation(report, root)


def _check_target_type(report: Pds4Hits, target: etree._Element) -> None:
    name = (target.findtext(f"{P}name") or "").strip()
    types = [(t.text or "").strip() for t in target.findall(f"{P}type")]
    lid = (target.findtext(f"{P}Internal_Reference/{P}lid_reference") or
           target.findtext(f"{P}Internal_Reference/{P}lidvid_reference") or "").strip()
    found = product(lid) if lid else None
    how = f"its context reference {lid}"
    if found is None and not lid:
        matches = {p.lid: p for p in named("target", name)} if name else {}
        found = next(iter(matches.values())) if len(matches) == 1 else None
        how = f"the registered target of that name ({found.lid})" if found else how
    registered_types = [t for t in found.types if t] if found else []
    if registered_types and not set(types) & set(registered_types):
        element = target.find(f"{P}type")
        report.add("PDS4-065", f"target {name!r} is typed {', '.join(types) or 'nothing'} but PDS registers "
                               f"{how} as {', '.join(registered_types)}",
                   element.sourceline if element is not None else target.sourceline, "type")


def _check_investigation(report: Pds4Hits, root: etree._Element) -> None:
    for area in root.iter(f"{P}Investigation_Area"):
        if (area.findtext(f"{P}Internal_Reference/{P}lid_reference") or "").strip().lower() != NO_INVESTIGATION:
            continue
        for component in root.iter(f"{P}Observing_System_Component"):
            host = product((component.findtext(f"{P}Internal_Reference/{P}lid_reference") or "").strip())
            if host is None or host.kind != "instrument_host":
                continue
            missions = {p.lid for n in host.names for p in named("investigation", n)}
            if len(missions) == 1:
                report.add("PDS4-066", f"the investigation is No Specific Investigation, but the instrument host "
                                       f"{host.lid} bears the name of the registered investigation "
                                       f"{next(iter(missions))}", area.sourceline, "Investigation_Area")
                return
