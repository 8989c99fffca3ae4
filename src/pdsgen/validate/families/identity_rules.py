"""IDN family: what a product says of itself - its identifier, when it was made, the time it
covers - is stated and possible, in any dialect (PDS3 labels, PDS4 labels, in a delivery or not).

- IDN-001: a PDS3 map or image product without PRODUCT_ID (an index row, an inventory, a
  SOURCE_PRODUCT_ID of another product cannot name it).
- IDN-002 / IDN-012: a creation time later than now (PDS3 PRODUCT_CREATION_TIME; PDS4
  creation_date_time of a File, modification_date of the history): a product cannot be made
  in the future. "Now" is read through `now()` alone (SOURCE_DATE_EPOCH when set, a
  reproducible build's time), with a day's slack for a time written in a local zone.
- IDN-003 / IDN-013: a stop time before its start (PDS3 START_TIME / STOP_TIME; PDS4
  Time_Coordinates): warnings, as NASA's validate passes its own test products 604-1 and 605-1,
  which stop six days before they start.
- IDN-004: a product made before a source it names (an orthoimage made before the DTM its
  SOURCE_PRODUCT_ID names): across the labels of the run, in the parent process.

Times are read by the label package's one reader of PDS times (label/mapping.utc_datetime: PDS3
and PDS4 both write ISO 8601 UTC times, calendar or day-of-year); one it cannot read is left to
the syntax rules.
"""

from __future__ import annotations

import datetime
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ... import clock
from ...label.mapping import utc_datetime as parse_time
from ..model import Hit
from ..registry import Rule, register

if TYPE_CHECKING:
    from lxml import etree

    from ...label.read import LabelCache
    from ..context import FileContext

_SLACK = datetime.timedelta(days=1)  # a creation time written in a local zone runs up to 14 h ahead of UTC
_UNSTATED = frozenset({"UNK", "N/A", "UNKNOWN", "NULL"})
# PDS3 objects whose label is a map or image product (what IDN-001 asks a PRODUCT_ID of)
_PRODUCT_OBJECTS = ("IMAGE", "IMAGE_MAP_PROJECTION", "SPECTRAL_QUBE", "QUBE")
PDS_NS = "{http://pds.nasa.gov/pds4/pds/v1}"


def now() -> datetime.datetime:
    """The validator's "now" (naive UTC), from pdsgen's one clock: SOURCE_DATE_EPOCH when set (the
    time of making a reproducible run's products states), else the system's time."""
    return clock.now().replace(tzinfo=None)


def _future(when: datetime.datetime | None) -> bool:
    return when is not None and when > now() + _SLACK


def _future_message(keyword: str, text: str) -> str:
    return (f"{keyword} {text} is later than now ({now():%Y-%m-%dT%H:%M:%S} UTC): a product cannot be made in the "
            "future (a clock set wrong, or a mistyped year)")


# --- PDS3 ---------------------------------------------------------------------------------------

def check_product_id(ctx: FileContext) -> Iterator[Hit]:
    """IDN-001: a map or image product label states its PRODUCT_ID."""
    root = ctx.root
    if root.get("PRODUCT_ID") is not None:
        return
    if any(block.kind == "OBJECT" and block.name.upper() in _PRODUCT_OBJECTS for block in root.walk()):
        yield Hit("no PRODUCT_ID: an index row, a collection inventory or another product's SOURCE_PRODUCT_ID "
                  "cannot name this product (state it in the label)", ctx.label.first_line, "PRODUCT_ID")


def check_creation_time(ctx: FileContext) -> Iterator[Hit]:
    """IDN-002: PRODUCT_CREATION_TIME is not in the future."""
    stmt = ctx.root.get("PRODUCT_CREATION_TIME")
    if stmt is not None and stmt.value.items is None and _future(parse_time(stmt.value.text)):
        yield Hit(_future_message("PRODUCT_CREATION_TIME", stmt.value.text.strip()), stmt.line,
                  "PRODUCT_CREATION_TIME")


