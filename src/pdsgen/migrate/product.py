"""Migrate one PDS3 product: a PDS4 label describing its unchanged files, beside copies of them.

Order: read the label (the validator's reader, `FileContext`) -> describe every object
(objects.py; refusals raise before anything is written) -> checksums of the files as they
are -> copy the files to temporary names in the output directory -> write the PDS4 label
under a temporary name -> rename all into place. A refusal or error leaves nothing of the
product behind.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import InputError, OutputError, PdsgenError
from ..label.read import LabelCache
from ..pds4.content import digest_file
from ..pds4.label import render_pds4
from ..results import CommandResult, written_line
from ..storage.staging import staged_files
from ..validate.context import FileContext
from .geometry import migrated_cartography
from .identity import (
    check_bundle_lid,
    check_product_lid,
    default_bundle_lid,
    identification,
    observation,
    product_id,
    sources,
)
from .objects import DataFile, Refused, describe_objects

COLLECTION = "data"


@dataclass(frozen=True)
class MigratedProduct:
    """What one migration wrote: the PDS4 label and the files it describes (in the output)."""

    product_id: str
    lid: str
    label_path: Path
    files: tuple[Path, ...]  # the files the label describes
    copied: bool = True  # `files` are copies written beside the label (not the originals, in place)
    # PDS3 keywords the bytes overrode (each names the keyword and why), and catalogue facts
    # stated otherwise than the label, or not for sure
    warnings: tuple[str, ...] = ()

    @property
    def summary_line(self) -> str:
        """What was written, in one line, in the form of product results (`results.written_line`)."""
        return written_line(self.written, (self.lid, f"{len(self.files)} file(s) described unchanged"))

    @property
    def written(self) -> tuple[Path, ...]:
        """The files this migration wrote: the PDS4 label, then the copies."""
        return (self.label_path, *self.files) if self.copied else (self.label_path,)


@dataclass
class MigrationRun(CommandResult):
    """Several products migrated in one run: what was written and what was refused
    (`pdsgen migrate`'s result: a refusal is told in one line and the others go on)."""

    migrated: list[MigratedProduct] = field(default_factory=list)
    failed: list[PdsgenError] = field(default_factory=list)
    warnings: tuple[str, ...] = ()  # the products' own (MigratedProduct.warnings): what PDS4 cannot describe is refused

    @property
    def ok(self) -> bool:
        return not self.failed

    @property
    def files(self) -> tuple[Path, ...]:
        return tuple(path for product in self.migrated for path in product.written)

    @property
    def labels(self) -> tuple[Path, ...]:
        """The PDS4 labels written, one per product migrated."""
        return tuple(product.label_path for product in self.migrated)

    @property
    def refused(self) -> tuple[str, ...]:
        """One line per obstacle: a product refused for three reasons gives three lines."""
        return tuple(line for failure in self.failed for line in str(failure).splitlines())

    @property
    def summary_lines(self) -> tuple[str, ...]:
        return (*(product.summary_line for product in self.migrated),
                f"{len(self.migrated)} product(s) migrated, {len(self.failed)} refused")

    def details(self) -> dict[str, Any]:
        return {"migrated": [{"product_id": p.product_id, "lid": p.lid, "label": str(p.label_path),
                              "files": [str(f) for f in p.files]} for p in self.migrated],
                "refused": list(self.refused)}


def migrate_product(label_path: str | os.PathLike[str], outdir: str | os.PathLike[str] | None = None, *,
                    bundle_lid: str | None = None, collection: str = COLLECTION, lid: str | None = None,
                    in_place: bool = False, overwrite: bool = False, copy: bool = True,
                    labels: LabelCache | None = None, root: str | os.PathLike[str] | None = None
                    ) -> MigratedProduct:
    """Write the PDS4 label of the PDS3 product whose label is `label_path` (attached or detached).

    The product's files are copied unchanged into `outdir` and the label written beside them
    (`<label stem>.xml`); with `in_place` the label is written beside the originals and nothing
    is copied; without `copy`, only the label is written to `outdir` (a delivery places the
    files itself). `lid` gives the product's whole LID; otherwise it is `<bundle_lid>:<collection>:
    <PRODUCT_ID>` (bundle LID from DATA_SET_ID when not given). Refused (InputError) with one line
    naming the construct when PDS4 cannot describe the files exactly; nothing is written then.
    `root` widens the tree the files the label names must stay inside (the label's directory
    by default): a volume's label naming ../../LABEL/X.FMT is migrated with root = the volume.
    """
    source = Path(label_path)
    if not source.is_file():
        raise InputError(source, "is not a regular file (a pipe, a device or a directory)"
                         if source.exists() else "no such file")
    if not in_place and outdir is None:
        raise OutputError(None, "give an output directory, or migrate in place")
    ctx = _read(source, labels, Path(root) if root is not None else None)
    files, image_id = describe_objects(ctx)
    pid, keyword = product_id(ctx.root, source.stem)
    ident = identification(ctx.root, check_bundle_lid(bundle_lid or default_bundle_lid(ctx.root)), collection,
                           pid, keyword)
    if lid is not None:
        ident["lid"] = check_product_lid(lid)
    obs = observation(ctx.root, source.name)
    warnings = [f"{source}: {w}" for w in obs.pop("warnings", ())]  # type: ignore[attr-defined]
    if keyword is None and lid is None:
        warnings.append(_named_by_file(source, str(ident["lid"])))
    cart = None
    if image_id is not None:
        image = next(o for f in files for o in f.objects if o.get("local_identifier") == image_id)
        cart = migrated_cartography(ctx, int(image["lines"]), int(image["samples"]),  # type: ignore[call-overload]
                                    str(obs["target_name"]), warnings)
        obs["display"] = image["kind"] == "array"  # disp: refers to arrays only, not an Encoded_Image
    target_dir = source.parent if in_place else Path(outdir)  # type: ignore[arg-type]
    label_out = target_dir / f"{source.stem}.xml"
    if label_out.exists() and not overwrite:
        raise OutputError(label_out, "exists (give overwrite to replace it)")
    text = render_pds4("migrated.xml.j2", {
        "ident": ident, "obs": obs, "cart": cart, "array_id": image_id, "sources": sources(ctx.root, source.name),
        "files": [_file_context(data) for data in files],
    }, source=source)
    written = _write(files, text, label_out, target_dir, copy and not in_place, overwrite)
    warnings += [f"{source}: {warning}" for warning in _warnings(files)]
    return MigratedProduct(pid, str(ident["lid"]), label_out, written, copied=copy and not in_place,
                           warnings=tuple(warnings))


def _named_by_file(source: Path, lid: str) -> str:
    """What migrate says when a label states neither PRODUCT_ID nor IMAGE_ID: the product's LID is
    then made from the file's name, an identifier the data's producer never gave (issue 49:
    never invent one without saying so)."""
    return f"{source}: states no PRODUCT_ID or IMAGE_ID: its LID {lid} is made from the file's name"


def migrate_products(labels: Iterable[str | os.PathLike[str]], outdir: str | os.PathLike[str] | None = None,
                     **options: object) -> MigrationRun:
    """Each product migrated on its own: a refused one is recorded and the others go on."""
    run = MigrationRun()
    for label in labels:
        try:
            run.migrated.append(migrate_product(label, outdir, **options))  # type: ignore[arg-type]
        except PdsgenError as exc:
            run.failed.append(exc)
    run.warnings = tuple(warning for product in run.migrated for warning in product.warnings)
    return run


def product_labels(paths: Iterable[str | os.PathLike[str]]) -> Iterator[Path]:
    """The PDS3 labels among `paths`: a label (.LBL) or attached-label product as given; a data
    file whose detached label (same stem, .LBL/.lbl) lies beside it, that label."""
    for given in paths:
        path = Path(given)
        if path.suffix.lower() != ".lbl":
            path = next((label for label in (path.with_suffix(".LBL"), path.with_suffix(".lbl"))
                         if label.is_file()), path)
        yield path


def _read(source: Path, labels: LabelCache | None = None, root: Path | None = None) -> FileContext:
    """The label as the validator reads it; `labels`: the run's cache (a delivery's); `root`:
    the user's wider trusted tree (label/beside.trusted_tree)."""
    from ..label.beside import trusted_tree

    try:
        ctx = FileContext(source, file=labels.open(source) if labels is not None else None,
                          tree=trusted_tree(source, None, root))
    except OSError as exc:
        raise InputError(source, f"cannot be read ({exc.strerror})") from None
    if not ctx.label.end_found:
        raise Refused(source, "is not a PDS3 label (no END statement)")
    return ctx


def _warnings(files: list[DataFile]) -> Iterator[str]:
    """What the description left out or overrode: each file's notes, then each object's."""
    for data in files:
        yield from data.warnings
        for obj in data.objects:
            yield from obj.get("warnings") or ()  # type: ignore[misc]


def _file_context(data: DataFile) -> dict[str, object]:
    content = digest_file(data.path)
    return {"file": {"name": data.name, "local_identifier": f"file_{Path(data.name).stem.lower()}"
                     + ("_label" if data.supplemental else ""),
                     "size": content.size, "md5": content.md5},
            "objects": data.objects, "supplemental": data.supplemental}


def _write(files: list[DataFile], text: str, label_out: Path, target_dir: Path, copy: bool,
           overwrite: bool) -> tuple[Path, ...]:
    """Copies (temporary names, then renamed) and the label; on any failure nothing remains."""
    target_dir.mkdir(parents=True, exist_ok=True)
    with staged_files() as stage:
        if copy:
            for data in files:
                final = target_dir / data.name
                if final.resolve() == data.path.resolve():
                    continue
                if final.exists() and not overwrite:
                    raise OutputError(final, "exists (give overwrite to replace it)")
                shutil.copyfile(data.path, stage(final, final.with_name(f".{final.name}.migrating")))
        stage(label_out, label_out.with_name(f".{label_out.name}.migrating")).write_text(text, encoding="utf-8")
    return tuple((target_dir / data.name) if copy else data.path for data in files)
