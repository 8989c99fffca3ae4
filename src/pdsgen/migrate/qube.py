"""QUBE and SPECTRAL_QUBE objects (ISIS2 cubes) as the PDS4 objects of the same bytes.

A cube's core is an Array_3D whose axes, slowest first, are AXIS_NAME reversed (PDS3 names
the fastest axis first; PDS4 arrays are Last Index Fastest). Suffix planes interleave with
the core, and an array has no stride, so they are described where they lie: suffix items
along the fastest axis (side planes) make each run of that axis a binary-table record;
planes along the slowest axis alone (back planes of a band-sequential cube) follow the whole
core as arrays of their own; planes along the middle axis (bottom planes) are described slice
by slice; side and back planes together make the core's runs records and each back plane a
table after the core. Back planes together with bottom planes are refused, naming them.
"""

from __future__ import annotations

from ..label.grammar import FLOAT_SAMPLE_TYPES
from ..pds4.model import pds4_data_type
from ..validate.context import FileContext
from .described import Refused, Target, positive_int, special_constants, where, with_structures
from .mapping import SPECIAL_CONSTANTS

# A cube's special-value keywords: the images' and tables' (mapping.py), and CORE_VALID_MINIMUM,
# which ISIS2 cubes give beside CORE_NULL and the CORE_*_SATURATION values.
QUBE_SPECIAL_CONSTANTS = {**SPECIAL_CONSTANTS, "CORE_VALID_MINIMUM": "valid_minimum"}
_AXIS_NAMES = {"SAMPLE": "Sample", "LINE": "Line", "BAND": "Band"}


def describe_qube(ctx: FileContext, target: Target) -> dict[str, object]:
    """The qube's core as Array_3D, or, with side planes, as records of a binary table."""
    block = with_structures(ctx, target.block)
    target = Target(block, target.ident, target.offset, target.path, target.record_bytes, target.next_start)
    axes = _axis_names(ctx, block)
    sizes = _numbers(ctx, block, "CORE_ITEMS", len(axes))
    item_bytes = positive_int(ctx, block, "CORE_ITEM_BYTES")
    item_type = (block.text("CORE_ITEM_TYPE") or "").upper()
    data_type = pds4_data_type(item_type, item_bytes * 8)
    if data_type is None:
        raise Refused(ctx.path, f"{where(block)}: CORE_ITEM_TYPE {item_type or 'not given'} of {item_bytes} bytes "
                                "has no PDS4 data type")
    suffix = _numbers(ctx, block, "SUFFIX_ITEMS", len(axes)) if block.get("SUFFIX_ITEMS") else [0] * len(axes)
    if any(n < 0 or n > _MAX_SUFFIX_ITEMS for n in suffix):
        raise Refused(ctx.path, f"{where(block)}: SUFFIX_ITEMS ({', '.join(map(str, suffix))}) is not {len(axes)} "
                                f"counts of 0 to {_MAX_SUFFIX_ITEMS}")
    planes_after = suffix[2] if not any(suffix[:2]) else 0  # suffix planes after the whole core (BSQ back planes)
    if planes_after:
        suffix = [0, 0, 0]
    if suffix[0] and suffix[2] and not suffix[1]:
        return _side_then_back_planes(ctx, target, axes, sizes, (data_type, item_bytes), suffix[0], suffix[2])
    if suffix[1] and not suffix[2]:
        return _slices_with_bottom_planes(ctx, target, axes, sizes, (data_type, item_bytes), suffix[0], suffix[1])
    if any(suffix[1:]):
        planes = [f"{_PLANE_OF[axis]} ({count})" for axis, count in zip(axes, suffix, strict=True) if count]
        raise Refused(ctx.path, f"{where(block)}: suffix planes ({', '.join(planes)} of SUFFIX_ITEMS) "
                                "interleave with the core; no PDS4 object describes them in place exactly")
    if suffix[0]:
        return _core_lines_with_suffix(ctx, target, axes, sizes, (data_type, item_bytes), suffix[0])
    is_float = item_type in FLOAT_SAMPLE_TYPES
    base, multiplier = block.number("CORE_BASE"), block.number("CORE_MULTIPLIER")
    identity = base in (None, 0) and multiplier in (None, 1)
    order = list(reversed(range(len(axes))))  # slowest first
    name = block.text("CORE_NAME")
    description = " ".join((block.text("DESCRIPTION") or f"The core of the {block.name} object of the PDS3 "
                            f"label{': ' + name if name else ''}, axes {', '.join(axes)} "
                            "(AXIS_NAME, fastest first).").split())
    count = 1
    for size in sizes:
        count *= size
    core: dict[str, object] = {
        "kind": "array", "element": "Array_3D", "local_identifier": target.ident, "offset": target.offset,
        "length": count * item_bytes, "axes": [(_AXIS_NAMES.get(axes[i], axes[i].title()), sizes[i]) for i in order],
        "description": description, "data_type": data_type, "unit": _core_unit(block),
        "scaling_factor": None if identity else (multiplier if multiplier is not None else 1.0),
        "value_offset": base if base is not None else 0.0,
        "special": special_constants(ctx, block, is_float, item_bytes * 8, QUBE_SPECIAL_CONSTANTS),
        "pds3": where(block),
    }
    if "LINE" in axes and "SAMPLE" in axes:  # what a map projection of the cube (cart:) is placed on
        core["lines"], core["samples"] = sizes[axes.index("LINE")], sizes[axes.index("SAMPLE")]
    if planes_after:
        core["extra"] = _planes_after_core(ctx, target, axes, sizes, target.offset + count * item_bytes, planes_after)
    return core


