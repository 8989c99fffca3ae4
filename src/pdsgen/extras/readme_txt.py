"""README.TXT of an Extras directory: what each file shows and how to read the data.

The text comes from the jinja2 template `templates/extras_readme.txt.j2`; this module
fills it from the products' labels, the params file and the previews just made, and
then enforces the archive's plain-text rules: 7-bit ASCII, CR LF line ends, no line
longer than 80 bytes with its CR LF (long lines are wrapped under their value
column).

README.TXT is also the only record of what the directory holds: a later
`pdsgen extras` call into the same directory reads the product entries and the
producer keywords back from it (`readme_index`), so nothing hidden is kept beside
it. The field tables below are that grammar, shared by the template that writes
the fields and the parser that reads them back.
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import jinja2
from PIL import Image

from ..encode import ascii_text
from ..formats.checksum import label_md5
from ..geo.conventions import wrap_360
from ..label.grammar import MAX_LINE_BYTES as GRAMMAR_MAX_LINE_BYTES
from ..missions.hirise import SYNTHETIC_BLUE_BG, SYNTHETIC_BLUE_RED, rdr_extras_line
from ..params import ParamValue
from ..resources import templates_dir
from .colour_ramp import RAMP_NAME
from .decimate import valid_range
from .product_source import DTM, ProductSource
from .renderings import extras_file_names, nomap_file_names
from .stretch import DTM_HIGH_PERCENT, DTM_LOW_PERCENT

if TYPE_CHECKING:
    from .renderings import ProductPreviews

README_NAME = "README.TXT"
TEMPLATE = "extras_readme.txt.j2"
MAX_LINE_BYTES = GRAMMAR_MAX_LINE_BYTES
VALUE_COLUMN = 19
_HANGING = re.compile(r"^(\s*[A-Za-z][A-Za-z0-9_ ()/.-]*:\s+)\S")

DTM_TYPE = "Digital terrain model (heights)"
ORTHO_TYPE = "Orthoimage"
NOMAP_TYPE = "HiRISE NOMAP mosaic (not map-projected)"
DEFAULT_PROJECT_NAME = "Extras of PDS3 map products"
DEFAULT_ARTIFACTS = "None reported by the producer."

# The product block: "Product ID:" at the margin, then these fields (label, entry
# key) two spaces in; a field whose value is empty is left out.
PRODUCT_ID_LABEL = "Product ID"
ENTRY_FIELDS = (
    ("Label identifier", "title"),
    ("Type", "kind_text"),
    ("Product file", "file_name"),
    # What the Extras were made from: the MD5 of the product's PDS3 label (formats/checksum.label_md5),
    # so Extras left from before a remake are known stale (validate DLV-017; deliver refuses them).
    ("Label MD5", "label_md5"),
    ("Source images", "sources"),
    ("Size", "size"),
    ("Bands", "bands"),
    ("Stretch", "stretch"),
    ("Projection", "projection"),
    ("Georeferencing", "georeferencing"),
    ("Post spacing", "spacing"),
    ("True scale", "true_scale"),
    ("Heights", "heights"),
    ("VALID_MINIMUM", "valid_minimum"),
    ("VALID_MAXIMUM", "valid_maximum"),
    ("DN to physical", "conversion"),
    ("No data", "nodata"),
    ("Relief shading", "shading"),
    ("Image credit", "credit"),
    ("Label producer", "label_producer"),
    ("Label institution", "label_institution"),
)
ENTRY_KEYS = ("product_id", *(key for _, key in ENTRY_FIELDS))
FILES_LABEL = "Extras files"

# Params keywords README.TXT shows (label at the margin); they describe the whole
# directory, so a later call's value replaces an earlier one and a keyword not
# given again is kept (read back from README.TXT).
DIRECTORY_FIELDS = (
    ("PRODUCER_FULL_NAME", "Producer"),
    ("PRODUCER_INSTITUTION_NAME", "Institution"),
    ("TECHNICAL_CONTACT", "Technical contact"),
    ("RATIONALE_DESC", "Rationale"),
    ("EXTRACTION_METHOD", "Extraction method"),
    ("VERTICAL_PRECISION", "Vertical precision"),
)
DIRECTORY_KEYWORDS = ("PROJECT_NAME", *(k for k, _ in DIRECTORY_FIELDS), "KNOWN_ARTIFACTS")

Entry = dict[str, str]


def field_line(label: str, indent: int = 2) -> str:
    """The start of a field line: indent, "Label:", padding to the value column."""
    head = " " * indent + f"{label}:"
    return head.ljust(VALUE_COLUMN) if len(head) < VALUE_COLUMN else head + " "


def product_entry(previews: ProductPreviews, credit: str, azimuth: float,
                  altitude: float) -> Entry:
    """Everything README.TXT says about one product, as text (see ENTRY_FIELDS)."""
    src = previews.source
    is_dtm = src.kind == DTM
    low, high = _valid_range(previews)
    bands = f" x {src.band_count} bands" if src.band_count > 1 else ""
    shading = (f"light from azimuth {azimuth:g} degrees, altitude {altitude:g} degrees, "
               f"vertical exaggeration {previews.exaggeration:g}x") if is_dtm else ""
    return {
        **empty_entry(),
        "product_id": src.product_id,
        "title": src.title if src.title and src.title != src.product_id else "",
        "kind_text": DTM_TYPE if is_dtm else ORTHO_TYPE,
        "file_name": src.path.name,
        "label_md5": (label_md5(src.label_path) or "") if src.label_path is not None else "",
        "sources": _sources(src),
        "size": f"{src.width} samples x {src.height} lines{bands}",
        "projection": _projection(src),
        "georeferencing": _georeferencing(src),
        "spacing": _spacing(src),
        "true_scale": (f"{_metres(previews.scale.metres_per_column / previews.grid.step_x)} "
                       f"per product pixel along rows at the image centre (latitude "
                       f"{previews.scale.latitude:.3f}, longitude "
                       f"{wrap_360(previews.scale.longitude):.3f} east)"),
        "heights": _heights(src) if is_dtm else "",
        "valid_minimum": low, "valid_maximum": high,
        "conversion": _conversion(src),
        "nodata": _nodata(src),
        "shading": shading,
        "credit": credit,
        "label_producer": _label(src, "PRODUCER_FULL_NAME"),
        "label_institution": _label(src, "PRODUCER_INSTITUTION_NAME"),
    }


def empty_entry() -> Entry:
    """An entry with every field empty (empty fields are left out of README.TXT)."""
    return {key: "" for key in ENTRY_KEYS}


def is_dtm_entry(entry: Mapping[str, str]) -> bool:
    return entry.get("kind_text") == DTM_TYPE


def is_nomap_entry(entry: Mapping[str, str]) -> bool:
    return entry.get("kind_text") == NOMAP_TYPE


def entry_files(entry: Mapping[str, str], outdir: Path) -> list[tuple[str, str, str]] | None:
    """(name, what, size) of the entry's Extras files in OUTDIR; None if one is missing."""
    files = []
    names = (nomap_file_names(entry["product_id"]) if is_nomap_entry(entry) else
             extras_file_names(entry["product_id"], is_dtm_entry(entry)))
    for name, what in names:
        size = _image_size(outdir / name)
        if size is None:
            return None
        files.append((name, what, f"{size[0]} x {size[1]} pixels"))
    return files


