"""README.TXT as the index of an Extras directory: read back, merged, replaced atomically.

Several `pdsgen extras` calls may write into one directory, one after another or
at the same time (a batch runs them in parallel), and README.TXT must describe all
of their products. Nothing hidden is kept for that: README.TXT itself is read
back (its product entries and producer keywords, with the field grammar of
`readme_txt`), the Extras files each entry names are looked up in the
directory, and the merged README.TXT replaces the old one by an atomic rename.

The read-merge-write runs under an exclusive `fcntl.flock` on the directory
itself (no lock file is left behind), so concurrent calls take turns and none
loses another's entries. Products whose Extras files are no longer all in the
directory are dropped; a product given again replaces its entry in place.
"""

from __future__ import annotations

import fcntl
import os
import re
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path

from ..errors import PdsgenError
from ..storage.staging import StagedOutputs, on_rollback
from .readme_txt import (
    DIRECTORY_FIELDS,
    ENTRY_FIELDS,
    FILES_LABEL,
    PRODUCT_ID_LABEL,
    README_NAME,
    Entry,
    entry_files,
    keyword_defaults,
    render_readme,
)

# What earlier pdsgen versions kept beside README.TXT; removed when found.
OLD_RECORD_NAME = ".pdsgen-extras.json"
_SECTION_RULE = re.compile(r"^-+$")
_ENTRY_LABELS = {label: key for label, key in ENTRY_FIELDS}
_DIRECTORY_LABELS = {label: key for key, label in DIRECTORY_FIELDS}
_FIELD = re.compile(r"^(?P<indent> {0,2})(?P<label>[A-Za-z][A-Za-z_ ()/-]*):(?: +(?P<value>.*))?$")