def _planes_after_core(ctx: FileContext, target: Target, axes: list[str], sizes: list[int], start: int,
                       count: int) -> list[dict[str, object]]:
    """Suffix planes along the slowest axis (back planes of a band-sequential cube) lie whole
    after the core: each is an Array_2D of the two faster axes, items of SUFFIX_BYTES (an item
    type of another size is refused: its place in the slot is not stated)."""
    block = target.block
    slowest = axes[2]
    slot = positive_int(ctx, block, "SUFFIX_BYTES")
    items = _typed_suffix_items(ctx, block, slowest, count, slot, "plane", "array")
    units = _suffix_list(block, f"{slowest}_SUFFIX_UNIT", count)
    plane = sizes[0] * sizes[1] * slot
    arrays = []
    for n, ((name, data_type), stated_unit) in enumerate(zip(items, units, strict=True)):
        unit = stated_unit if isinstance(stated_unit, str) and stated_unit.upper() not in ("N/A", "NONE", "UNK") \
            else None
        arrays.append({
            "kind": "array", "element": "Array_2D", "local_identifier": f"{target.ident}_{_PLANE_OF[slowest]}_{n + 1}",
            "offset": start + n * plane, "length": plane,
            "axes": [(_AXIS_NAMES[axes[1]], sizes[1]), (_AXIS_NAMES[axes[0]], sizes[0])],
            "description": f"{_PLANE_OF[slowest].capitalize()} plane {n + 1} of the {block.name} object: {name}.",
            "data_type": data_type, "unit": unit, "scaling_factor": None, "value_offset": 0.0, "special": [],
            "pds3": f"{where(block)} {_PLANE_OF[slowest]} plane {n + 1}"})
    return arrays


def _side_then_back_planes(ctx: FileContext, target: Target, axes: list[str], sizes: list[int],
                           core_type: tuple[str, int], side: int, back: int) -> dict[str, object]:
    """Side planes and back planes, no bottom planes: the core's runs with their side items
    (a table of a record per run), then each back plane whole after the core, its runs of
    (fastest axis + side) items of SUFFIX_BYTES (a table each, a record per run: the plane's
    items a group, the corner bytes a byte group)."""
    block = target.block
    table = _core_lines_with_suffix(ctx, target, axes, sizes, core_type, side)
    slowest, fast = axes[2], axes[0]
    slot = int(block.number("SUFFIX_BYTES") or 0)
    items = _typed_suffix_items(ctx, block, slowest, back, slot, "plane", "field")
    record = (sizes[0] + side) * slot
    start = target.offset + int(table["length"])  # type: ignore[call-overload]
    planes: list[dict[str, object]] = []
    for n, (name, field_type) in enumerate(items):
        fields: list[dict[str, object]] = [
            {"name": name, "location": 1, "length": slot, "data_type": field_type, "unit": None,
             "scaling_factor": None, "value_offset": None, "description": None, "special": [],
             "group": {"repetitions": sizes[0], "location": 1, "length": sizes[0] * slot}},
            {"name": "CORNER", "location": 1, "length": 1, "data_type": "UnsignedByte", "unit": None,
             "scaling_factor": None, "value_offset": None, "description": None, "special": [],
             "group": {"repetitions": side * slot, "location": 1 + sizes[0] * slot, "length": side * slot}}]
        planes.append({
            "kind": "table", "element": "Table_Binary",
            "local_identifier": f"{target.ident}_{_PLANE_OF[slowest]}_{n + 1}",
            "offset": start + n * sizes[1] * record, "length": sizes[1] * record, "records": sizes[1],
            "record_length": record, "fields": fields, "delimiter": None,
            "description": f"{_PLANE_OF[slowest].capitalize()} plane {n + 1} of the {block.name} object ({name}): a "
                           f"record per {fast.lower()} run, its {sizes[0]} items and {side * slot} corner bytes.",
            "pds3": f"{where(block)} {_PLANE_OF[slowest]} plane {n + 1}"})
    table["extra"] = planes
    return table


