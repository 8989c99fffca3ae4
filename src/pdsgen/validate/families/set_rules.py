"""SET family: products that belong together in one directory agree with each other.

Per file, a small picklable `LabelSummary` (validate/summary.py) is taken from the label (so a process pool can
return it); the set checks then compare summaries of one directory: shared projection
parameters, SOURCE_PRODUCT_ID references to products of the set, Extras and README.
SET-005 (a product label describes some data) is a set check too, because only the whole
run tells an empty product label from a fragment another label includes (^STRUCTURE).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from pathlib import Path

from ...label.tree import REFERENCE_POINTERS
from ..context import FileContext
from ..model import Hit
from ..profiles import hrsc_orbit, is_hirise, is_hrsc
from ..projection import normalise
from ..quantities import kilometres as _km
from ..quantities import number as _num
from ..registry import Rule, register
from ..summary import LabelSummary

# Product ids of a HiRISE-style DTM set (pds3-products.md section 3): a reference of this
# form in SOURCE_PRODUCT_ID names a product that must be in the same set.
SET_PRODUCT_ID = re.compile(
    r"DT[A-Z]{3}_\d{6}_\d{4}_\d{6}_\d{4}_[A-Z]\d{2}|[A-Z]{3}_\d{6}_\d{4}_(?:RED|IRB)_[A-Z]_\d{2}_ORTHO"
)
_PROJECTION_KEYS = ("MAP_PROJECTION_TYPE", "A_AXIS_RADIUS", "B_AXIS_RADIUS", "C_AXIS_RADIUS",
                    "CENTER_LATITUDE", "CENTER_LONGITUDE")


# Names of format and catalog files, which hold object definitions or catalog text for
# other labels to include or point at, not products of their own.
FRAGMENT_SUFFIXES = (".FMT", ".CAT")


def describes_data(ctx: FileContext) -> bool:
    """A data pointer (^IMAGE, ^TABLE ...), an OBJECT (IMAGE, TABLE, COMPRESSED_FILE,
    FILE ...) or a root ^STRUCTURE include (whose objects live in the included file)."""
    root = ctx.root
    has_object = any(block.kind == "OBJECT" for block in root.blocks())
    has_pointer = next(ctx.data_pointers(), None) is not None
    return has_object or has_pointer or root.get("^STRUCTURE") is not None


def referenced_files(ctx: FileContext) -> list[str]:
    """Upper-case base names of the files this label includes or points at for reference
    (^STRUCTURE, ^DATA_SET_CATALOG ...), at any depth."""
    names: set[str] = set()
    for block in ctx.root.walk():
        for stmt in block.statements():
            key = stmt.keyword.upper()
            if stmt.pointer and (key in REFERENCE_POINTERS or key.endswith("_CATALOG")):
                for value in stmt.value.scalars():
                    if value.kind in ("string", "ident"):
                        names.add(value.text.replace("\\", "/").rsplit("/", 1)[-1].strip().upper())
    return sorted(names)


def summarise(ctx: FileContext) -> LabelSummary:
    root = ctx.root
    summary = LabelSummary(str(ctx.path))
    summary.describes_nothing = ctx.size > 0 and not describes_data(ctx)  # empty: FILE-011 says it
    summary.first_line = ctx.label.first_line
    summary.referenced = referenced_files(ctx)
    stmt = root.get("PRODUCT_ID")
    if stmt is not None and stmt.value.items is None:
        summary.product_id, summary.product_id_line = stmt.value.text.strip(), stmt.line
    src = root.get("SOURCE_PRODUCT_ID")
    if src is not None:
        summary.sources = [str(v.py).strip() for v in src.value.scalars()]
        summary.sources_line = src.line
    block = next(root.find("IMAGE_MAP_PROJECTION"), None)
    if block is not None:
        name = normalise(block.text("MAP_PROJECTION_TYPE") or "")
        radii = tuple(_km(block, k) for k in _PROJECTION_KEYS[1:4])
        centre = tuple(_num(block, k) for k in _PROJECTION_KEYS[4:])
        summary.projection = (name, *radii, *centre)
        summary.projection_line = block.line
    return summary


def names_follow_product_id(ctx: FileContext) -> bool:
    """PDS3 does not tie PRODUCT_ID to the file name (Cassini ISS `1_N1472853667.118`, Dawn
    FC `0038582`); HiRISE, HRSC and pdsgen's own products do name files after it."""
    return ctx.written_by_pdsgen or is_hrsc(ctx) or is_hirise(ctx)