@contextmanager
def directory_lock(outdir: Path) -> Iterator[None]:
    """Hold an exclusive flock on OUTDIR while the block runs (blocks until free)."""
    fd = os.open(outdir, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # closing releases the lock


def read_readme(outdir: Path) -> tuple[list[Entry], dict[str, str]]:
    """Product entries and params keywords an existing README.TXT in OUTDIR holds."""
    path = outdir / README_NAME
    if not path.is_file():
        return [], {}
    try:
        text = path.read_bytes().decode("ascii")
    except (OSError, UnicodeDecodeError) as exc:
        raise PdsgenError(path, f"cannot be read as an Extras README ({exc}); move it away "
                                "to start afresh") from None
    return parse_readme(text, path)


def parse_readme(text: str, path: Path | None = None) -> tuple[list[Entry], dict[str, str]]:
    """The inverse of `readme_txt.render_readme` (file lists are not kept: they are
    looked up in the directory)."""
    lines = text.replace("\r\n", "\n").split("\n")
    sections = _sections(lines)
    if "PRODUCTS" not in sections or "PRODUCER AND CONTACT" not in sections:
        raise PdsgenError(path, "is not an Extras README written by pdsgen (no PRODUCTS "
                                "section); move it away to start afresh")
    entries = _entries(sections["PRODUCTS"], path)
    keywords = _fields(sections["PRODUCER AND CONTACT"], 0, _DIRECTORY_LABELS)
    title = lines[:next((i for i, line in enumerate(lines) if line and set(line) == {"="}), 1)]
    keywords["PROJECT_NAME"] = " ".join(" ".join(title).split())  # wrapped when long
    keywords["KNOWN_ARTIFACTS"] = " ".join(" ".join(sections.get("KNOWN ARTIFACTS", [])).split())
    defaults = keyword_defaults(entries)
    return entries, {k: v for k, v in keywords.items() if v and v != defaults.get(k)}


def merge_entries(previous: Sequence[Entry], new: Sequence[Entry]) -> list[Entry]:
    """Earlier entries (replaced in place when given again), then the new ones."""
    fresh = {e["product_id"]: e for e in new}
    merged = [fresh.pop(e["product_id"], e) for e in previous]
    return merged + list(fresh.values())


def publish_readme(outdir: Path, new: Sequence[Entry], keywords: Mapping[str, str]) -> Path:
    """Merge NEW into OUTDIR's README.TXT under the directory lock; return its path."""
    readme = outdir / README_NAME
    with directory_lock(outdir):
        previous, recorded = read_readme(outdir)
        _write_readme(outdir, merge_entries(previous, new), {**recorded, **keywords})
    ours = {entry["product_id"] for entry in new}
    replaced = [entry for entry in previous if entry["product_id"] in ours]
    # Taken back with this call's previews, README.TXT is not restored to the file it
    # replaced: another run may have added its products since. This call's entries give
    # way to those they replaced instead, and the others stay.
    on_rollback(lambda: _take_back(outdir, ours, replaced))
    return readme


def _take_back(outdir: Path, ours: set[str], replaced: Sequence[Entry]) -> None:
    with directory_lock(outdir):
        current, recorded = read_readme(outdir)
        earlier = {entry["product_id"]: entry for entry in replaced}
        entries = [earlier.get(entry["product_id"], entry) for entry in current
                   if entry["product_id"] not in ours or entry["product_id"] in earlier]
        _write_readme(outdir, entries, recorded)


def _write_readme(outdir: Path, candidates: Sequence[Entry], keywords: Mapping[str, str]) -> None:
    """README.TXT of the candidate entries whose files are all present, with the directory
    `keywords` (the caller holds the directory lock and has read the README once); with no
    entry left it is removed, as it would describe nothing."""
    readme = outdir / README_NAME
    entries, files = [], []
    for entry in candidates:
        found = entry_files(entry, outdir)
        if found is not None:
            entries.append(entry)
            files.append(found)
    if not entries:
        readme.unlink(missing_ok=True)
        return
    with StagedOutputs([readme], overwrite=True, restore_on_rollback=False) as staged:
        staged.path(readme).write_bytes(render_readme(entries, files, keywords))
    (outdir / OLD_RECORD_NAME).unlink(missing_ok=True)


def _sections(lines: list[str]) -> dict[str, list[str]]:
    """Upper-case headings underlined with dashes -> the lines under them."""
    sections: dict[str, list[str]] = {}
    current: list[str] | None = None
    for i, line in enumerate(lines):
        if i + 1 < len(lines) and _SECTION_RULE.match(lines[i + 1]) and line.isupper():
            current = sections.setdefault(line.strip(), [])
        elif current is not None and not _SECTION_RULE.match(line):
            current.append(line)
    return sections


def _entries(lines: list[str], path: Path | None) -> list[Entry]:
    """Split the PRODUCTS section at each "Product ID:" and read each block's fields."""
    blocks: list[list[str]] = []
    for line in lines:
        match = _FIELD.match(line)
        if match and match["indent"] == "" and match["label"] == PRODUCT_ID_LABEL:
            blocks.append([])
        if blocks:
            blocks[-1].append(line)
    entries = []
    for block in blocks:
        head = _FIELD.match(block[0])
        assert head is not None
        entry = {key: "" for _, key in ENTRY_FIELDS}
        entry["product_id"] = (head["value"] or "").strip()
        entry.update(_fields(block[1:], 2, _ENTRY_LABELS))
        if not re.fullmatch(r"[A-Za-z0-9_.\-]+", entry["product_id"]):
            raise PdsgenError(path, f"names a product ID {entry['product_id']!r} that is not "
                                    "usable in a file name; move it away to start afresh")
        entries.append(entry)
    return entries


def _fields(lines: list[str], indent: int, labels: Mapping[str, str]) -> dict[str, str]:
    """Known "Label: value" fields at INDENT, with their wrapped continuation lines."""
    values: dict[str, list[str]] = {}
    current: list[str] | None = None
    for line in lines:
        match = _FIELD.match(line)
        if match and len(match["indent"]) == indent and match["label"] in labels:
            current = values.setdefault(labels[match["label"]], [])
            current.append((match["value"] or "").strip())
        elif match and len(match["indent"]) <= indent or line.strip() == f"{FILES_LABEL}:":
            current = None  # another field or the file list: not a continuation
        elif current is not None and line.startswith(" " * (indent + 1)) and line.strip():
            current.append(line.strip())
        else:
            current = None
    return {key: " ".join(parts) for key, parts in values.items()}
