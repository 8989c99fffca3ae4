"""The one library call a batch job makes, per kind: the same call its CLI command makes.

A job's parameters are those its click command parsed (see manifest.py), under the
click parameter names; each function here passes them to the library function
behind the command - through the command's own `library_options` where it has
one, so the keywords are chosen in one place - and returns what the job wrote:
`outputs` (the files it made), `shared` (directory-wide files it updated) and
`products` (the files a later job reads: a DTM's .IMG, an orthoimage's .LBL).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ..products.result import ProductResult

Outputs = dict[str, list[str]]
# Files `pdsgen extras` and `pdsgen validate` take for a product: its PDS3 label.
LABEL_SUFFIXES = (".img", ".lbl")


def run_dtm(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    from ..cli.dtm import library_options
    from ..products.dtm import write_dtm

    options = {**library_options(p), "overwrite": overwrite}
    return _product(write_dtm(p["input_path"], p["outdir"], profile=p["profile"], **options))


def run_ortho(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    from ..cli.ortho import library_options, ortho_inputs
    from ..products.ortho import write_ortho

    options = {**library_options(p), "overwrite": overwrite, "threads": threads}
    return _product(write_ortho(ortho_inputs(p), p["outdir"], profile=p["profile"], **options))


def run_mosaic(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    from ..cli.mosaic import library_options
    from ..mosaic import write_mosaic

    options = {**library_options(p), "overwrite": overwrite}
    return _product(write_mosaic(list(p["inputs"]), p["outdir"], **options))


def _product(product: ProductResult) -> Outputs:
    """Every file of a product; the one later jobs read is its label (or, for iMars, its GeoTIFF).
    The product's warnings go to the job's log, as the command prints them."""
    for warning in getattr(product, "warnings", ()):
        print(f"warning: {warning}")
    labels = [f for f in product.files if f.suffix.lower() in LABEL_SUFFIXES]
    return _written(list(product.files), labels[:1] or list(product.files[:1]))


def run_extras(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    from ..extras import make_extras
    from ..extras.readme_txt import README_NAME

    written = make_extras(p["products"], p["outdir"], credit=p["credit"], params=p["params_file"],
                          browse_width=p["browse_width"], thumb_width=p["thumb_width"], azimuth=p["azimuth"],
                          altitude=p["altitude"], exaggeration=p["exaggeration"], kind=p["kind"],
                          profile=p["profile"], product_id=p["product_id"], overwrite=overwrite,
                          report=print)  # notes into the log
    directory_files = [w for w in written if w.name == README_NAME]
    return _written([w for w in written if w not in directory_files], [], shared=directory_files)


def run_migrate(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    """`pdsgen migrate`: each product's PDS4 label beside unchanged copies of its files; a refused
    product fails the job (one line each) after the others are written."""
    from ..errors import PdsgenError
    from ..migrate import migrate_products, product_labels

    run = migrate_products(product_labels(p["products"]), p["outdir"], bundle_lid=p["bundle_lid"],
                           collection=p["collection"], in_place=p["in_place"], overwrite=overwrite)
    if run.failed:
        raise PdsgenError(None, "; ".join(str(f) for f in run.failed))
    return _written([f for m in run.migrated for f in (m.label_path, *m.files) if not p["in_place"] or
                     f == m.label_path], [m.label_path for m in run.migrated])


class ProblemsFound(Exception):
    """A validation that ran and found errors: the job failed, with the report's summary as reason."""


def run_validate(p: Mapping[str, Any], overwrite: bool, threads: int) -> Outputs:
    """Validate; the report goes to `output` (written whole, then renamed) when given."""
    from ..formats.staging import StagedOutputs
    from ..validate import render, validate_paths

    report = validate_paths(p["paths"], strict=p["strict"], jobs=p["jobs"], labels_only=p["labels_only"],
                            dictionaries=p["dictionaries"])
    written: list[Path] = []
    if p["output"]:
        output = Path(p["output"])
        output.parent.mkdir(parents=True, exist_ok=True)
        with StagedOutputs([output], overwrite=True) as staged:
            staged.path(output).write_text(render(report, p["fmt"]), encoding="utf-8")
        written.append(output)
    else:
        print(render(report, p["fmt"]), end="")  # into the job's log
    if report.exit_code != 0:
        raise ProblemsFound(report.summary_line())
    return _written(written, [])


def _written(outputs: list[Path], products: list[Path], shared: Sequence[Path] = ()) -> Outputs:
    """`shared`: files the job updated that describe its whole directory (README.TXT);
    a later job in that directory rewrites them, so they are reported, not checked on resume."""
    return {"outputs": [str(o) for o in outputs], "products": [str(p) for p in products],
            "shared": [str(s) for s in shared]}


# Each takes the job's parameters, whether it may replace its earlier outputs, and its
# thread budget (GDAL's comes from the child's environment; the JPEG 2000 encoder's is
# passed to write_ortho).
RUNNERS: dict[str, Callable[[Mapping[str, Any], bool, int], Outputs]] = {
    "dtm": run_dtm, "ortho": run_ortho, "mosaic": run_mosaic, "extras": run_extras, "validate": run_validate,
    "migrate": run_migrate,
}