def _image_size(path: Path) -> tuple[int, int] | None:
    """Width and height from the image header (Pillow reads only the header)."""
    if not path.is_file():
        return None
    try:
        with Image.open(path) as image:
            return image.size
    except OSError:
        return None


def directory_keywords(params: Mapping[str, ParamValue]) -> dict[str, str]:
    """The README keywords this call's params give (only those given)."""
    return {key: _param(params, key) for key in DIRECTORY_KEYWORDS if key in params}


def keyword_defaults(entries: Sequence[Mapping[str, str]]) -> dict[str, str]:
    """What README.TXT shows for each directory keyword nobody gave."""
    return {"PROJECT_NAME": DEFAULT_PROJECT_NAME,
            "PRODUCER_FULL_NAME": _first(entries, "label_producer"),
            "PRODUCER_INSTITUTION_NAME": _first(entries, "label_institution"),
            "TECHNICAL_CONTACT": "UNK", "RATIONALE_DESC": "", "EXTRACTION_METHOD": "",
            "VERTICAL_PRECISION": "", "KNOWN_ARTIFACTS": DEFAULT_ARTIFACTS}


def render_readme(entries: Sequence[Mapping[str, str]], files: Sequence[list[tuple[str, str, str]]],
                  keywords: Mapping[str, str]) -> bytes:
    """README.TXT bytes for these entries and their files (ASCII, CR LF, <= 80 bytes a line)."""
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(templates_dir()),
                             trim_blocks=True, lstrip_blocks=True, autoescape=False,
                             undefined=jinja2.StrictUndefined, keep_trailing_newline=True,
                             finalize=ascii_text)  # every {{ }} value leaves as escaped ASCII text
    env.filters["field"] = field_line
    # One paragraph each: README.TXT is read back, and wrapping keeps no line breaks.
    given = {k: " ".join(v.split()) for k, v in keywords.items()}
    shown = {**keyword_defaults(entries), **{k: v for k, v in given.items() if v}}
    text = env.get_template(TEMPLATE).render(
        project_name=shown["PROJECT_NAME"],
        products=[{**e, "files": f} for e, f in zip(entries, files, strict=True)],
        product_id_label=PRODUCT_ID_LABEL, entry_fields=ENTRY_FIELDS, files_label=FILES_LABEL,
        directory=[(label, shown[key]) for key, label in DIRECTORY_FIELDS if shown[key]],
        credit=_distinct(entries, "credit", "; ") or "none",
        known_artifacts=shown["KNOWN_ARTIFACTS"],
        dtm_low=f"{DTM_LOW_PERCENT:g}", dtm_high=f"{100 - DTM_HIGH_PERCENT:g}",
        ramp=RAMP_NAME, nomap=any(is_nomap_entry(e) for e in entries),
        observations=observation_index(entries, files),
        blue_bg=f"{SYNTHETIC_BLUE_BG:g}", blue_red=f"{-SYNTHETIC_BLUE_RED:g}",
    )
    return plain_text_bytes(text)


