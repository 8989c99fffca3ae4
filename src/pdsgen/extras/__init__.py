"""Extras: the preview JPEGs and README.TXT that archive users look at first.

`make_extras` takes products this tool wrote, archived PDS3 products it did not
write, or GeoTIFFs, and writes for each its browse, annotated browse and thumbnail
JPEGs (three renderings for a DTM, one for an orthoimage), then one README.TXT that
describes every product whose Extras are in the directory, those of earlier calls
included (see `readme_index`). Every product is inspected before anything is written, so a bad
input stops the run with nothing written; each product's files then appear all
together or not at all.
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Mapping, Sequence
from pathlib import Path

from PIL import Image

from ..errors import PdsgenError
from ..formats.staging import StagedOutputs, prepare_output_dir
from ..missions import hirise as hirise_mission
from ..missions import mission_names
from ..missions.base import get_mission
from ..products.params import ParamValue, resolve_params
from .product_source import KINDS, ProductSource, open_product
from .readme_index import INDEX_NAME, index_bytes, load_index, merge_entries
from .readme_txt import README_NAME, directory_keywords, product_entry, render_readme
from .renderings import THUMB_WIDTH, ProductPreviews, render_product

DEFAULT_CREDIT = hirise_mission.CREDIT
JPEG_QUALITY = 90

__all__ = ["make_extras", "extras_file_names", "DEFAULT_CREDIT", "KINDS"]


def make_extras(
    products: Sequence[str | os.PathLike[str]],
    outdir: str | os.PathLike[str],
    *,
    credit: str | None = None,
    params: str | os.PathLike[str] | Mapping[str, ParamValue] | None = None,
    browse_width: int | None = None,
    thumb_width: int = THUMB_WIDTH,
    azimuth: float = 315.0,
    altitude: float = 45.0,
    exaggeration: float | None = None,
    kind: str | None = None,
    profile: str | None = None,
    overwrite: bool = False,
) -> list[Path]:
    """Write the Extras of PRODUCTS into OUTDIR; return the paths written.

    `browse_width` defaults to 1024 px for DTMs and 2048 px for orthoimages (never
    wider than the data); `kind` ("dtm" or "ortho") overrides detection for all
    products. `exaggeration` is the shaded relief's vertical exaggeration (default:
    1, raised automatically when the relief would be too faint to see at preview
    scale, and then printed on the images). The credit line is `credit`, else the params' CREDIT, else
    the credit of `profile`, else that of the mission the product's label names (HRSC:
    "ESA/DLR/FU Berlin"), else "NASA/JPL/University of Arizona".
    """
    if not products:
        raise PdsgenError(None, "no products given")
    azimuth = _check_options(browse_width, thumb_width, azimuth, altitude, exaggeration)
    keywords = resolve_params(params)
    sources = [open_product(p, kind) for p in products]
    credits = [_credit(credit, keywords, profile or src.mission) for src in sources]
    _check_unique_ids(sources)
    previous, recorded_keywords = load_index(Path(outdir))
    outdir = prepare_output_dir(outdir)
    written: list[Path] = []
    entries = []
    for src, credit_line in zip(sources, credits, strict=True):
        previews = render_product(src, credit=credit_line, browse_width=browse_width,
                                  thumb_width=thumb_width, azimuth=azimuth, altitude=altitude,
                                  exaggeration=exaggeration)
        written += _write_previews(previews, outdir, overwrite)
        entries.append(product_entry(previews, credit_line, azimuth, altitude))
    return [*written, *_write_readme(outdir, merge_entries(previous, entries, outdir),
                                     {**recorded_keywords, **directory_keywords(keywords)})]


def _write_readme(outdir: Path, entries: list[dict], keywords: dict[str, str]) -> list[Path]:
    """README.TXT for every product in OUTDIR, and the record it is made from.

    Both describe the directory, not one call, so they are replaced without
    --overwrite (the record keeps what earlier calls put in).
    """
    readme, index = outdir / README_NAME, outdir / INDEX_NAME
    with StagedOutputs([readme, index], overwrite=True) as staged:
        staged.path(readme).write_bytes(render_readme(entries, keywords))
        staged.path(index).write_bytes(index_bytes(entries, keywords))
    return [readme, index]


def extras_file_names(previews: ProductPreviews) -> list[tuple[str, str]]:
    """(file name, what it is) for every preview file of one product."""
    pid = previews.source.product_id
    names = []
    for p in previews.previews:
        r = p.rendering
        names += [(f"{pid}.{r.browse}.jpg", f"{r.description}, browse"),
                  (f"{pid}.{r.annotated}.jpg", f"{r.description}, annotated browse"),
                  (f"{pid}.{r.thumb}.jpg", f"{r.description}, thumbnail")]
    return names


def _write_previews(previews: ProductPreviews, outdir: Path, overwrite: bool) -> list[Path]:
    pid = previews.source.product_id
    jobs: list[tuple[Path, Image.Image, bool]] = []
    for p in previews.previews:
        r = p.rendering
        jobs += [(outdir / f"{pid}.{r.browse}.jpg", p.browse, False),
                 (outdir / f"{pid}.{r.annotated}.jpg", p.annotated, True),
                 (outdir / f"{pid}.{r.thumb}.jpg", p.thumb, False)]
    with StagedOutputs([path for path, _, _ in jobs], overwrite) as staged:
        for path, image, annotated in jobs:
            options = {"quality": JPEG_QUALITY}
            if annotated or image.mode == "RGB":
                options["subsampling"] = 0 if annotated else 2
            image.save(staged.path(path), format="JPEG", **options)
    return [path for path, _, _ in jobs]


def _credit(credit: str | None, keywords: Mapping[str, ParamValue], profile: str) -> str:
    profile_credit = get_mission(profile).credit if profile in mission_names() else ""
    text = credit if credit is not None else str(keywords.get("CREDIT", profile_credit or DEFAULT_CREDIT))
    if not text.isascii():
        raise PdsgenError(None, f"credit line {text!r} must be ASCII text")
    return " ".join(text.split())


def _check_options(browse_width: int | None, thumb_width: int, azimuth: float, altitude: float,
                   exaggeration: float | None) -> float:
    """Refuse unusable numbers (nan, inf, out of range); return azimuth in [0, 360).

    nan slips through plain range comparisons in some spellings and inf breaks the
    trigonometry, so each value is checked to be a finite number first.
    """
    if browse_width is not None:
        _check_int("browse width", browse_width, 16, 65500)
    _check_int("thumbnail width", thumb_width, 8, 4096)
    if not _is_finite_number(azimuth):
        raise PdsgenError(None, f"light azimuth {azimuth!r} must be a finite number of degrees")
    if exaggeration is not None and not (_is_finite_number(exaggeration)
                                         and 0.0 < exaggeration <= 1e4):
        raise PdsgenError(None, f"vertical exaggeration {exaggeration!r} must be in (0, 10000]")
    if not (_is_finite_number(altitude) and 0.0 < altitude <= 90.0):
        raise PdsgenError(None, f"light altitude {altitude!r} must be in (0, 90] degrees")
    return float(azimuth) % 360.0 + 0.0  # + 0.0 turns -0.0 into 0.0


def _check_int(what: str, value: object, low: int, high: int) -> None:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not (
            low <= int(value) <= high):
        raise PdsgenError(None, f"{what} {value!r} must be a whole number of pixels, "
                                f"{low} .. {high}")


def _is_finite_number(value: object) -> bool:
    return (isinstance(value, numbers.Real) and not isinstance(value, bool)
            and math.isfinite(value))


def _check_unique_ids(sources: list[ProductSource]) -> None:
    seen: dict[str, Path] = {}
    for src in sources:
        if src.product_id in seen:
            raise PdsgenError(src.path, f"has the same product ID {src.product_id} as "
                                        f"{seen[src.product_id]}; their Extras would collide")
        seen[src.product_id] = src.path