def _slices_with_bottom_planes(ctx: FileContext, target: Target, axes: list[str], sizes: list[int],
                               core_type: tuple[str, int], side: int, bottom: int) -> dict[str, object]:
    """Suffix planes along the middle axis (bottom planes of a band-sequential cube), with or
    without side planes: each slice of the slowest axis is its core runs (with their side
    items) then `bottom` suffix runs of (fastest axis + side) items of SUFFIX_BYTES. Each
    slice is described in place: its core (an Array_2D, or with side items a table of a
    record per run) and its bottom runs (a table: the bottom items a group, the corner bytes
    where side and bottom planes meet a byte group). Bottom items of several types, or narrower
    than SUFFIX_BYTES, are refused."""
    block = target.block
    data_type, item_bytes = core_type
    fast, middle, _ = axes
    slot = positive_int(ctx, block, "SUFFIX_BYTES")
    kinds = {(str(t or "").upper(), n) for t, n in zip(_suffix_list(block, f"{middle}_SUFFIX_ITEM_TYPE", bottom),
                                                        _suffix_list(block, f"{middle}_SUFFIX_ITEM_BYTES", bottom),
                                                        strict=True)}
    bottom_type = next(iter(kinds)) if len(kinds) == 1 else None
    field_type = (pds4_data_type(bottom_type[0], int(bottom_type[1]) * 8)
                  if bottom_type is not None and isinstance(bottom_type[1], int) else None)
    if field_type is None or bottom_type is None or bottom_type[1] != slot:
        raise Refused(ctx.path, f"{where(block)}: {_PLANE_OF[middle]} plane items ({', '.join(sorted(map(str, kinds)))}"
                                f") are not of one PDS4 type filling SUFFIX_BYTES {slot}")
    if sizes[2] > _MAX_SLICES:
        raise Refused(ctx.path, f"{where(block)}: {sizes[2]} {axes[2].lower()}s with {_PLANE_OF[middle]} planes, more "
                                f"than the {_MAX_SLICES} migrate describes one by one")
    side_table = _core_lines_with_suffix(ctx, target, axes, sizes, core_type, side) if side else None
    run = sizes[0] * item_bytes + side * slot
    bottom_record = (sizes[0] + side) * slot
    slice_bytes = sizes[1] * run + bottom * bottom_record
    plane = _PLANE_OF[middle]
    objects: list[dict[str, object]] = []
    for k in range(sizes[2]):
        start = target.offset + k * slice_bytes
        name = f"{axes[2].lower()} {k + 1}"
        if side_table is not None:
            core = {**side_table, "local_identifier": f"{target.ident}_{k + 1}", "offset": start,
                    "records": sizes[1], "length": sizes[1] * run,
                    "description": f"{name.capitalize()} of the {block.name} object: a record per {fast.lower()} run "
                                   f"with its {_PLANE_OF[fast]} plane item(s).", "pds3": f"{where(block)} {name}"}
        else:
            core = _slice_array(ctx, target, axes, sizes, core_type, start, k)
        bottom_fields: list[dict[str, object]] = [
            {"name": f"{middle}_SUFFIX", "location": 1, "length": slot, "data_type": field_type, "unit": None,
             "scaling_factor": None, "value_offset": None, "description": None, "special": [],
             "group": {"repetitions": sizes[0], "location": 1, "length": sizes[0] * slot}}]
        if side:
            bottom_fields.append({"name": "CORNER", "location": 1, "length": 1, "data_type": "UnsignedByte",
                                  "unit": None, "scaling_factor": None, "value_offset": None, "description": None,
                                  "special": [], "group": {"repetitions": side * slot,
                                                           "location": 1 + sizes[0] * slot, "length": side * slot}})
        objects += [core, {
            "kind": "table", "element": "Table_Binary", "local_identifier": f"{target.ident}_{k + 1}_{plane}",
            "offset": start + sizes[1] * run, "length": bottom * bottom_record, "records": bottom,
            "record_length": bottom_record, "fields": bottom_fields, "delimiter": None,
            "description": f"The {plane} plane of {name} of the {block.name} object: {bottom} run(s) of "
                           f"{sizes[0]} items" + (f" and the {side * slot} corner bytes." if side else "."),
            "pds3": f"{where(block)} {name} {plane} plane"}]
    first = objects[0]
    first["extra"] = objects[1:]
    return first