def check_time_order(ctx: FileContext) -> Iterator[Hit]:
    """IDN-003: STOP_TIME is not before START_TIME (top level, or within one object)."""
    for block in ctx.root.walk():
        start, stop = block.get("START_TIME"), block.get("STOP_TIME")
        if start is None or stop is None or start.value.items is not None or stop.value.items is not None:
            continue
        begin, end = parse_time(start.value.text), parse_time(stop.value.text)
        if begin is not None and end is not None and end < begin:
            yield Hit(f"STOP_TIME {stop.value.text.strip()} is before START_TIME {start.value.text.strip()}",
                      stop.line, "STOP_TIME")


def made_before_sources(labels: LabelCache | None = None) -> Callable[[str], list[Hit]]:
    """IDN-004 across the run: each PDS3 product's PRODUCT_ID, creation time and sources, as
    its label passes; a product made before a source it names is reported on the second of
    the two to pass (the message names both). `labels`: the run's label cache, so a label the
    file's own checks parsed is not parsed again."""
    made: dict[str, tuple[datetime.datetime, str]] = {}  # PRODUCT_ID -> (creation time, label)
    waiting: dict[str, list[tuple[datetime.datetime, str, int | None]]] = {}  # source id -> products naming it

    def observe(path: str) -> list[Hit]:
        facts = _product_facts(path, labels)
        if facts is None:
            return []
        product_id, created, sources, line = facts
        hits = []
        for source in sources:
            known = made.get(source)
            if known is not None and created < known[0]:
                hits.append(_before_hit(created, source, known[0], known[1], line))
            elif known is None:
                waiting.setdefault(source, []).append((created, path, line))
        if product_id:
            made[product_id] = (created, path)
            for product_time, product_path, product_line in waiting.pop(product_id, []):
                if product_time < created:
                    hits.append(Hit(f"{_before(product_time, product_id, created)} ({Path(path).name})",
                                    product_line, "PRODUCT_CREATION_TIME", file=product_path))
        return hits

    return observe


def _before(created: datetime.datetime, source: str, source_time: datetime.datetime) -> str:
    return (f"made {created:%Y-%m-%dT%H:%M:%S}, before its source {source} "
            f"(made {source_time:%Y-%m-%dT%H:%M:%S}): a product cannot be made from one not yet made")


def _before_hit(created: datetime.datetime, source: str, source_time: datetime.datetime, source_path: str,
                line: int | None) -> Hit:
    return Hit(f"{_before(created, source, source_time)} ({Path(source_path).name})", line, "PRODUCT_CREATION_TIME")


def _product_facts(path: str, labels: LabelCache | None) -> tuple[str | None, datetime.datetime, list[str],
                                                                   int | None] | None:
    """(PRODUCT_ID, creation time, SOURCE_PRODUCT_IDs, line of the time) of a PDS3 label that
    states its creation time; None for any other file."""
    from ...formats.sniff import file_head
    from ...label.read import is_pds3_head, read_pds3_label  # loaded when a run has PDS3 labels

    if not is_pds3_head(file_head(path, 64) or b""):  # an image, a table ...: 64 bytes tell, not 256 KiB
        return None
    try:
        label = read_pds3_label(Path(path), labels)
    except (OSError, ValueError):
        return None
    if label is None:
        return None
    root = label.root
    stmt = root.get("PRODUCT_CREATION_TIME")
    created = parse_time(stmt.value.text) if stmt is not None and stmt.value.items is None else None
    if created is None or stmt is None:
        return None
    ident = root.get("PRODUCT_ID")
    product_id = ident.value.text.strip().upper() if ident is not None and ident.value.items is None else None
    sources_stmt = root.get("SOURCE_PRODUCT_ID")
    sources = [str(v.py).strip().upper() for v in sources_stmt.value.scalars()] if sources_stmt is not None else []
    return product_id, created, sources, stmt.line


