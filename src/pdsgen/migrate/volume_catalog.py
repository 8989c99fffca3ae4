"""The bundle's own facts, from the volume's catalog: VOLDESC.CAT and the DATA_SET catalog.

Title, description and Citation_Information (authors, year, description) come from the
DATA_SET object (CATALOG/*.CAT, found by its content whatever the file is called); the
volume's VOLUME_ID and DATA_SET_ID(s) become aliases; the investigation, host, instrument
and target become context references only where PDS's registry snapshot holds the LID
(a reference to an unregistered LID resolves nowhere). A catalog file need not start as a
PDS3 label (genuine ones lack the header): it is parsed as ODL all the same.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from ..label.parser import LabelFile
from ..label.tree import Block
from ..pds4.context import TARGETS
from ..validate.pds4.context_registry import is_registered
from .identity import lid_part, observation
from .identity import text as keyword_text

_UNWRITTEN = "[TO BE WRITTEN"


def text(root: Block, key: str) -> str | None:
    """A keyword's text (identity.text), None where it is still to be written (pdsgen's own
    volumes mark such text so): a bundle label never carries a placeholder on."""
    value = keyword_text(root, key)
    return None if value is None or _UNWRITTEN in value else value


@dataclass
class BundleFacts:
    """What the bundle label says of the volume as a whole."""

    title: str = "PDS3 volume migrated to PDS4"
    description: str = "A PDS3 volume whose products are described in PDS4 labels, their files unchanged."
    citation: str = ""
    authors: str | None = None
    year: str | None = None
    keywords: list[str] = field(default_factory=list)
    aliases: list[tuple[str, str]] = field(default_factory=list)
    references: list[tuple[str, str]] = field(default_factory=list)  # (LID, reference_type)
    data_set_ids: list[str] = field(default_factory=list)


def read_catalog(path: Path) -> Block | None:
    """The ODL tree of a catalog file (with or without a PDS3 header); None when unreadable."""
    try:
        return LabelFile.read(path).root
    except OSError:
        return None


def volume_data_sets(voldesc: Path | None) -> list[str]:
    """The DATA_SET_IDs VOLDESC.CAT's VOLUME object names (none without one)."""
    volume = _volume_block(voldesc)
    statement = volume.get("DATA_SET_ID") if volume is not None else None
    ids = [str(v.py) for v in statement.value.scalars()] if statement is not None else []
    return [i for i in ids if i and i.upper() != "N/A"]


def _field(reference: object, name: str) -> object:
    return reference.get(name) if isinstance(reference, dict) else getattr(reference, name, None)


def _lid_of(reference: object) -> str | None:
    lid = _field(reference, "lid")
    return str(lid) if lid else None


def bundle_facts(voldesc: Path | None, catalogs: Iterable[Path], product_label: Path | None) -> BundleFacts:
    """The bundle's facts from VOLDESC.CAT, the DATA_SET catalog among `catalogs`, and (where the
    volume has no catalog, as pdsgen's own volumes) a product label's mission keywords."""
    facts = BundleFacts()
    volume = _volume_block(voldesc)
    data_set = next((b for path in catalogs if (root := read_catalog(path)) is not None
                     for b in root.walk() if b.name.upper() == "DATA_SET"), None)
    if volume is not None:
        _from_volume(facts, volume)
    if data_set is not None:
        _from_data_set(facts, data_set)
    product = LabelFile.read_pds3(product_label) if product_label is not None else None
    if product is not None and product_label is not None:
        _from_product(facts, product.root, product_label.name)
    facts.keywords = list(dict.fromkeys(k for k in facts.keywords if k))
    facts.references = list(dict.fromkeys(facts.references))
    facts.year = facts.year or None
    return facts


def _volume_block(voldesc: Path | None) -> Block | None:
    root = read_catalog(voldesc) if voldesc is not None else None
    if root is None:
        return None
    return next((b for b in root.walk() if b.name.upper() == "VOLUME"), None)