def _slice_array(ctx: FileContext, target: Target, axes: list[str], sizes: list[int], core_type: tuple[str, int],
                 start: int, k: int) -> dict[str, object]:
    """One slice of the slowest axis of a cube's core, as an Array_2D at `start`."""
    block = target.block
    data_type, item_bytes = core_type
    base, multiplier = block.number("CORE_BASE"), block.number("CORE_MULTIPLIER")
    identity = base in (None, 0) and multiplier in (None, 1)
    return {"kind": "array", "element": "Array_2D", "local_identifier": f"{target.ident}_{k + 1}", "offset": start,
            "length": sizes[0] * sizes[1] * item_bytes,
            "axes": [(_AXIS_NAMES[axes[1]], sizes[1]), (_AXIS_NAMES[axes[0]], sizes[0])],
            "description": f"{axes[2].capitalize()} {k + 1} of the core of the {block.name} object.",
            "data_type": data_type, "unit": _core_unit(block),
            "scaling_factor": None if identity else (multiplier if multiplier is not None else 1.0),
            "value_offset": base if base is not None else 0.0,
            "special": special_constants(ctx, block, data_type.startswith("IEEE"), item_bytes * 8,
                                         QUBE_SPECIAL_CONSTANTS),
            "pds3": f"{where(block)} {axes[2].lower()} {k + 1}"}


# The suffix plane a SUFFIX_ITEMS count along each axis makes (ISIS2 cubes).
_PLANE_OF = {"SAMPLE": "side", "LINE": "bottom", "BAND": "back"}


def _core_lines_with_suffix(ctx: FileContext, target: Target, axes: list[str], sizes: list[int],
                            core_type: tuple[str, int], count: int) -> dict[str, object]:
    """Suffix items along the fastest axis only (side planes of a SAMPLE-fastest cube): each run
    of the fastest axis with its suffix items is one record of a binary table - the core's
    items as a group, each suffix item a field - so no byte moves (an array has no stride).
    Suffix items of another size than SUFFIX_BYTES (the slot each is stored in) are refused:
    where in the slot the value lies is not stated."""
    block = target.block
    data_type, item_bytes = core_type
    fastest = axes[0]
    slot = positive_int(ctx, block, "SUFFIX_BYTES")
    fields: list[dict[str, object]] = [_core_field(ctx, block, data_type, item_bytes, sizes[0])]
    location = 1 + sizes[0] * item_bytes
    for n, (name, field_type) in enumerate(_typed_suffix_items(ctx, block, fastest, count, slot, "plane item",
                                                               "field")):
        fields.append({"name": name, "location": location, "length": slot,
                       "data_type": field_type, "unit": None, "scaling_factor": None, "value_offset": None,
                       "description": f"{_PLANE_OF[fastest].capitalize()} plane item {n + 1} of the PDS3 qube.",
                       "special": [], "group": None})
        location += slot
    record = sizes[0] * item_bytes + count * slot
    records = sizes[1] * sizes[2]
    description = (f"The {block.name} object's core with its {_PLANE_OF[fastest]} plane: each record one "
                   f"{fastest.lower()} run ({sizes[0]} items, AXIS_NAME {', '.join(axes)}) and its {count} suffix "
                   f"item(s); records {axes[1].lower()} by {axes[1].lower()}, then {axes[2].lower()} by "
                   f"{axes[2].lower()}. A PDS4 array cannot skip the suffix bytes.")
    return {"kind": "table", "element": "Table_Binary", "local_identifier": target.ident, "offset": target.offset,
            "length": records * record, "records": records, "record_length": record, "description": description,
            "fields": fields, "delimiter": None, "pds3": where(block)}


