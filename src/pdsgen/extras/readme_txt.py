"""README.TXT of an Extras directory: what each file shows and how to read the data.

The text comes from the jinja2 template `templates/extras_readme.txt.j2`; this module
fills it from the products' labels, the params file and the previews just made, and
then enforces the archive's plain-text rules: 7-bit ASCII, CR LF line ends, no line
longer than 80 bytes with its CR LF (long lines are wrapped under their value
column).
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import jinja2

from ..label.grammar import MAX_LINE_BYTES as GRAMMAR_MAX_LINE_BYTES
from ..products.params import ParamValue
from ..resources import templates_dir
from .colour_ramp import RAMP_NAME
from .product_source import DTM, ProductSource
from .stretch import DTM_HIGH_PERCENT, DTM_LOW_PERCENT

if TYPE_CHECKING:
    from .renderings import ProductPreviews

README_NAME = "README.TXT"
TEMPLATE = "extras_readme.txt.j2"
MAX_LINE_BYTES = GRAMMAR_MAX_LINE_BYTES
_HANGING = re.compile(r"^(\s*[A-Za-z][A-Za-z0-9_ ()/.-]*:\s+)\S")


# Params keywords README.TXT shows; they describe the whole directory, so a later
# call's value replaces an earlier one and a keyword not given again is kept.
DIRECTORY_KEYWORDS = ("PROJECT_NAME", "PRODUCER_FULL_NAME", "PRODUCER_INSTITUTION_NAME",
                      "TECHNICAL_CONTACT", "RATIONALE_DESC", "EXTRACTION_METHOD",
                      "VERTICAL_PRECISION", "KNOWN_ARTIFACTS")

# What a product entry holds (all JSON types), so a recorded entry can be checked.
ENTRY_KEYS = frozenset({
    "product_id", "kind_text", "file_name", "sources", "width", "height", "bands",
    "projection", "spacing", "true_scale", "valid_minimum", "valid_maximum", "conversion",
    "nodata", "is_dtm", "exaggeration", "files", "credit", "azimuth", "altitude",
    "label_producer", "label_institution",
})


def product_entry(previews: ProductPreviews, credit: str, azimuth: float,
                  altitude: float) -> dict[str, Any]:
    """Everything README.TXT says about one product, as plain JSON-able values.

    The entry is all README.TXT needs, so products of earlier calls can be described
    again from their recorded entries without re-reading them.
    """
    entry = _product_context(previews)
    entry["files"] = [list(f) for f in entry["files"]]
    entry.update(credit=credit, azimuth=f"{azimuth:g}", altitude=f"{altitude:g}",
                 label_producer=_label([previews], "PRODUCER_FULL_NAME"),
                 label_institution=_label([previews], "PRODUCER_INSTITUTION_NAME"))
    return entry


def directory_keywords(params: Mapping[str, ParamValue]) -> dict[str, str]:
    """The README keywords this call's params give (only those given)."""
    return {key: _param(params, key, "") for key in DIRECTORY_KEYWORDS if key in params}


def render_readme(entries: Sequence[Mapping[str, Any]], keywords: Mapping[str, str]) -> bytes:
    """The README.TXT bytes for these product entries (ASCII, CR LF, <= 80 bytes a line)."""
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(templates_dir()),
                             trim_blocks=True, lstrip_blocks=True, autoescape=False,
                             undefined=jinja2.StrictUndefined, keep_trailing_newline=True)
    light = [e for e in entries if e["is_dtm"]] or list(entries)
    text = env.get_template(TEMPLATE).render(
        project_name=keywords.get("PROJECT_NAME", "Extras of PDS3 map products"),
        products=entries,
        producer=keywords.get("PRODUCER_FULL_NAME", _first(entries, "label_producer")),
        institution=keywords.get("PRODUCER_INSTITUTION_NAME",
                                 _first(entries, "label_institution")),
        contact=keywords.get("TECHNICAL_CONTACT", "UNK"),
        credit=_distinct(entries, "credit", "; ") or "none",
        rationale=keywords.get("RATIONALE_DESC", ""),
        extraction_method=keywords.get("EXTRACTION_METHOD", ""),
        vertical_precision=keywords.get("VERTICAL_PRECISION", ""),
        known_artifacts=keywords.get("KNOWN_ARTIFACTS", "None reported by the producer."),
        dtm_low=f"{DTM_LOW_PERCENT:g}", dtm_high=f"{100 - DTM_HIGH_PERCENT:g}",
        azimuth=_distinct(light, "azimuth", " or "), altitude=_distinct(light, "altitude", " or "),
        ramp=RAMP_NAME,
    )
    return plain_text_bytes(text)


def _distinct(entries: Sequence[Mapping[str, Any]], key: str, separator: str) -> str:
    """The different values of `key` among the entries, in order of first appearance."""
    return separator.join(dict.fromkeys(str(e[key]) for e in entries if e[key]))


def _first(entries: Sequence[Mapping[str, Any]], key: str) -> str:
    return next((str(e[key]) for e in entries if e[key] not in ("", "UNK")), "UNK")


def plain_text_bytes(text: str) -> bytes:
    """ASCII, CR LF, lines wrapped to at most 78 characters (80 bytes with CR LF)."""
    text = text.replace("\t", "    ").encode("ascii", "replace").decode("ascii")
    lines: list[str] = []
    for line in text.splitlines():
        lines += _wrap(line.rstrip(), MAX_LINE_BYTES - 2)
    while lines and not lines[-1]:
        lines.pop()
    return ("\r\n".join(lines) + "\r\n").encode("ascii")


