"""PTR and REC families: where objects start, and whether records add up to the file size.

Pointer forms (PDS3): `n` (record), `n <BYTES>`, `"F"`, `("F", n)`, `("F", n <BYTES>)`.
For FIXED_LENGTH files `RECORD_BYTES * FILE_RECORDS` is the exact file size and an
attached object starts right after the label's LABEL_RECORDS records.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from ...label.tree import Pointer, parse_pointer
from ..context import FileContext
from ..model import Hit
from ..registry import Rule, register
from .file_rules import padding_bytes
from .image_rules import object_bytes


def _kw(ptr: Pointer) -> str:
    return "^" + ptr.statement.keyword.upper()


def check_pointer_form(ctx: FileContext) -> Iterator[Hit]:
    for ptr in ctx.pointers:
        if ptr.form == "invalid":
            yield Hit(
                f"{_kw(ptr)} = {ptr.statement.value.raw[:40]} is not a PDS3 pointer "
                '(n, n <BYTES>, "FILE", ("FILE", n) or ("FILE", n <BYTES>))',
                ptr.statement.line,
                _kw(ptr),
            )
        elif (ptr.record is not None and ptr.record < 1) or (ptr.byte is not None and ptr.byte < 1):
            yield Hit(f"{_kw(ptr)} points to position {ptr.record or ptr.byte}; the first is 1",
                      ptr.statement.line, _kw(ptr))


def _named_targets(ctx: FileContext) -> Iterator[tuple[Pointer, str]]:
    """Each data pointer with each file it names (a set of files: every one of them)."""
    if ctx.labels_only:
        return
    for ptr in ctx.data_pointers():
        for file_name in ptr.targets:
            yield ptr, file_name


def check_target_exists(ctx: FileContext) -> Iterator[Hit]:
    for ptr, file_name in _named_targets(ctx):
        exact, other = ctx.resolve(file_name)
        if exact is None and other is None and ctx.outside(file_name) is None:  # PTR-009 tells the outside
            yield Hit(f"{_kw(ptr)} names {file_name}, which is not in {ctx.path.parent}",
                      ptr.statement.line, _kw(ptr))


def check_target_inside(ctx: FileContext) -> Iterator[Hit]:
    """Every file the label names lies inside the tree given (the directory validated, or
    --root; the label's directory for a label given alone), links resolved: a name leaving
    it (../x, /etc/x, a link pointing out) is read by no pdsgen command."""
    for keyword, name, line in ctx.outside_names():
        yield Hit(f"{keyword} names {name}, which lies outside {ctx.tree} (the tree given; "
                  "--root widens it); it is not read", line, keyword)


def _reference_pointers(ctx: FileContext) -> list[Pointer]:
    """Reference pointers at any depth (a TABLE's ^STRUCTURE is inside its OBJECT), ^..._STRUCTURE
    included (an include pointer by NASA's rule); found once."""
    found = ctx.cache.get("_reference_pointers")
    if found is None:
        found = ctx.cache["_reference_pointers"] = [
            ptr for block in ctx.root.walk() for stmt in block.statements() if stmt.pointer
            for ptr in (parse_pointer(stmt),) if ptr.is_reference or ptr.name.endswith("_STRUCTURE")]
    return found


def check_reference_exists(ctx: FileContext) -> Iterator[Hit]:
    """Files named by reference pointers (^STRUCTURE, ^DESCRIPTION, ^DATA_SET_CATALOG, ^TEXT ...)
    exist: beside the label, or in its volume's LABEL/, DOCUMENT/ or CATALOG/ directory inside
    the trusted tree (label/beside.find_reference, as a reader finds them). How much a missing
    one weighs: see _missing_reference_level."""
    from ...label.beside import INCLUDE_KINDS, VOLUME_DIRECTORIES, find_reference, pointer_kind, volume_root

    volume: tuple[Path, bool] | None = None
    for ptr in _reference_pointers(ctx):
        kind = pointer_kind(ptr.name)
        for name in ptr.targets:
            if ctx.outside(name) is not None:
                continue  # PTR-009 tells the outside
            if volume is None:
                volume = volume_root(ctx.path.parent, ctx.tree)
            if find_reference(ctx.path.parent, name, kind, ctx.tree, volume[0]) is not None:
                continue
            if ctx.labels_only and kind not in INCLUDE_KINDS:
                continue  # a document is not a label: a repository of labels goes without it
            level = _missing_reference_level(kind, volume[1], _holds_catalog(volume[0]))
            if level == "skip":
                continue
            # said without the directory's path: a delivery is checked in a work directory first
            where = f" or in a {VOLUME_DIRECTORIES[kind]} directory of its volume" if kind and "/" not in name else ""
            yield Hit(f"{_kw(ptr)} names {name}, which is not beside the label{where}", ptr.statement.line,
                      _kw(ptr), severity=level)


def _missing_reference_level(kind: str | None, whole_volume: bool, catalog_directory: bool) -> str | None:
    """A missing format file (^STRUCTURE) is an error in a volume given whole (VOLDESC.CAT in
    the tree): its table cannot be read there (NASA's PDS3 tools rate a missing referenced file
    an error); a warning for products checked without their volume, whose LABEL/ may hold it.
    A missing document (^DESCRIPTION = "JP2INFO.TXT", ^TEXT ...) is a warning: the product
    arrives without what describes it, though no reader misreads its data. A missing catalog
    file (^DATA_SET_MAP_PROJECTION = "DSMAP.CAT", ^..._CATALOG) is a warning in a volume given
    whole with a CATALOG/ directory that lacks it, a note in a volume that carries no CATALOG/
    at all (a data provider's delivery, such as pdsgen's own, whose catalog set the archive
    holds), and not reported for products checked alone: catalog files belong to the volume's
    CATALOG/, made once for all its products, never beside one."""
    if kind == "STRUCTURE":
        return None if whole_volume else "warning"
    if kind == "CATALOG":
        if not whole_volume:
            return "skip"
        return "warning" if catalog_directory else "info"
    return "warning"


def _holds_catalog(volume: Path) -> bool:
    """The volume carries a CATALOG/ directory (any case)."""
    from ...label.beside import directory_listing

    return any(name.upper() == "CATALOG" and (volume / name).is_dir() for name in directory_listing(volume))


def check_target_case(ctx: FileContext) -> Iterator[Hit]:
    for ptr, file_name in _named_targets(ctx):
        exact, other = ctx.resolve(file_name)
        if exact is None and other is not None:
            yield Hit(f"{_kw(ptr)} names {file_name} but the file is {other.name} "
                      "(case differs)", ptr.statement.line, _kw(ptr))


def _lowest_attached(ctx: FileContext) -> tuple[Pointer, int] | None:
    offsets = ((p, ctx.pointer_offset(p)) for p in ctx.data_pointers() if p.attached)
    found = [(p, o) for p, o in offsets if o is not None]
    return min(found, key=lambda po: po[1]) if found else None


def check_start_inside_label(ctx: FileContext) -> Iterator[Hit]:
    lowest = _lowest_attached(ctx)
    if lowest is None or not ctx.label.end_found:
        return
    ptr, offset = lowest
    if offset < ctx.label.label_end:
        yield Hit(f"{_kw(ptr)} starts at byte {offset + 1}, inside the label text "
                  f"(which ends at byte {ctx.label.label_end})", ptr.statement.line, _kw(ptr))


def _first_data_byte(pad: bytes) -> int | None:
    for i, b in enumerate(pad):
        if b not in b" \r\n\x00":
            return i
    return None


def check_start_blank_gap(ctx: FileContext) -> Iterator[Hit]:
    """Data found before the pointed start byte: the pointer is too large."""
    lowest = _lowest_attached(ctx)
    found = padding_bytes(ctx) if lowest is not None and ctx.label.end_found else None
    if not found or not found[1]:
        return
    ptr, offset = lowest  # type: ignore[misc]
    first = _first_data_byte(found[1])
    if first is not None:
        at = ctx.label.label_end + first + 1
        yield Hit(f"non-blank bytes at byte {at}, before {_kw(ptr)} start byte {offset + 1}: "
                  "the pointer or LABEL_RECORDS is too large", ptr.statement.line, _kw(ptr))


def check_start_possible(ctx: FileContext) -> Iterator[Hit]:
    """The object's first bytes are blanks: harmless, or the pointer is too small."""
    lowest = _lowest_attached(ctx)
    if lowest is None or ctx.labels_only or not ctx.label.end_found:
        return
    ptr, offset = lowest
    if offset < ctx.label.label_end or offset >= ctx.size:
        return
    with open(ctx.path, "rb") as fh:
        fh.seek(offset)
        chunk = fh.read(256)
    blanks = len(chunk) - len(chunk.lstrip(b" \r\n"))
    if 0 < blanks < len(chunk):
        yield Hit(f"{_kw(ptr)} data begins with {blanks} blank byte(s) (data may start at byte "
                  f"{offset + blanks + 1}, pointer says {offset + 1})", ptr.statement.line, _kw(ptr))


def check_data_present(ctx: FileContext) -> Iterator[Hit]:
    """Said once for a label-only copy of an attached label: the data are absent, so nothing
    is checked (or computed) from them, and no error is reported about them."""
    if ctx.data_absent and not ctx.labels_only:
        lowest = _lowest_attached(ctx)
        where = f"; {_kw(lowest[0])} starts at byte {lowest[1] + 1}" if lowest else ""
        yield Hit(f"the file ends with its label ({ctx.size} bytes{where}): a label-only copy, "
                  "the data it describes are absent; data checks skipped",
                  lowest[0].statement.line if lowest else None, _kw(lowest[0]) if lowest else None)


def check_record_bytes_present(ctx: FileContext) -> Iterator[Hit]:
    for block in ctx.root.walk():
        rt = block.get("RECORD_TYPE")
        if rt is not None and rt.value.text.upper() == "FIXED_LENGTH" and block.get(
            "RECORD_BYTES"
        ) is None:
            yield Hit("RECORD_TYPE = FIXED_LENGTH needs RECORD_BYTES", rt.line, "RECORD_BYTES")


def _fixed_records(ctx: FileContext) -> tuple[int, int] | None:
    root = ctx.root
    if root.text("RECORD_TYPE") != "FIXED_LENGTH":
        return None
    rb, fr = root.number("RECORD_BYTES"), root.number("FILE_RECORDS")
    if not isinstance(rb, int) or not isinstance(fr, int):
        return None
    return rb, fr


def _record_file(ctx: FileContext) -> tuple[int, str] | None:
    """(size, name) of the file RECORD_BYTES/FILE_RECORDS describe, if known."""
    if ctx.attached:
        return ctx.size, ctx.path.name
    names = {p.file_name for p in ctx.data_pointers() if p.file_name}
    if len(names) != 1:
        return None
    ptr = next(p for p in ctx.data_pointers() if p.file_name)
    path = ctx.target_path(ptr)
    return (path.stat().st_size, path.name) if path is not None else None


def check_file_size(ctx: FileContext) -> Iterator[Hit]:
    records = _fixed_records(ctx)
    if records is None or ctx.labels_only:
        return
    target = _record_file(ctx)
    if target is None:
        return
    size, name = target
    rb, fr = records
    if rb * fr != size:
        stmt = ctx.root.get("FILE_RECORDS")
        yield Hit(f"RECORD_BYTES x FILE_RECORDS = {rb} x {fr} = {rb * fr} bytes, but {name} has "
                  f"{size} bytes", stmt.line if stmt else None, "FILE_RECORDS")


def check_label_records(ctx: FileContext) -> Iterator[Hit]:
    root = ctx.root
    stmt = root.get("LABEL_RECORDS")
    if stmt is None or not ctx.attached or not ctx.label.end_found:
        return
    val = stmt.value
    if val.kind != "int":
        return
    unit = (val.unit or "").upper()
    rb = ctx.record_bytes
    if unit == "BYTES":
        label_space = int(val.number)
    elif rb is None:
        return
    else:
        label_space = int(val.number) * rb
    if label_space < ctx.label.label_end:
        yield Hit(f"LABEL_RECORDS gives {label_space} bytes but the label text takes "
                  f"{ctx.label.label_end}", stmt.line, "LABEL_RECORDS")
    lowest = _lowest_attached(ctx)
    if lowest is not None and lowest[1] != label_space:
        ptr, offset = lowest
        expect = f"{label_space + 1} <BYTES>" if ptr.byte is not None else (
            f"{label_space // rb + 1}" if rb else "?")
        yield Hit(f"{_kw(ptr)} starts at byte {offset + 1} but LABEL_RECORDS ends the label at "
                  f"byte {label_space}: expected {_kw(ptr)} = {expect}", ptr.statement.line,
                  _kw(ptr))


def check_required_storage(ctx: FileContext) -> Iterator[Hit]:
    for block in ctx.root.walk():
        stmt = block.get("REQUIRED_STORAGE_BYTES")
        if stmt is None or not stmt.value.is_number:
            continue
        for unc in ctx.root.find("UNCOMPRESSED_FILE"):
            rb, fr = unc.number("RECORD_BYTES"), unc.number("FILE_RECORDS")
            if isinstance(rb, int) and isinstance(fr, int) and rb * fr != stmt.value.py:
                yield Hit(f"REQUIRED_STORAGE_BYTES = {stmt.value.py}, expected RECORD_BYTES x "
                          f"FILE_RECORDS of {unc.name} = {rb} x {fr} = {rb * fr}", stmt.line,
                          "REQUIRED_STORAGE_BYTES")
            break


def check_object_fits_records(ctx: FileContext) -> Iterator[Hit]:
    """Label arithmetic only: the object must fit in the records the label declares."""
    records = _fixed_records(ctx)
    if records is None:
        return
    rb, fr = records
    for ptr in ctx.data_pointers():
        if ptr.form in ("file", "files", "invalid") and ptr.file_name is None:
            continue
        block = ctx.object_for(ptr)
        offset = ctx.pointer_offset(ptr)
        need = object_bytes(block) if block is not None else None
        if need is None or offset is None:
            continue
        if offset + need > rb * fr:
            yield Hit(f"{ptr.name} needs bytes {offset + 1}..{offset + need} but "
                      f"RECORD_BYTES x FILE_RECORDS = {rb * fr}", ptr.statement.line, _kw(ptr))


def check_object_in_file(ctx: FileContext) -> Iterator[Hit]:
    """The data file must hold every byte of the object (a truncated file fails here)."""
    if ctx.labels_only:
        return
    for ptr in ctx.data_pointers():
        if ptr.form in ("files", "invalid"):
            continue
        block = ctx.object_for(ptr)
        offset = ctx.pointer_offset(ptr)
        need = object_bytes(block) if block is not None else None
        size = ctx.target_size(ptr)
        if need is None or offset is None or size is None:
            continue
        if offset + need > size:
            name = ptr.file_name or ctx.path.name
            yield Hit(f"{ptr.name} needs bytes {offset + 1}..{offset + need} of {name}, which has "
                      f"only {size} bytes (truncated?)", ptr.statement.line, _kw(ptr))


def check_uncompressed_records(ctx: FileContext) -> Iterator[Hit]:
    """An UNCOMPRESSED_FILE holds exactly its IMAGE: RECORD_BYTES x FILE_RECORDS = image bytes
    (ISIS's JP2 exporter forgets the band count here)."""
    for block in ctx.root.find("UNCOMPRESSED_FILE"):
        rb, fr = block.number("RECORD_BYTES"), block.number("FILE_RECORDS")
        image = next((b for b in block.blocks() if b.kind == "OBJECT" and b.get("LINES") is not None), None)
        need = object_bytes(image) if image is not None else None
        if isinstance(rb, int) and isinstance(fr, int) and need is not None and rb * fr != need:
            stmt = block.get("FILE_RECORDS")
            yield Hit(f"{block.name}: RECORD_BYTES x FILE_RECORDS = {rb} x {fr} = {rb * fr} bytes, but "
                      f"its {image.name} holds {need} bytes (LINES x LINE_SAMPLES x BANDS x "
                      "sample bytes)", stmt.line if stmt else block.line, "FILE_RECORDS")


def check_records_accounted(ctx: FileContext) -> Iterator[Hit]:
    """FILE_RECORDS no larger than the objects need (label arithmetic, and the file's size).

    Checked only when every data object's size is known from its keywords. Records at the
    end that no object describes, in a file that really has them (RECORD_BYTES x
    FILE_RECORDS = its size), mislead no reader: genuine archives have such an end-of-file
    record, so that is a warning. Where the file does not have them, the label's arithmetic
    is broken - a keyword (often LINES) was edited - and the data cannot be where the label
    says: an error. Where the data file could not be looked at (absent, a label-only copy,
    --labels-only) only the label is known, and PDS3 permits records no object describes:
    a warning that says so.
    """
    records = _fixed_records(ctx)
    if records is None or records[0] <= 0:  # no record to count in (REC-002 tells the size)
        return
    rb, fr = records
    ends = []
    for ptr in ctx.data_pointers():
        block = ctx.object_for(ptr)
        offset = ctx.pointer_offset(ptr)
        need = object_bytes(block) if block is not None else None
        if need is None or offset is None or ptr.form in ("files", "invalid"):
            return
        ends.append(offset + need)
    if not ends or len({p.file_name for p in ctx.data_pointers()}) != 1:
        return
    needed = -(-max(ends) // rb)
    if fr <= needed:
        return
    stmt = ctx.root.get("FILE_RECORDS")
    line = stmt.line if stmt else None
    gap = f"FILE_RECORDS = {fr} but the objects end in record {needed}: {fr - needed} records of {rb} bytes"
    target = None if ctx.labels_only or ctx.data_absent else _record_file(ctx)
    if target is None:
        why = "--labels-only" if ctx.labels_only else \
            "a label-only copy" if ctx.data_absent else "not found beside the label"
        yield Hit(f"{gap} hold no described object; the data file could not be looked at ({why}), so "
                  "whether it has them is unknown (PDS3 permits records no object describes)", line,
                  "FILE_RECORDS", severity="warning")
        return
    if target[0] == rb * fr:
        yield Hit(f"{gap} at the end of {target[1]} hold no described object; the file has them "
                  f"({target[0]} bytes), so no reader is misled", line, "FILE_RECORDS", severity="warning")
        return
    yield Hit(f"{gap} hold no described object and {target[1]} has {target[0]} bytes, not {rb * fr} "
              "(an edited LINES?)", line, "FILE_RECORDS")


def _include_walk(ctx: FileContext):
    """The label's include walk (label/includes.py), inside the trusted tree; made once per label."""
    from ...label.includes import IncludeWalk  # start-up: loaded only for a label with includes

    walk = ctx.cache.get("_include_walk")
    if walk is None:
        walk = ctx.cache["_include_walk"] = IncludeWalk(ctx.tree)
    return walk


def check_include_loops(ctx: FileContext) -> Iterator[Hit]:
    """Include pointers (^STRUCTURE, ^CATALOG and their _STRUCTURE/_CATALOG forms) must not
    lead back to a file already being included. The files are found as a reader finds them
    (beside the including file, else in the volume's LABEL/ or CATALOG/ directory, inside the
    trusted tree), read by the one label reader with its bound, each once: a fan-out of files
    including each other four times over, 20 deep, is 20 reads, not 4^19 paths."""
    from ...label.beside import is_include

    if not any(is_include(ptr.name) for ptr in _reference_pointers(ctx)):
        return  # nothing to walk (and the walk's module not loaded)
    reported: set[str] = set()
    for keyword, line, loop in _include_walk(ctx).loops(ctx.path, ctx.label):
        text = " -> ".join(p.name for p in loop)
        if text not in reported:
            reported.add(text)
            yield Hit(f"{keyword} include loop: {text}", line, keyword)


register(
    Rule("PTR-001", "error", "pointers have a PDS3 form: n, n <BYTES>, \"F\", (\"F\", n)",
         check_pointer_form),
    Rule("PTR-002", "error", "files named by data pointers exist", check_target_exists,
         needs_data=True),
    Rule("PTR-003", "error", "files named by pointers match in case", check_target_case,
         needs_data=True),
    Rule("PTR-004", "error", "attached data do not start inside the label text",
         check_start_inside_label),
    Rule("PTR-005", "error", "no data between the label's END and the pointed start byte",
         check_start_blank_gap),
    Rule("PTR-006", "info", "attached data begin with blanks (start may be later)",
         check_start_possible, needs_data=True),
    Rule("PTR-007", "error", "include pointers (^STRUCTURE, ^CATALOG ...) do not loop back", check_include_loops,
         note="followed with --labels-only too: included files are labels, not data"),
    Rule("PTR-008", "warning", "an attached label's file holds its data (not a label-only copy; "
         "data checks are skipped for one)", check_data_present),
    Rule("PTR-009", "error", "files a label names lie inside the tree given (the directory validated, "
         "--root, or the label's directory; no ../, absolute path or link leading out)", check_target_inside),
    Rule("PTR-010", "error", "files named by reference pointers (^STRUCTURE, ^DESCRIPTION, ^..._CATALOG) exist "
         "beside the label or in its volume's LABEL/DOCUMENT/CATALOG directory", check_reference_exists,
         note="error for a format file (^STRUCTURE) in a volume given whole (VOLDESC.CAT), else a warning; "
         "catalog files are looked for only in a volume given whole"),
    Rule("REC-001", "error", "RECORD_TYPE = FIXED_LENGTH comes with RECORD_BYTES",
         check_record_bytes_present),
    Rule("REC-002", "error", "RECORD_BYTES x FILE_RECORDS equals the file size", check_file_size,
         needs_data=True),
    Rule("REC-003", "error", "LABEL_RECORDS hold the label and end where attached data start",
         check_label_records),
    Rule("REC-004", "error", "REQUIRED_STORAGE_BYTES = RECORD_BYTES x FILE_RECORDS of the image",
         check_required_storage),
    Rule("REC-005", "error", "objects fit in RECORD_BYTES x FILE_RECORDS", check_object_fits_records),
    Rule("REC-006", "error", "the data file holds every byte of each object (not truncated)",
         check_object_in_file, needs_data=True),
    Rule("REC-007", "error", "an UNCOMPRESSED_FILE's records hold exactly its IMAGE",
         check_uncompressed_records),
    Rule("REC-008", "error", "FILE_RECORDS no larger than the described objects need",
         check_records_accounted, note="warning where the file really has the undescribed records "
         "at its end, RECORD_BYTES x FILE_RECORDS being its size: no reader misreads them; warning "
         "where the data file could not be looked at (absent, label-only copy, --labels-only)"),
)
