"""Context references against PDS's registry of context products (PDS4-063).

A label's investigation, observing system, target, facility ... are context products that
PDS registers; a reference to an unregistered LID is one no archive user can follow. NASA's
validator checks them against a snapshot of the registry it ships
(registered_context_products.json, refreshed weekly); pdsgen ships the same snapshot's
LIDVIDs (schemas/pds4/context_products.txt.xz, provenance in its first line and in
schemas/pds4/SOURCES.md) and checks the same references the same way, offline:

- the references are the Internal_References whose reference_type starts with `is_` or
  ends with one of CONTEXT_SUFFIXES (data_to_investigation, is_instrument_host ...);
- a LID reference is registered when its LID is (case aside); a LIDVID reference when the
  LID is registered with that version or a later one.

A context product registered after the snapshot is reported until the snapshot is renewed
(tools/pack_context_products.py); ignoring the rule, or configuring its severity, sets it
aside as NASA's option to skip context validation does.
"""

from __future__ import annotations

import lzma
from functools import cache

from lxml import etree

from ...resources import schemas_dir
from .label_tree import P, Pds4Hits

CONTEXT_SUFFIXES = ("_to_target", "_to_investigation", "_to_instrument", "_to_instrument_host", "_to_other",
                    "_to_facility", "_to_telescope", "_to_airborne", "_to_laboratory")


@cache
def registered() -> dict[str, tuple[float, ...]]:
    """Lower-case LID -> the versions registered for it (empty when none is given)."""
    path = schemas_dir() / "pds4" / "context_products.txt.xz"
    products: dict[str, tuple[float, ...]] = {}
    for line in lzma.decompress(path.read_bytes()).decode("utf-8").splitlines():
        if not line or line.startswith("#"):
            continue
        lid, _, version = line.partition(" ")
        versions = products.setdefault(lid.lower(), ())
        if version:
            products[lid.lower()] = (*versions, float(version))
    return products


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
