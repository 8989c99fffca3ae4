"""Extras: the preview JPEGs and README.TXT that archive users look at first.

`make_extras` takes products this tool wrote, archived PDS3 products it did not
write, or GeoTIFFs, and writes for each its browse, annotated browse and thumbnail
JPEGs (three renderings for a DTM, one for an orthoimage, plus a full-scale
quick-look JPEG 2000 for an orthoimage), then one README.TXT that describes every
product whose Extras are in the directory, those of earlier and concurrent calls
included (see `readme_index`). Every product is inspected before anything is
written, so a bad input stops the run with nothing written; each product's files
then appear all together or not at all.
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

from PIL import Image

from ..errors import ParamsError, PdsgenError, param
from ..formats.kind import NOMAP
from ..geo.conventions import wrap_360
from ..params import ParamValue, resolve_params
from ..progress import advance, is_large
from ..storage.staging import StagedOutputs, prepare_output_dir, publishes_together
from .credit import product_credit
from .nomap import make_nomap_extras
from .product_source import DTM, KINDS, ProductSource, open_product, quiet_gdal
from .qlook import write_qlook
from .readme_index import publish_readme, read_readme
from .readme_txt import directory_keywords, product_entry
from .renderings import QLOOK_SUFFIX, THUMB_WIDTH, ProductPreviews, render_product

JPEG_QUALITY = 90

__all__ = ["make_extras", "KINDS", "NOMAP"]


@publishes_together
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
    product_id: str | None = None,
    overwrite: bool = False,
    report: Callable[[str], None] | None = None,
    root: str | os.PathLike[str] | None = None,
    vertical_datum: str | None = None,
) -> list[Path]:
    """Write the Extras of PRODUCTS into OUTDIR; return the paths written.

    `browse_width` defaults to 1024 px for DTMs and 2048 px for orthoimages (never
    wider than the data); `kind` ("dtm" or "ortho") overrides detection for all
    products. `exaggeration` is the shaded relief's vertical exaggeration (default:
    1, raised automatically when the relief would be too faint to see at preview
    scale, and then printed on the images). The credit line is `credit`, else the
    params' CREDIT, else the credit of `profile`, else the product's own (see
    `credit.product_credit`). `report`, when given, receives one line per product
    saying which kind it was taken for and why (after success).

    `root`: the directory tree the files a product's label names may lie in (a volume's
    LABEL/ beside DATA/), when the label lies inside it; by default the label's own directory
    is the only tree trusted. `vertical_datum`: what the DTMs' heights are above, stated in
    the legends and README.TXT (e.g. "the Mars 2000 areoid"); by default only what a label's
    own words say, else that the label does not name it.

    `kind` "nomap" takes one HiRISE observation's RED and/or IRB NOMAP mosaics
    (not map-projected) and writes the six NOMAP Extras (see `nomap`); `product_id`
    then gives the observation ID when the file names carry none.
    """
    if not products:
        raise PdsgenError(None, "no products given")
    if kind == NOMAP:
        _refuse_relief_options(thumb_width, azimuth, altitude, exaggeration)
        if vertical_datum is not None:
            raise ParamsError(None, f"{param('vertical_datum')} has no use with {param('kind', 'nomap')} "
                                    "(NOMAP Extras show no heights)")
        if root is not None:
            raise ParamsError(None, f"{param('root')} has no use with {param('kind', 'nomap')} "
                                    "(NOMAP mosaics are read as images, without labels)")
        return _make_nomap(products, outdir, credit, params, browse_width, profile,
                           product_id, overwrite, report)
    if product_id is not None:
        raise ParamsError(None, f"{param('product_id')} names a NOMAP observation; it needs {param('kind', 'nomap')}")
    azimuth = _check_options(browse_width, thumb_width, azimuth, altitude, exaggeration)
    keywords = resolve_params(params)
    with quiet_gdal():
        sources = [open_product(p, kind, root=root, vertical_datum=_datum_text(vertical_datum)) for p in products]
        credits = [product_credit(src, credit, keywords, profile) for src in sources]
        _check_unique_ids(sources)
        read_readme(Path(outdir))  # an unreadable README.TXT stops the run before writing
        outdir = prepare_output_dir(outdir)
        written: list[Path] = []
        entries = []
        shown = is_large(sum(src.width * src.height for src in sources), len(sources))
        for done, (src, credit_line) in enumerate(zip(sources, credits, strict=True), start=1):
            previews = render_product(src, credit=credit_line, browse_width=browse_width,
                                      thumb_width=thumb_width, azimuth=azimuth,
                                      altitude=altitude, exaggeration=exaggeration)
            written += _write_product_extras(previews, outdir, overwrite)
            entries.append(product_entry(previews, credit_line, azimuth, altitude))
            if shown:  # a release's worth of products: how far through them
                advance(done, len(sources), "products")
        readme = publish_readme(outdir, entries, directory_keywords(keywords))
    if report is not None:  # after success only: a failed run says one thing, its error
        for src in sources:
            what = "a DTM" if src.kind == DTM else "an orthoimage"
            report(f"{src.path}: taken as {what} ({src.kind_reason})")
    return [*written, readme]


def _datum_text(vertical_datum: str | None) -> str | None:
    """The datum as the legends write it ("m above <datum>"): one line of 7-bit text."""
    if vertical_datum is None:
        return None
    text = " ".join(str(vertical_datum).split())
    if not text or not text.isascii() or '"' in text or len(text) > 60:
        raise ParamsError(None, f"{param('vertical_datum')} must be up to 60 characters of 7-bit text without "
                                f"double quotes (e.g. {param('vertical_datum', 'the Mars 2000 areoid')})")
    return text


def _refuse_relief_options(thumb_width: int, azimuth: float, altitude: float, exaggeration: float | None) -> None:
    """NOMAP Extras have no thumbnail and no shaded relief: an option for them would be ignored."""
    given = {"thumb_width": thumb_width != THUMB_WIDTH, "azimuth": azimuth != 315.0,
             "altitude": altitude != 45.0, "exaggeration": exaggeration is not None}
    for name, set_by_caller in given.items():
        if set_by_caller:
            raise ParamsError(None, f"{param(name)} has no use with {param('kind', 'nomap')} "
                                    "(NOMAP Extras have no thumbnail or shaded relief)")


def _make_nomap(products: Sequence[str | os.PathLike[str]], outdir: str | os.PathLike[str],
                credit: str | None, params: str | os.PathLike[str] | Mapping[str, ParamValue] | None,
                browse_width: int | None, profile: str | None, product_id: str | None,
                overwrite: bool, report: Callable[[str], None] | None) -> list[Path]:
    """The NOMAP branch of make_extras: the same credit, params and option checks."""
    if browse_width is not None:
        _check_int("browse width", browse_width, 16, 65500)
    keywords = resolve_params(params)
    return make_nomap_extras(
        products, outdir, product_id=product_id,
        credit=lambda src: product_credit(src, credit, keywords, profile),
        keywords=directory_keywords(keywords), browse_width=browse_width,
        overwrite=overwrite, jpeg_quality=JPEG_QUALITY, report=report)


def _write_product_extras(previews: ProductPreviews, outdir: Path, overwrite: bool
                          ) -> list[Path]:
    """One product's JPEGs (and an orthoimage's QLOOK.JP2), all published together."""
    pid = previews.source.product_id
    jobs: list[tuple[Path, Image.Image, bool]] = []
    for p in previews.previews:
        r = p.rendering
        jobs += [(outdir / f"{pid}.{r.browse}.jpg", p.browse, False),
                 (outdir / f"{pid}.{r.annotated}.jpg", p.annotated, True),
                 (outdir / f"{pid}.{r.thumb}.jpg", p.thumb, False)]
    paths = [path for path, _, _ in jobs]
    qlook = outdir / f"{pid}.{QLOOK_SUFFIX}" if previews.source.kind != DTM else None
    with StagedOutputs(paths + ([qlook] if qlook else []), overwrite) as staged:
        for path, image, annotated in jobs:
            options = {"quality": JPEG_QUALITY}
            if annotated or image.mode == "RGB":
                options["subsampling"] = 0 if annotated else 2
            image.save(staged.path(path), format="JPEG", **options)
        if qlook is not None:
            write_qlook(previews.source, previews.stretches, staged.path(qlook))
    return paths + ([qlook] if qlook else [])


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
    return wrap_360(float(azimuth)) + 0.0  # + 0.0 turns -0.0 into 0.0


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