def check_product_id(ctx: FileContext) -> Iterator[Hit]:
    stmt = ctx.root.get("PRODUCT_ID")
    if stmt is None or stmt.value.items is not None or not names_follow_product_id(ctx):
        return
    pid = stmt.value.text.strip().upper()
    name = ctx.path.name.upper()
    stem = name.split(".")[0]
    if pid not in (stem, name) and pid.split(".")[0] != stem:
        yield Hit(f"PRODUCT_ID {stmt.value.text.strip()} does not match the file name {ctx.path.name}",
                  stmt.line, "PRODUCT_ID")


def _finding(summary: LabelSummary, message: str, line: int | None, keyword: str | None) -> Hit:
    """A problem of one product of the set: the runner adds rule id and severity."""
    return Hit(message, line, keyword, file=summary.path)


def by_directory(summaries: list[LabelSummary]) -> dict[str, list[LabelSummary]]:
    groups: dict[str, list[LabelSummary]] = {}
    for s in summaries:
        groups.setdefault(os.path.dirname(s.path), []).append(s)
    return dict(sorted(groups.items()))


def check_projections(summaries: list[LabelSummary], referenced: set[str] | None = None) -> Iterator[Hit]:
    """SET-001: map products that belong together share projection, radii and centre.

    Real volumes keep many unrelated products in one directory (an HRSC or LOLA DATA/
    folder: each DT4 sinusoidal about its own longitude), so only related products are
    compared: one that names another in SOURCE_PRODUCT_ID (an orthoimage and the DTM it
    was made on), products made from the same source images (one stereo pair), and HRSC
    products of one orbit and sequence."""
    for group in by_directory(summaries).values():
        for related in related_products(group):
            yield from _projections(related, "SET-001")


def _link_keys(s: LabelSummary) -> set[str]:
    """Keys two related products share: their own id, their sources, their HRSC orbit."""
    keys = {f"id:{ref.upper()}" for ref in s.sources if ref.upper() not in ("N/A", "UNK", "NULL")}
    if s.product_id:
        keys.add(f"id:{s.product_id.upper()}")
    orbit = hrsc_orbit(s.product_id or "") or hrsc_orbit(Path(s.path).name)
    if orbit:
        keys.add(f"hrsc:{orbit}")
    return keys


