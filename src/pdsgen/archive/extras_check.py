"""Whether a directory's Extras still describe its products: README.TXT against the labels.

The Extras' README.TXT records, for each product, what the Extras were made from (its PDS3
label's MD5, "Label MD5"), its size and its valid range. A product remade after its Extras
(`pdsgen dtm --overwrite`, then delivered again) leaves them stale: README.TXT then says 300
lines while the label says 280, and the previews show the old extent. Staleness is a fact
here, not a guess: the MD5 recorded is compared with the label's. One home for the check:
the validator's delivery rules report it (DLV-017, DLV-018, DLV-019) and `pdsgen deliver`
refuses stale Extras before it writes anything.

README.TXT is read with this module's own reader (the Extras writer's field names are the
only thing shared: they are the file's format).
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from ..bounded import text_lines
from ..errors import InputError, param
from ..formats.checksum import label_md5
from ..formats.jpeg_size import jpeg_size
from ..formats.preview_size import browse_size, thumbnail_size
from ..label.read import LabelCache, read_pds3_label
from ..storage.containment import contained, name_problem
from . import layout

README = "README.TXT"
_SIZE = re.compile(r"(\d+) samples x (\d+) lines")
_FIELD = re.compile(r"^  ([A-Za-z][A-Za-z0-9_ ()/.-]*):\s*(.*)$")
_PREVIEW = re.compile(r"\b(browse|thumbnail) \((\d+) x (\d+) pixels\)")
_CONTINUATION = 19  # README.TXT's value column: a longer indent continues the field above


@dataclass
class ReadmeEntry:
    """One product as README.TXT documents it."""

    product_id: str
    line: int
    fields: dict[str, str] = field(default_factory=dict)
    files: list[tuple[str, int]] = field(default_factory=list)  # (Extras file name, line)
    descriptions: dict[str, str] = field(default_factory=dict)  # Extras file name -> its description

    def preview_size(self, name: str) -> tuple[str, int, int] | None:
        """("browse" or "thumbnail", width, height) of a file the entry lists, as its description
        states it (an annotated browse, a quick look or a file not described: None)."""
        match = _PREVIEW.search(self.descriptions.get(name, ""))
        if match is None or "annotated" in self.descriptions[name]:
            return None
        return match.group(1), int(match.group(2)), int(match.group(3))


@dataclass(frozen=True)
class ExtrasProblem:
    """One disagreement between the Extras and the products. kind: "stale" (the label changed
    since the Extras were made), "differs" (a size or valid range README.TXT states is not the
    label's), "preview" (a browse or thumbnail not the size the Extras make of the product),
    "absent" (README.TXT documents a product or preview not in the directory)."""

    kind: str
    file: Path
    message: str
    line: int | None = None


def read_entries(readme: Path) -> list[ReadmeEntry]:
    """The product entries of an Extras README.TXT (its PRODUCTS section)."""
    try:
        lines = text_lines(readme, "README.TXT")
    except InputError:
        return []
    entries: list[ReadmeEntry] = []
    key = ""
    in_files = False
    for number, line in enumerate(lines, 1):
        if line.startswith("Product ID:"):
            entries.append(ReadmeEntry(line.split(":", 1)[1].strip(), number))
            key, in_files = "", False
        elif not entries or not line.strip():
            continue
        elif not line.startswith(" "):  # the next section's heading: the products are over
            if entries and line.strip() and not line.startswith("Product ID"):
                break
        elif line.startswith("  Extras files:"):
            in_files = True
        elif in_files and line.startswith("    ") and not line.startswith("     "):
            entries[-1].files.append((line.strip(), number))
        elif in_files and entries[-1].files:  # the description of the file above, over lines
            name = entries[-1].files[-1][0]
            entries[-1].descriptions[name] = f"{entries[-1].descriptions.get(name, '')} {line.strip()}".strip()
        elif (match := _FIELD.match(line)) is not None and not in_files:
            key = match.group(1)
            entries[-1].fields[key] = match.group(2).strip()
        elif key and not in_files and line.startswith(" " * _CONTINUATION):
            entries[-1].fields[key] += " " + line.strip()
    return entries


def readmes(root: Path) -> Iterator[Path]:
    """The Extras README.TXT files under `root` (a delivery's EXTRAS/, a product directory's extras/)."""
    for path in sorted(root.rglob(README)):  # the name the Extras write
        if path.is_file():
            yield path


@dataclass(frozen=True)
class DocumentedLabel:
    """What README.TXT is compared with, of the delivered label of its product: the label's MD5
    (formats/checksum.label_md5), its IMAGE object's size (samples, lines) and valid range."""

    md5: str | None
    size: tuple[int, int] | None
    valid: dict[str, float]


def extras_problems(root: Path, labels: LabelCache | None = None) -> list[ExtrasProblem]:
    """Every disagreement between the Extras under `root` and the products they document.
    `labels`: the run's label cache (deliver reads each label once for all its steps)."""
    problems: list[ExtrasProblem] = []
    for readme in readmes(root):
        for entry in read_entries(readme):
            product = product_of(root, readme, entry)
            problems.extend(entry_problems(readme, entry, product, _label_facts(product, labels) if product else None))
    return problems


def _label_facts(product: Path, labels: LabelCache | None) -> DocumentedLabel | None:
    label = read_pds3_label(product, labels)
    if label is None:
        return None
    image = label.image()
    if image is None:
        return DocumentedLabel(label_md5(product), None, {})
    samples, lines = image.number("LINE_SAMPLES"), image.number("LINES")
    valid = {k: float(v) for k in ("VALID_MINIMUM", "VALID_MAXIMUM")
             if isinstance(v := image.number(k), (int, float))}
    size = (samples, lines) if isinstance(samples, int) and isinstance(lines, int) else None
    return DocumentedLabel(label_md5(product), size, valid)


def product_of(root: Path, readme: Path, entry: ReadmeEntry) -> Path | None:
    """The delivered label of the product a README.TXT entry documents (None when it is not there)."""
    return _product_file(root, readme, entry.fields.get("Product file", ""))


def _product_file(root: Path, readme: Path, name: str) -> Path | None:
    """Where the product README.TXT names lies: beside it, one directory up (a product
    directory's extras/), or in the delivery's DATA/."""
    for directory in (readme.parent, readme.parent.parent, root / layout.DATA_DIR, root):
        candidate = named_in(directory, name)
        if candidate is not None and candidate.is_file():
            return candidate
    return None


def named_in(directory: Path, name: str) -> Path | None:
    """DIRECTORY / NAME for a file name README.TXT gives (a product, a preview), by the one
    containment rule: None for a name that is no plain relative name (../x, /etc/passwd, a NUL)
    or whose links lead out of DIRECTORY - such a name is never looked up or read."""
    if not name or name_problem(name) is not None:
        return None
    path = directory.joinpath(*name.split("/"))
    return path if contained(path, directory) is not None else None


def entry_problems(readme: Path, entry: ReadmeEntry, product: Path | None,
                   label: DocumentedLabel | None) -> Iterator[ExtrasProblem]:
    """One README.TXT entry against its delivered product (`product`, None when it is not
    there) and what its label states (`label`, None when it is no PDS3 label)."""
    name = entry.fields.get("Product file", "")
    if product is None:
        yield ExtrasProblem("absent", readme, f"documents product {entry.product_id} ({name or 'no file named'}), "
                                              "which is not delivered: make the Extras again from the products "
                                              "delivered", entry.line)
        return
    for file_name, line in entry.files:
        if (path := named_in(readme.parent, file_name)) is None or not path.is_file():
            yield ExtrasProblem("absent", readme, f"documents preview {file_name} of {entry.product_id}, which is "
                                                  "not delivered", line)
    recorded = entry.fields.get("Label MD5", "")
    current = label.md5 if label is not None else None
    remedy = (f"the Extras were made from another version of {product.name}: make them again from it into "
              f"{readme.parent.name}/ ({param('overwrite', True)}) and deliver again")
    if recorded and current and recorded != current:
        yield ExtrasProblem("stale", readme, f"Label MD5 {recorded} of {entry.product_id} is not that of its "
                                             f"label now ({current}): {remedy}", entry.line)
    if label is not None:
        yield from _numbers_problems(readme, entry, label, remedy)
        yield from _preview_problems(readme, entry, product, label)


def _preview_problems(readme: Path, entry: ReadmeEntry, product: Path,
                      label: DocumentedLabel) -> Iterator[ExtrasProblem]:
    """Each browse and thumbnail JPEG the entry lists is the size the Extras make of the product
    (formats/preview_size, the Extras' own arithmetic) at the width the file has: one of a
    product since remade at another size is not (kind "preview"). An annotated browse (margins
    around the browse) is left to its browse; a thumbnail is made of the browse."""
    if label.size is None:
        return
    previews = [(path, kind, jpeg_size(path)) for path, kind in _previews(readme, entry)]
    browse = next((browse_size(*label.size, size[0]) for _, kind, size in previews
                   if kind == "browse" and size is not None), None)
    for path, kind, size in previews:
        if size is None:
            continue
        if kind == "browse":
            made = browse_size(*label.size, size[0])
        elif browse is not None:
            made = thumbnail_size(*browse, size[0])
        else:
            continue
        if size != made:
            yield ExtrasProblem("preview", path, f"{size[0]} x {size[1]} pixels, but the {kind} the Extras make "
                                                 f"{size[0]} pixels wide of {product.name} ({label.size[0]} samples "
                                                 f"x {label.size[1]} lines) is {made[0]} x {made[1]}: a {kind} of "
                                                 f"another version of the product: make the Extras again from it "
                                                 f"into {readme.parent.name}/ ({param('overwrite', True)})")


def _previews(readme: Path, entry: ReadmeEntry) -> list[tuple[Path, str]]:
    """The browse and thumbnail files an entry lists and the directory holds (by the kind their
    description states)."""
    listed = []
    for name, _ in entry.files:
        stated = entry.preview_size(name)
        path = named_in(readme.parent, name)
        if stated is not None and path is not None and path.is_file():
            listed.append((path, stated[0]))
    return listed


def _numbers_problems(readme: Path, entry: ReadmeEntry, label: DocumentedLabel, remedy: str) -> Iterator[ExtrasProblem]:
    """README.TXT's size and valid range against the label's image object."""
    size = _SIZE.search(entry.fields.get("Size", ""))
    if size is not None and label.size is not None and (int(size.group(1)), int(size.group(2))) != label.size:
        samples, lines = label.size
        yield ExtrasProblem("differs", readme, f"{entry.product_id}: Size {size.group(0)}, but its label has "
                                               f"{samples} samples x {lines} lines: {remedy}", entry.line)
    for keyword in ("VALID_MINIMUM", "VALID_MAXIMUM"):
        stated = entry.fields.get(keyword, "")
        value = label.valid.get(keyword)
        if stated and value is not None and not _agrees(stated, value):
            yield ExtrasProblem("differs", readme, f"{entry.product_id}: {keyword} {stated}, but its label has "
                                                   f"{value:g}: {remedy}", entry.line)


def _agrees(stated: str, value: float) -> bool:
    """Whether README.TXT's rounded number is the label's value (to the decimals written)."""
    try:
        number = float(stated)
    except ValueError:
        return True  # not a number (a note): nothing to compare
    decimals = len(stated.split(".", 1)[1]) if "." in stated else 0
    return abs(number - value) <= 0.5 * 10.0 ** -decimals + 1e-9 * max(1.0, abs(value))