def _core_field(ctx: FileContext, block, data_type: str, item_bytes: int, count: int) -> dict[str, object]:
    base, multiplier = block.number("CORE_BASE"), block.number("CORE_MULTIPLIER")
    identity = base in (None, 0) and multiplier in (None, 1)
    is_float = data_type.startswith("IEEE")
    return {"name": "CORE", "location": 1, "length": item_bytes, "data_type": data_type, "unit": _core_unit(block),
            "scaling_factor": None if identity else (multiplier if multiplier is not None else 1.0),
            "value_offset": None if identity else (base or 0.0), "description": None,
            "special": special_constants(ctx, block, is_float, item_bytes * 8, QUBE_SPECIAL_CONSTANTS),
            "group": {"repetitions": count, "location": 1, "length": count * item_bytes}}


# More suffix items than any genuine cube has (ISIS2 cubes carry a few dozen back planes at most):
# a hostile count is refused before anything is built for it.
_MAX_SUFFIX_ITEMS = 10_000
# Slices of a cube with bottom planes are described one by one: a bound on how many.
_MAX_SLICES = 10_000


def _typed_suffix_items(ctx: FileContext, block, axis: str, count: int, slot: int, noun: str,
                        element: str) -> list[tuple[str, str]]:
    """(name, PDS4 data type) of each suffix item along `axis`; an item whose type PDS4 cannot
    state, or narrower than its slot (where in the slot the value lies is not stated), is refused
    as "<side|back|bottom> <noun> N ... has no exact PDS4 <element>"."""
    names = _suffix_list(block, f"{axis}_SUFFIX_NAME", count)
    types = _suffix_list(block, f"{axis}_SUFFIX_ITEM_TYPE", count)
    sizes_of = _suffix_list(block, f"{axis}_SUFFIX_ITEM_BYTES", count)
    items = []
    for n in range(count):
        pds3_type, size = str(types[n] or "").upper(), sizes_of[n]
        data_type = pds4_data_type(pds3_type, int(size) * 8) if isinstance(size, int) else None
        if data_type is None or size != slot:
            raise Refused(ctx.path, f"{where(block)}: {_PLANE_OF[axis]} {noun} {n + 1} ({pds3_type or 'no type'} "
                                    f"of {size} bytes in SUFFIX_BYTES {slot}) has no exact PDS4 {element}")
        items.append((str(names[n] or f"{axis}_SUFFIX_{n + 1}"), data_type))
    return items


def _suffix_list(block, key: str, count: int) -> list[object]:
    """A per-item suffix keyword as a list of `count` values (a scalar stands for one item)."""
    value = block.value(key)
    if value is None:
        return [None] * count
    items = value.items if value.items is not None else [value]
    found: list[object] = [item.number if item.is_number else item.text for item in items]
    return (found + [None] * count)[:count]


def _axis_names(ctx: FileContext, block) -> list[str]:
    value = block.value("AXIS_NAME")
    if value is None or value.items is None:
        raise Refused(ctx.path, f"{where(block)}: AXIS_NAME is missing or not a list of axes")
    names = [item.text.upper() for item in value.items]
    if len(names) != 3 or sorted(names) != ["BAND", "LINE", "SAMPLE"]:
        raise Refused(ctx.path, f"{where(block)}: AXIS_NAME ({', '.join(names)}) is not the three axes SAMPLE, "
                                "LINE and BAND in some order")
    return names


def _numbers(ctx: FileContext, block, key: str, count: int) -> list[int]:
    value = block.value(key)
    items = value.items if value is not None else None
    if items is None or len(items) != count or not all(i.is_number and isinstance(i.number, int) for i in items):
        raise Refused(ctx.path, f"{where(block)}: {key} is missing or not {count} integers")
    return [int(i.number) for i in items]


def _core_unit(block) -> str | None:
    unit = block.text("CORE_UNIT")
    return None if unit is None or unit.upper() in ("N/A", "UNK", "NULL", "NONE") else unit