def related_products(group: list[LabelSummary]) -> list[list[LabelSummary]]:
    """Map products of one directory joined into sets of related products (see check_projections);
    a product related to nothing else is left out."""
    mapped = [s for s in group if s.projection is not None]
    owner: dict[str, int] = {}
    parent = list(range(len(mapped)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, s in enumerate(mapped):
        own = {f"id:{s.product_id.upper()}"} if s.product_id else set()
        for key in _link_keys(s):
            if key in owner and (key not in own or owner[key] != i):
                parent[root(i)] = root(owner[key])
            owner.setdefault(key, i)
    sets: dict[int, list[LabelSummary]] = {}
    for i, s in enumerate(mapped):
        sets.setdefault(root(i), []).append(s)
    return [members for members in sets.values() if len(members) > 1]


def is_delivery_set(directory: Path, group: list[LabelSummary]) -> bool:
    """Several map products together, or Extras/README.TXT begun: a set to check as a whole.
    A single product written on its own is not one (its sources may live elsewhere)."""
    products = [s for s in group if s.projection is not None and s.product_id]
    if not products:
        return False
    names = _names(directory)
    return len(products) >= 2 or "README.TXT" in {n.upper() for n in names} or any(
        "EXTRA" in n.upper() and (directory / n).is_dir() for n in names)


def check_sources(summaries: list[LabelSummary], referenced: set[str] | None = None) -> Iterator[Hit]:
    """SET-003: SOURCE_PRODUCT_ID values naming products of the set resolve within it."""
    for directory, group in by_directory(summaries).items():
        if is_delivery_set(Path(directory), group):
            yield from _sources(group, "SET-003")


def check_extras(summaries: list[LabelSummary], referenced: set[str] | None = None) -> Iterator[Hit]:
    """SET-004: a delivery set has README.TXT and a browse JPEG per product."""
    for directory, group in by_directory(summaries).items():
        yield from _extras(Path(directory), group, "SET-004")


def check_describes_data(summaries: list[LabelSummary], referenced: set[str] | None = None) -> Iterator[Hit]:
    """SET-005: a product label describes some data. Labels named *.FMT/*.CAT, and labels
    another label of the run includes or points at (`referenced`: names from every label
    of the run), are fragments and exempt."""
    if referenced is None:
        referenced = {name for s in summaries for name in s.referenced}
    for s in summaries:
        name = Path(s.path).name.upper()
        if s.describes_nothing and name not in referenced and not name.endswith(FRAGMENT_SUFFIXES):
            yield _finding(s, "the label describes no data: no data pointer (^IMAGE, "
                           "^TABLE ...) and no OBJECT (IMAGE, TABLE, COMPRESSED_FILE, FILE ...)",
                           s.first_line, None)


def _fmt(values: tuple) -> str:
    keys = ("type", "A", "B", "C", "CENTER_LATITUDE", "CENTER_LONGITUDE")
    return ", ".join(f"{k} {v}" for k, v in zip(keys, values, strict=False))


def _projections(group: list[LabelSummary], rule: str) -> Iterator[Hit]:
    mapped = [s for s in group if s.projection is not None]
    if len(mapped) < 2:
        return
    reference = next((s for s in mapped if (s.product_id or "").upper().startswith("DT")), mapped[0])
    for s in mapped:
        if s is reference:
            continue
        diffs = [
            (k, a, b) for k, a, b in zip(_PROJECTION_KEYS, reference.projection, s.projection, strict=False)  # type: ignore[arg-type]
            if not (a == b or (isinstance(a, float) and isinstance(b, float) and abs(a - b) <= 1e-9 * max(1.0, abs(a))))
        ]
        if diffs:
            what = "; ".join(f"{k} {b} vs {a}" for k, a, b in diffs)
            yield _finding(s, f"projection differs from {Path(reference.path).name}: "
                           f"{what}", s.projection_line, diffs[0][0])


def _sources(group: list[LabelSummary], rule: str) -> Iterator[Hit]:
    ids = {s.product_id.upper() for s in group if s.product_id}
    for s in group:
        for ref in s.sources:
            if SET_PRODUCT_ID.fullmatch(ref.upper()) and ref.upper() not in ids:
                yield _finding(s, f"SOURCE_PRODUCT_ID {ref} names a product that is "
                               "not in this directory", s.sources_line, "SOURCE_PRODUCT_ID")


def _extras(directory: Path, group: list[LabelSummary], rule: str) -> Iterator[Hit]:
    """A directory holding map products should have README.TXT and browse JPEGs (Extras)."""
    if not is_delivery_set(directory, group):
        return
    products = [s for s in group if s.projection is not None and s.product_id]
    names = _names(directory)
    extras_dirs = [directory / n for n in names if "EXTRA" in n.upper() and (directory / n).is_dir()]
    # a PDS3 volume keeps them beside DATA/, in EXTRAS/ (pdsgen deliver)
    extras_dirs += [p for p in (directory.parent / "EXTRAS",) if directory.name.upper() == "DATA" and p.is_dir()]
    for sub in extras_dirs:
        names |= _names(sub)
    upper = {n.upper() for n in names}
    if "README.TXT" not in upper:
        yield _finding(products[0], f"no README.TXT in {directory} or its "
                       "EXTRAS directory", None, None)
    # every "NAME." a browse JPEG's name starts with: one look-up per product, not a scan of the names
    jpeg_prefixes = {n[:i + 1] for n in upper if n.endswith(".JPG") for i, c in enumerate(n) if c == "."}
    for s in products:
        prefix = s.product_id.upper() + "."  # type: ignore[union-attr]
        if prefix not in jpeg_prefixes:
            yield _finding(s, f"no browse JPEG ({s.product_id}.*.jpg) for this "
                           "product in its directory or EXTRAS", s.product_id_line, "PRODUCT_ID")


def _names(directory: Path) -> set[str]:
    try:
        return set(os.listdir(directory))
    except OSError:
        return set()


register(
    Rule("SET-001", "error", "related products (an ortho and its DTM, one stereo pair, one HRSC orbit) "
         "share projection parameters", None, set_check=check_projections),
    Rule("SET-002", "error", "PRODUCT_ID matches the file name (HiRISE, HRSC and pdsgen products)",
         check_product_id),
    Rule("SET-003", "error", "SOURCE_PRODUCT_ID references to products of the set resolve", None,
         set_check=check_sources),
    Rule("SET-004", "warning", "a delivery set has README.TXT and browse JPEGs (Extras)", None,
         set_check=check_extras),
    Rule("SET-005", "warning", "a product label describes data: a data pointer or an OBJECT "
         "(*.FMT/*.CAT and labels others include are exempt)", None, set_check=check_describes_data),
)
