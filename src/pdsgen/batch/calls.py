"""The one library call a batch job makes, per kind: the same call its CLI command makes.

A job's parameters are those its click command parsed (see manifest.py), under the
click parameter names; each function here passes them to the library function
behind the command - through the vocabulary's `library_options` (products/options.py,
mosaic/options.py), the one the command calls too, so the keywords are chosen in one
place - and returns what the job wrote:
`outputs` (the files it made), `shared` (directory-wide files it updated) and
`products` (the files a later job reads: a DTM's .IMG, an orthoimage's .LBL).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ..results import CommandResult
from ..storage import OutputArea, local_inputs, output_area

Outputs = dict[str, list[str]]
# Files `pdsgen extras` and `pdsgen validate` take for a product: its PDS3 label.
LABEL_SUFFIXES = (".img", ".lbl")


def run_dtm(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    from ..products.dtm import write_dtm
    from ..products.options import DTM_OPTIONS, library_options

    options = {**library_options("dtm", DTM_OPTIONS, p), "overwrite": overwrite}
    with output_area(p["outdir"], overwrite) as area:  # the worker writes into the bucket itself (s3:// OUTDIR)
        return _product(write_dtm(p["input_path"], area.directory, profile=p["profile"], **options), area)


def run_ortho(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    from ..products.options import ORTHO_OPTIONS, library_options, ortho_inputs, ortho_shared_files
    from ..products.ortho import write_ortho

    options = {**library_options("ortho", ORTHO_OPTIONS, p), "overwrite": overwrite, "threads": threads}
    with output_area(p["outdir"], overwrite, shared=ortho_shared_files()) as area:
        return _product(write_ortho(ortho_inputs(p), area.directory, profile=p["profile"], **options), area)


def run_mosaic(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    from ..mosaic import write_mosaic
    from ..mosaic.options import library_options

    options = {**library_options(p), "overwrite": overwrite}
    with local_inputs(p["inputs"]) as inputs, output_area(p["outdir"], overwrite) as area:  # as `pdsgen mosaic`
        return _product(write_mosaic(inputs.paths, area.directory, **options), area)


def _product(product: CommandResult, area: OutputArea) -> Outputs:
    """Every file of a product; the one later jobs read is its label (or, for iMars, its GeoTIFF)."""
    labels = [f for f in product.files if f.suffix.lower() in LABEL_SUFFIXES]
    return _reported(product, labels[:1] or list(product.files[:1]), area=area)


def run_extras(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    from ..extras import make_extras
    from ..extras.options import library_options
    from ..extras.readme_txt import README_NAME
    from ..extras.result import ExtrasResult

    with local_inputs(p["products"]) as inputs, output_area(p["outdir"], overwrite, shared=(README_NAME,)) as area:
        written = make_extras(inputs.paths, area.directory, **{**library_options(p), "overwrite": overwrite},
                              report=lambda line: print(inputs.shown(line)))  # notes into the log
        extras = ExtrasResult.of(written)
        return _reported(extras, [], shared=extras.directory_files, area=area)


def run_migrate(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    """`pdsgen migrate`: each product's PDS4 label beside unchanged copies of its files; a refused
    product fails the job (one line each) after the others are written. One directory given is a
    PDS3 volume, migrated to a bundle as the command does (its bundle label is the job's product)."""
    from ..migrate import migrate_products, product_labels

    if len(p["products"]) == 1 and Path(p["products"][0]).is_dir():
        from ..migrate.volume import migrate_volume

        volume = migrate_volume(p["products"][0], p["outdir"], bundle_lid=p["bundle_lid"], in_place=p["in_place"],
                                overwrite=overwrite)
        return _reported(volume, list(volume.files[:1]))
    run = migrate_products(product_labels(p["products"]), p["outdir"], bundle_lid=p["bundle_lid"],
                           collection=p["collection"], in_place=p["in_place"], overwrite=overwrite)
    return _reported(run, list(run.labels))


class ProblemsFound(Exception):
    """A validation that ran and found errors: the job failed, with the report's summary as reason."""


def run_validate(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    """Validate; the report goes to `output` (written whole, then renamed or PUT) when given."""
    from ..storage import files
    from ..validate import render, validate_paths

    with local_inputs(p["paths"]) as inputs:
        report = validate_paths(inputs.paths, strict=p["strict"], jobs=p["jobs"], labels_only=p["labels_only"],
                                dictionaries=p["dictionaries"])
        text = inputs.shown(render(report, p["fmt"]))
    written: list[str] = []
    if p["output"]:
        files.write_text_whole(p["output"], text)
        written.append(str(p["output"]))
    else:
        print(text, end="")  # into the job's log
    if report.exit_code != 0:
        raise ProblemsFound(report.summary_line())
    return {"outputs": written, "products": [], "shared": []}


def _reported(result: CommandResult, products: list[Path], shared: Sequence[Path] = (),
              area: OutputArea | None = None) -> Outputs:
    """What any job's result says, read through the result contract only: its warnings go to the
    job's log (as the command prints them), what it refused fails the job (one line each, after the
    others were written), and its files are the job's outputs - `shared` ones apart."""
    for warning in result.warnings:
        print(f"warning: {warning}")
    if result.refused:
        from ..errors import PdsgenError

        raise PdsgenError(None, "; ".join(result.refused))
    return _written([f for f in result.files if f not in shared], products, shared, area)


def _written(outputs: list[Path], products: list[Path], shared: Sequence[Path] = (),
             area: OutputArea | None = None) -> Outputs:
    """`shared`: files the job updated that describe its whole directory (README.TXT);
    a later job in that directory rewrites them, so they are reported, not checked on resume.
    Files written in an s3:// OUTDIR's staging area are reported where they were uploaded."""
    named = area.remote if area is not None else str
    return {"outputs": [named(o) for o in outputs], "products": [named(p) for p in products],
            "shared": [named(s) for s in shared]}


# Each takes the job's parameters, whether it may replace its earlier outputs, and its
# thread budget (GDAL's comes from the child's environment; the JPEG 2000 encoder's is
# passed to write_ortho).
RUNNERS: dict[str, Callable[[Mapping[str, Any], bool, int], Outputs]] = {
    "dtm": run_dtm, "ortho": run_ortho, "mosaic": run_mosaic, "extras": run_extras, "validate": run_validate,
    "migrate": run_migrate,
}