def _wrap(line: str, width: int) -> list[str]:
    if len(line) <= width:
        return [line]
    match = _HANGING.match(line)
    indent = " " * len(match.group(1)) if match and len(match.group(1)) <= width // 2 else (
        " " * (len(line) - len(line.lstrip()) + 2))
    wrapped = textwrap.wrap(line, width=width, subsequent_indent=indent,
                            break_long_words=True, break_on_hyphens=False)
    return wrapped or [line[:width]]


def _product_context(previews: ProductPreviews) -> dict[str, Any]:
    from . import extras_file_names  # the names are defined next to the writer

    src = previews.source
    sizes = {}
    for p in previews.previews:
        r = p.rendering
        sizes[r.browse] = p.browse.size
        sizes[r.annotated] = p.annotated.size
        sizes[r.thumb] = p.thumb.size
    files = []
    for name, what in extras_file_names(previews):
        code = name[len(src.product_id) + 1: -len(".jpg")]
        w, h = sizes[code]
        files.append((name, what, f"{w} x {h} pixels"))
    low, high = _valid_range(previews)
    return {
        "product_id": src.product_id,
        "kind_text": "Digital terrain model (elevations)" if src.kind == DTM else "Orthoimage",
        "file_name": src.path.name,
        "sources": _sources(src),
        "width": src.width, "height": src.height, "bands": src.band_count,
        "projection": _projection(src),
        "spacing": _spacing(src),
        "true_scale": (f"{_metres(previews.scale.metres_per_column / previews.grid.step_x)} "
                       f"per product pixel along rows at the image centre (latitude "
                       f"{previews.scale.latitude:.3f}, longitude "
                       f"{previews.scale.longitude % 360.0:.3f} east)"),
        "valid_minimum": low, "valid_maximum": high,
        "conversion": _conversion(src),
        "nodata": _nodata(src),
        "is_dtm": src.kind == DTM,
        "exaggeration": f"{previews.exaggeration:g}",
        "files": files,
    }


def _valid_range(previews: ProductPreviews) -> tuple[str, str]:
    """The label's VALID_MINIMUM/MAXIMUM, else (for DTMs) computed over the full raster."""
    from .decimate import valid_range

    src = previews.source
    if src.valid_minimum is not None and src.valid_maximum is not None:
        return _number(src.valid_minimum), _number(src.valid_maximum)
    if src.kind == DTM:
        found = valid_range(src)
        if found is not None:
            return (f"{_number(found[0])} (computed, not in the label)",
                    f"{_number(found[1])} (computed, not in the label)")
    return "not given in the label", "not given in the label"


def _sources(src: ProductSource) -> str:
    value = src.label.get("SOURCE_PRODUCT_ID")
    if value is None or value == "N/A":
        return "not given in the label"
    if isinstance(value, (list, tuple, set)):
        return ", ".join(str(v) for v in value)
    return str(value)


def _projection(src: ProductSource) -> str:
    mp = src.label.get("IMAGE_MAP_PROJECTION")
    if mp is not None and "MAP_PROJECTION_TYPE" in mp:
        parts = [str(mp["MAP_PROJECTION_TYPE"])]
        for key, name in (("CENTER_LATITUDE", "centre latitude"),
                          ("CENTER_LONGITUDE", "centre longitude")):
            value = getattr(mp.get(key), "value", mp.get(key))
            if isinstance(value, (int, float)):
                parts.append(f"{name} {value:g} deg")
        return ", ".join(parts)
    match = re.search(r'PROJECTION\["([^"]+)"', src.crs.to_wkt())
    name = match.group(1).replace("_", " ") if match else "geographic (longitude/latitude)"
    return f"{name} (from the GDAL georeferencing)"


def _spacing(src: ProductSource) -> str:
    mp = src.label.get("IMAGE_MAP_PROJECTION")
    if mp is not None and "MAP_SCALE" in mp:
        scale = mp["MAP_SCALE"]
        value, unit = getattr(scale, "value", scale), getattr(scale, "units", "")
        return f"{value:g} {unit or 'METERS/PIXEL'} (MAP_SCALE)"
    unit = "degrees" if src.crs.is_geographic else "metres"
    return f"{abs(src.transform.a):.6g} x {abs(src.transform.e):.6g} {unit} per pixel"


def _conversion(src: ProductSource) -> str:
    scale = src.scale
    offset = src.offset
    if src.kind == DTM:
        return f"elevation in metres = DN * {scale:.10g} + {offset:.10g}"
    image = src.label.get("UNCOMPRESSED_FILE", {}).get("IMAGE", src.label.get("IMAGE", {}))
    what = "I/F" if "SCALING_FACTOR" in image else "physical value"
    return f"{what} = DN * {scale:.10g} + {offset:.10g}"


def _nodata(src: ProductSource) -> str:
    if src.nodata is None:
        return "no no-data value"
    text = f"DN {src.nodata:.10g} (black in the previews)"
    if src.special_dns:
        text += "; special DNs (saturation) " + ", ".join(
            f"{v:g}" for v in sorted(set(src.special_dns)))
    return text


def _metres(value: float) -> str:
    return f"{value:.0f} m" if value >= 100 else f"{value:.3g} m"


def _number(value: float) -> str:
    return f"{value:.10g}"


def _param(params: Mapping[str, ParamValue], key: str, default: str) -> str:
    value = params.get(key)
    if value is None:
        return default
    return ", ".join(value) if isinstance(value, list) else str(value)


def _label(products: Sequence[ProductPreviews], key: str) -> str:
    for p in products:
        value = p.source.label.get(key)
        if value not in (None, "", "N/A"):
            return str(value)
    return "UNK"