def observation_index(entries: Sequence[Mapping[str, str]],
                      files: Sequence[list[tuple[str, str, str]]]) -> list[tuple[str, list[str]]]:
    """HiRISE observations' Extras, one line per file ("name  what"), in directory order.

    The release gives each observation twelve Extras over several products (RED and
    COLOR RDRs, three NOMAP renderings); this gathers them under the observation.
    """
    found: dict[str, list[tuple[str, str]]] = {}
    for entry, entry_files_ in zip(entries, files, strict=True):
        for name, _, _ in entry_files_:
            line = rdr_extras_line(entry["product_id"], name)
            if line is not None:
                found.setdefault(line[0], []).append((name, line[1]))
    index = []
    for observation, lines in found.items():
        width = max(len(name) for name, _ in lines)
        index.append((observation, [f"{name.ljust(width)}  {what}" for name, what in lines]))
    return index


def _distinct(entries: Sequence[Mapping[str, str]], key: str, separator: str) -> str:
    """The different values of `key` among the entries, in order of first appearance."""
    return separator.join(dict.fromkeys(str(e[key]) for e in entries if e.get(key)))


def _first(entries: Sequence[Mapping[str, str]], key: str) -> str:
    return next((str(e[key]) for e in entries if e.get(key) not in (None, "", "UNK")), "UNK")


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


def _valid_range(previews: ProductPreviews) -> tuple[str, str]:
    """The label's VALID_MINIMUM/MAXIMUM, else (for DTMs) computed over the full raster."""
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
    from ..geo.label_georef import projection_object

    mp = projection_object(src.label)
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


def _georeferencing(src: ProductSource) -> str:
    if src.georeferencing != "label":
        return ""
    return ("from the label's map projection object (GDAL reads none), with the "
            "standard PDS3 projection offset convention")


def _spacing(src: ProductSource) -> str:
    from ..geo.label_georef import projection_object

    mp = projection_object(src.label)
    if mp is not None and "MAP_SCALE" in mp:
        scale = mp["MAP_SCALE"]
        value, unit = getattr(scale, "value", scale), getattr(scale, "units", "")
        return f"{value:g} {unit or 'KM/PIXEL'} (MAP_SCALE)"
    unit = "degrees" if src.crs.is_geographic else "metres"
    return f"{abs(src.transform.a):.6g} x {abs(src.transform.e):.6g} {unit} per pixel"


def _heights(src: ProductSource) -> str:
    assert src.heights is not None
    text = f"metres above {src.heights.datum}"
    if src.heights.radius_removed_m is not None:
        text += (f"; the label's OFFSET ({src.heights.radius_removed_m:.10g} m) is that "
                 f"sphere's radius, so planetary radius = height + OFFSET")
    return text


def _conversion(src: ProductSource) -> str:
    if src.kind == DTM:
        return f"height in metres = DN * {src.scale:.10g} + {src.offset:.10g}"
    image = src.label.get("UNCOMPRESSED_FILE", {}).get("IMAGE", src.label.get("IMAGE", {}))
    what = "I/F" if "SCALING_FACTOR" in image else "physical value"
    return f"{what} = DN * {src.scale:.10g} + {src.offset:.10g}"


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


def _param(params: Mapping[str, ParamValue], key: str) -> str:
    value = params.get(key)
    if value is None:
        return ""
    return ", ".join(value) if isinstance(value, list) else str(value)


def _label(src: ProductSource, key: str) -> str:
    value = src.label.get(key)
    return "" if value in (None, "", "N/A", "UNK") else " ".join(str(value).split())
