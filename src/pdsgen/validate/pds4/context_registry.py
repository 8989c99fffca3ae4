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

from lxml import etree

from ...pds4.context import (  # noqa: F401 - the registry's facts, read in pds4 (pds4 never imports validate)
    ContextProduct,
    named,
    normal_name,
    numbered_comet,
    product,
    registered,
    target_types,
)
from .label_tree import P, Pds4Hits

CONTEXT_SUFFIXES = ("_to_target", "_to_investigation", "_to_instrument", "_to_instrument_host", "_to_other",
                    "_to_facility", "_to_telescope", "_to_airborne", "_to_laboratory")


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