# --- PDS4 ---------------------------------------------------------------------------------------

def _pds4_tree(path: Path) -> etree._Element | None:
    from lxml import etree

    try:
        root = etree.parse(str(path), etree.XMLParser(no_network=True, resolve_entities=False)).getroot()
    except (OSError, etree.XMLSyntaxError):
        return None  # PDS4-001 says why
    return root if isinstance(root.tag, str) and root.tag.startswith(PDS_NS + "Product_") else None


def _pds4_check(find: Callable[[etree._Element], Iterable[Hit]]) -> Callable[[Any], list[Hit]]:
    """A PDS4 rule's check: `find` over the label's parsed tree (nothing for an unreadable one)."""

    def check(label: Any) -> list[Hit]:
        root = _pds4_tree(Path(label.path))
        return list(find(root)) if root is not None else []

    check.__name__ = find.__name__
    return check


def pds4_future_times(root: etree._Element) -> Iterator[Hit]:
    """IDN-012: no creation_date_time or modification_date later than now."""
    for tag in ("creation_date_time", "modification_date"):
        for element in root.iter(f"{PDS_NS}{tag}"):
            text = (element.text or "").strip()
            if _future(parse_time(text)):
                yield Hit(_future_message(tag, text), element.sourceline, tag)


def pds4_time_order(root: etree._Element) -> Iterator[Hit]:
    """IDN-013: Time_Coordinates stop_date_time is not before start_date_time."""
    for area in root.iter(f"{PDS_NS}Time_Coordinates"):
        start = area.find(f"{PDS_NS}start_date_time")
        stop = area.find(f"{PDS_NS}stop_date_time")
        begin = parse_time(start.text) if start is not None else None
        end = parse_time(stop.text) if stop is not None else None
        if begin is not None and end is not None and stop is not None and end < begin:
            yield Hit(f"stop_date_time {(stop.text or '').strip()} is before start_date_time "
                      f"{(start.text or '').strip() if start is not None else ''}", stop.sourceline, "stop_date_time")


def pds4_unstated(root: etree._Element) -> Iterator[Hit]:
    """The investigation, observing system components and targets a PDS4 label leaves unnamed
    ("UNK", "N/A", "Unknown"): DLV-008 (delivery_rules.py), the PDS4 side of DLV-007."""
    for area in ("Investigation_Area", "Observing_System_Component", "Target_Identification"):
        for element in root.iter(f"{PDS_NS}{area}"):
            name = element.find(f"{PDS_NS}name")
            if name is not None and (name.text or "").strip().upper() in _UNSTATED:
                yield Hit(f"{area} name {(name.text or '').strip()}: not stated (write it in a params file and make "
                          "the product again)", name.sourceline, "name")


pds4_unstated_check = _pds4_check(pds4_unstated)


register(
    Rule("IDN-001", "warning", "a PDS3 map or image product states its PRODUCT_ID", check_product_id),
    Rule("IDN-002", "warning", "PRODUCT_CREATION_TIME is not later than now (SOURCE_DATE_EPOCH when set)",
         check_creation_time),
    Rule("IDN-003", "warning", "STOP_TIME is not before START_TIME", check_time_order),
    Rule("IDN-004", "warning", "a product is not made before a source its SOURCE_PRODUCT_ID names (across the run)",
         None, run_check=made_before_sources),
    Rule("IDN-012", "warning", "PDS4 creation_date_time and modification_date are not later than now",
         _pds4_check(pds4_future_times), target="pds4"),
    Rule("IDN-013", "warning", "PDS4 Time_Coordinates stop_date_time is not before start_date_time (NASA's test "
                               "products 604-1 and 605-1 hold one: a warning, as a deviation genuine products carry)",
         _pds4_check(pds4_time_order), target="pds4"),
)