def _from_volume(facts: BundleFacts, volume: Block) -> None:
    volume_id, name = text(volume, "VOLUME_ID"), text(volume, "VOLUME_NAME")
    statement = volume.get("DATA_SET_ID")
    ids = [str(v.py) for v in statement.value.scalars()] if statement is not None else []
    facts.data_set_ids = [i for i in ids if i and i.upper() != "N/A"]  # as volume_data_sets
    for data_set_id in facts.data_set_ids:
        facts.aliases.append((data_set_id, "PDS3 DATA_SET_ID"))
    if volume_id:
        facts.aliases.append((volume_id, "PDS3 VOLUME_ID"))
        facts.title = f"{name or volume_id}: PDS3 volume {volume_id} in PDS4"
    description = text(volume, "DESCRIPTION")
    if description:
        facts.description = description
    date = text(volume, "PUBLICATION_DATE")
    facts.year = date[:4] if date and date[:4].isdigit() else None


def _from_data_set(facts: BundleFacts, data_set: Block) -> None:
    name = text(data_set, "DATA_SET_NAME")
    if name:
        facts.title = name
        facts.keywords.append(name)
    abstract = text(data_set, "ABSTRACT_DESC") or text(data_set, "DATA_SET_DESC")
    if abstract:
        facts.description = abstract
    facts.citation = text(data_set, "CITATION_DESC") or ""
    producers = [str(v.py) for b in data_set.walk() if (s := b.get("PRODUCER_FULL_NAME")) is not None
                 for v in s.value.scalars()]
    facts.authors = "; ".join(p for p in producers if p) or None
    release = text(data_set, "DATA_SET_RELEASE_DATE")
    if release and release[:4].isdigit():
        facts.year = release[:4]
    data_set_id = text(data_set, "DATA_SET_ID")
    if data_set_id and data_set_id not in facts.data_set_ids:
        facts.data_set_ids.append(data_set_id)
        facts.aliases.insert(0, (data_set_id, "PDS3 DATA_SET_ID"))
    _context(facts, data_set)


def _context(facts: BundleFacts, root: Block) -> None:
    """Mission, host, instrument and target as keywords, and as references where registered."""
    mission = text(root, "MISSION_NAME")
    host = text(root, "INSTRUMENT_HOST_ID") or text(root, "SPACECRAFT_ID")
    instrument = text(root, "INSTRUMENT_ID")
    target = text(root, "TARGET_NAME")
    facts.keywords += [mission or "", text(root, "INSTRUMENT_HOST_NAME") or host or "",
                       text(root, "INSTRUMENT_NAME") or instrument or "", (target or "").title()]
    candidates = []
    if mission:
        candidates.append((f"urn:nasa:pds:context:investigation:mission.{lid_part(mission)}",
                           "bundle_to_investigation"))
    if host:
        candidates.append((f"urn:nasa:pds:context:instrument_host:spacecraft.{lid_part(host)}",
                           "bundle_to_instrument_host"))
        if instrument:
            candidates.append((f"urn:nasa:pds:context:instrument:{lid_part(instrument)}.{lid_part(host)}",
                               "bundle_to_instrument"))
    if target:
        known = TARGETS.get(target.upper())
        if known is not None and known[2]:
            candidates.append((known[2], "bundle_to_target"))
    facts.references += [(lid, kind) for lid, kind in candidates if is_registered(lid)]


def _from_product(facts: BundleFacts, root: Block, label_name: str) -> None:
    """Where the volume has no DATA_SET catalog: the keywords of one product's label, and the
    context a single product's migration states (identity.observation: mission profiles first)."""
    if not facts.references:
        _context(facts, root)
        seen = observation(root, label_name)
        kinds = {"Host": "bundle_to_instrument_host", "Instrument": "bundle_to_instrument"}
        found = [(_lid_of(seen["investigation"]), "bundle_to_investigation"),
                 *((_lid_of(c), kinds.get(str(_field(c, "type")), "")) for c in seen["components"]),  # type: ignore[attr-defined]
                 (seen["target_lid"], "bundle_to_target")]
        facts.references += [(str(lid), kind) for lid, kind in found if lid and kind and is_registered(str(lid))]
    data_set_id = text(root, "DATA_SET_ID")
    if data_set_id and data_set_id not in facts.data_set_ids:
        facts.data_set_ids.append(data_set_id)
        facts.aliases.insert(0, (data_set_id, "PDS3 DATA_SET_ID"))
    if facts.title.startswith("PDS3 volume") or facts.title.endswith(" in PDS4"):
        name = text(root, "DATA_SET_NAME")
        if name:
            facts.title = f"{name} (PDS3 volume in PDS4)"
