"""Find what an Extras run needs to know about one product, whoever wrote it.

A product reaches us as a PDS3 `.IMG` with an attached label, a detached `.LBL`
pointing at an `.IMG` or a `.JP2`, a bare `.JP2`/`.IMG` whose label sits beside it,
or a GeoTIFF. GDAL (through rasterio) reads the pixels and the georeferencing of all
of them; the label, when there is one, is read (pdsgen.label) because it says things GDAL
does not pass on reliably: the product ID, which DN means "no data" (MISSING_CONSTANT
as a float bit pattern, CORE_NULL for a JP2 that carries no nodata of its own), the
DN-to-physical mapping, VALID_MINIMUM/MAXIMUM, and whether the product is a DTM.
"""

from __future__ import annotations

import math
import os
import re
import struct
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape

import numpy as np
import rasterio
from rasterio.errors import NotGeoreferencedWarning, RasterioError
from rasterio.transform import Affine

from ..errors import PdsgenError, param
from ..formats.kind import (
    DTM,
    KINDS,
    LENGTH_UNITS,
    ORTHO,
    KindDecision,
    decide_kind,
    raster_facts,
    sample_shape,
    sampled_range,
)
from ..formats.raster import not_utf8
from ..geo.label_georef import LabelGeorefError, label_georeferencing
from ..label.beside import find_beside, outside_tree, trusted_tree
from ..label.grammar import FLOAT_SAMPLE_TYPES
from ..label.mapping import label_mapping
from ..label.read import LabelFile, structure_problem
from ..label.tree import Block, every_named_file
from ..missions import LabelFacts, detect_mission
from ..missions.hrsc import is_dtm_name as is_hrsc_dtm_name
from .heights import HeightReference, height_reference, mission_datum, radius_offset_m

__all__ = ["DTM", "ORTHO", "KINDS", "ProductSource", "open_product", "quiet_gdal"]

# GDAL's block cache defaults to 5 % of RAM; a preview needs only a few blocks at a
# time, so a small cache keeps memory bounded by the preview size, not the raster.
# In MB, the unit formats/raster.py measured: as a byte count GDAL_CACHEMAX raised peak memory.
# One decoding thread: GDAL reports a worker thread's errors (a damaged JPEG 2000
# tile) on stderr itself and hands back zeros, where the calling thread's errors
# reach rasterio as an exception we turn into one line.
GDAL_ENV = {"GDAL_CACHEMAX": 16, "GDAL_PAM_ENABLED": "NO", "GDAL_NUM_THREADS": "1"}

_FLOAT_TYPES = FLOAT_SAMPLE_TYPES
# GDAL metadata items that describe a raster's content (searched for height words).
# A pixel smaller than this in area (in the CRS units squared) is no real grid: its inverse
# loses every digit (1e-300 m squared underflows to zero).
_SMALLEST_PIXEL_AREA = 1e-30


@contextmanager
def quiet_gdal() -> Iterator[None]:
    """GDAL settings for previews, with library warnings kept from the user.

    GDAL's block cache defaults to 5 % of RAM; a preview needs only a few blocks
    at a time, so a small cache keeps memory bounded by the preview size. A
    product without a geotransform (its georeferencing then comes from the
    label) makes rasterio warn, and damaged data make numpy warn about
    overflows: neither is the user's business beyond the one-line error or the
    result, so both are silenced here.
    """
    with warnings.catch_warnings(), np.errstate(all="ignore"), rasterio.Env(**GDAL_ENV):
        warnings.simplefilter("ignore", NotGeoreferencedWarning)
        warnings.simplefilter("ignore", RuntimeWarning)
        yield


@dataclass
class ProductSource:
    """One product as the Extras see it (metadata only; pixels are read on demand)."""

    path: Path                      # what the user named
    raster_path: Path               # what GDAL opens
    label_path: Path | None         # the PDS3 label, attached or detached, if any
    product_id: str
    kind: str                       # DTM or ORTHO
    width: int
    height: int
    band_count: int
    dtype: str
    crs: Any
    transform: Any
    nodata: float | None            # DN meaning "no data", as the label (or GDAL) says
    special_dns: tuple[float, ...]  # other DNs to leave out of statistics (saturation)
    scale: float = 1.0              # physical = DN * scale + offset
    offset: float = 0.0
    unit: str = ""
    valid_minimum: float | None = None   # physical units, from the label
    valid_maximum: float | None = None
    label: dict = field(default_factory=dict)

    gdal_nodata: float | None = None     # what GDAL itself reports
    mission: str = ""                    # profile whose conventions the product follows, if known
    title: str = ""                      # PRODUCT_ID as the label writes it (else product_id)
    kind_reason: str = ""                # why the product was taken for a DTM or an orthoimage
    heights: HeightReference | None = None   # DTMs: what the heights are measured from
    georeferencing: str = "GDAL"         # "GDAL" or "label" (IMAGE_MAP_PROJECTION read here)

    @contextmanager
    def open(self, out_shape: tuple[int, int] | None = None
             ) -> Iterator[rasterio.io.DatasetReader]:
        """Open the raster, overriding GDAL's nodata with the label's when they differ.

        The override is a small in-memory VRT: reads through it, including
        decimated reads with averaging, leave the label's no-data DN out. A VRT
        averages from the full resolution, so when the caller will read at
        `out_shape` (height, width) the VRT is built over the finest reduced
        resolution level (JPEG 2000 level, GeoTIFF overview) that is still at
        least that size: the read then decodes that level only.
        """
        with quiet_gdal():
            target: str | Path = self.raster_path
            try:
                if self.nodata is not None and not _same_nodata(self.gdal_nodata, self.nodata):
                    target = self._nodata_vrt(self._overview_level(out_shape))
                with rasterio.open(target) as ds:
                    yield ds
            except RasterioError as exc:
                raise PdsgenError(self.path, f"cannot read the raster ({_first_line(exc)})") from None

    def _overview_level(self, out_shape: tuple[int, int] | None) -> int | None:
        if out_shape is None:
            return None
        with rasterio.open(self.raster_path) as ds:
            factors = ds.overviews(1)
        reduction = min(self.height / out_shape[0], self.width / out_shape[1])
        usable = [i for i, f in enumerate(factors) if f <= reduction]
        return usable[-1] if usable else None

    def _nodata_vrt(self, level: int | None) -> str:
        gdal_type = {"uint8": "Byte", "int8": "Int8", "uint16": "UInt16", "int16": "Int16",
                     "uint32": "UInt32", "int32": "Int32", "float32": "Float32",
                     "float64": "Float64"}[self.dtype]
        width, height, transform = self.width, self.height, self.transform
        options = ""
        if level is not None:
            with rasterio.open(self.raster_path, OVERVIEW_LEVEL=level) as ds:
                width, height = ds.width, ds.height
            transform = transform @ Affine.scale(self.width / width, self.height / height)
            options = f'<OpenOptions><OOI key="OVERVIEW_LEVEL">{level}</OOI></OpenOptions>'
        src = escape(os.fspath(self.raster_path.resolve()))
        bands = "".join(
            f'<VRTRasterBand dataType="{gdal_type}" band="{b}">'
            f"<NoDataValue>{self.nodata!r}</NoDataValue>"
            f'<SimpleSource><SourceFilename relativeToVRT="0">{src}</SourceFilename>'
            f"{options}<SourceBand>{b}</SourceBand></SimpleSource></VRTRasterBand>"
            for b in range(1, self.band_count + 1)
        )
        geo = ""
        if self.crs is not None and self.georeferencing == "GDAL":
            geo += f"<SRS>{escape(self.crs.to_wkt())}</SRS>"
            t = transform
            geo += (f"<GeoTransform>{t.c!r}, {t.a!r}, {t.b!r}, {t.f!r}, {t.d!r}, {t.e!r}"
                    "</GeoTransform>")
        return (f'<VRTDataset rasterXSize="{width}" rasterYSize="{height}">'
                f"{geo}{bands}</VRTDataset>")


def open_product(path: str | os.PathLike[str], kind: str | None = None, *, root: str | os.PathLike[str] | None = None,
                 vertical_datum: str | None = None) -> ProductSource:
    """Inspect PRODUCT and return its description; PdsgenError if it is not usable.

    `root`: the tree the files its label names may lie in (a volume's LABEL/ or CATALOG/
    beside DATA/), when the label lies inside it; otherwise the label's own directory.
    `vertical_datum`: what a DTM's heights are above, as the user states it (heights.py)."""
    path = Path(path)
    trusted_root = Path(root) if root is not None else None
    if not path.exists():
        raise PdsgenError(path, "no such file")
    if kind is not None and kind not in KINDS:
        raise PdsgenError(path, f"unknown product kind {kind!r} (use dtm or ortho)")
    label_path, label = _find_label(path, trusted_root)
    raster_path = _raster_path(path, label_path, label, trusted_root)
    _refuse_unreadable(raster_path, label_path, label)
    try:
        with quiet_gdal(), rasterio.open(raster_path) as ds:
            info = raster_facts(ds)
    except RasterioError:
        raise PdsgenError(raster_path, "not a raster GDAL can read") from None
    except UnicodeEncodeError:  # GDAL takes names as UTF-8: a Latin-1 byte cannot be passed to it
        raise not_utf8(raster_path) from None
    image = _image_object(label)
    mission = _mission(label, path)
    src = ProductSource(
        path=path, raster_path=raster_path, label_path=label_path,
        product_id=_product_id(label, path), kind="", label=label, mission=mission,
        nodata=_label_nodata(image, info["dtype"], info["nodata"]),
        special_dns=_special_dns(image), title=_title(label, path),
        **{k: v for k, v in info.items() if k not in ("nodata", "scale", "offset", "hints")},
    )
    src.gdal_nodata = info["nodata"]
    src.scale, src.offset = _scaling(image, info)
    src.unit = str(image.get("UNIT", "") or "") or src.unit  # the label's, else GDAL's
    decision = (KindDecision(kind, f"{param('kind')} says so") if kind else
                decide_kind(label, image, info, path, lambda: _value_range(src), is_hrsc_dtm_name(path.stem)))
    src.kind, src.kind_reason = decision.kind, decision.reason
    _check_band_count(src)
    if src.kind == DTM:
        factor = LENGTH_UNITS.get(src.unit.upper(), 1.0)
        src.scale, src.offset = src.scale * factor, src.offset * factor
        radius = radius_offset_m(label, src.offset)
        src.heights = height_reference(label, image, mission_datum(mission, path.name), radius, vertical_datum)
        if radius is not None:  # radii -> heights above the reference sphere
            src.offset -= radius
    src.valid_minimum = _physical(image.get("VALID_MINIMUM"), src)
    src.valid_maximum = _physical(image.get("VALID_MAXIMUM"), src)
    if src.crs is None:
        _georeference_from_label(src)
    _refuse_degenerate_grid(src)
    return src


def _refuse_degenerate_grid(src: ProductSource) -> None:
    """A grid whose pixel has no usable size (0, 1e-300 m: its area underflows to zero, so no
    position maps back to a pixel) is refused in one line, before any scale bar is drawn."""
    transform = src.transform
    if transform is not None and src.crs is not None and (
            not all(map(math.isfinite, transform[:6])) or transform.is_degenerate
            or abs(transform.determinant) < _SMALLEST_PIXEL_AREA):
        raise PdsgenError(src.label_path or src.path, f"the map grid's pixel ({transform.a:.6g} x {transform.e:.6g}) "
                                                      "has no usable size; the georeferencing cannot be used")


def _georeference_from_label(src: ProductSource) -> None:
    """CRS and geotransform from the label's map projection when GDAL found none."""
    try:
        found = label_georeferencing(src.label)
    except LabelGeorefError as exc:
        raise PdsgenError(src.label_path or src.path, f"GDAL finds no georeferencing and the "
                                                      f"label's cannot be used: {exc}") from None
    if found is None:
        raise PdsgenError(src.path, "has no map projection (neither GDAL nor a PDS3 label "
                                    "gives one); Extras need georeferencing for the scale bar "
                                    "and north arrow")
    src.crs, src.transform = found
    src.georeferencing = "label"


def _value_range(src: ProductSource) -> tuple[float, float] | None:
    """Minimum and maximum of a small decimated read of band 1, physical units (the file opened
    as the product's label says: its nodata)."""
    shape = sample_shape(src.width, src.height)
    with src.open(shape) as ds:
        return sampled_range(ds, src.scale, src.offset, shape)


def _check_band_count(src: ProductSource) -> None:
    """A DTM is one band of heights; an orthoimage is grey (1 band) or colour (3)."""
    allowed = (1,) if src.kind == DTM else (1, 3)
    if src.band_count in allowed:
        return
    what = "a DTM needs exactly 1" if src.kind == DTM else "an orthoimage needs 1 or 3"
    hint = f"; use {param('kind', ORTHO)} for a colour image" if src.kind == DTM and src.band_count == 3 else ""
    raise PdsgenError(src.path, f"has {src.band_count} bands; {what}{hint}")


def _find_label(path: Path, root: Path | None = None) -> tuple[Path | None, dict]:
    """The product's PDS3 label (attached, the file itself, or a sibling), or none."""
    with _told_unreadable(path):
        own = LabelFile.read_pds3(path)
    if own is not None:
        return path, _label_values(own, root)
    if path.suffix.lower() in (".img", ".jp2"):
        sibling = find_beside(path.parent, f"{path.stem}.lbl")
        if sibling is not None:
            with _told_unreadable(sibling):
                return sibling, _label_values(LabelFile.read(sibling), root)
    return None, {}


@contextmanager
def _told_unreadable(path: Path) -> Iterator[None]:
    try:
        yield
    except OSError as exc:
        raise PdsgenError(path, f"cannot read ({exc.strerror})") from None


def _label_values(found: LabelFile, root: Path | None = None) -> dict:
    path, label = found.path, found.label
    broken = structure_problem(label)
    if broken is not None:
        raise PdsgenError(path, f"label cannot be parsed (line {broken.line}: {broken.message})")
    _refuse_outside(path, label.root, trusted_tree(path, root=root))
    return label_mapping(label)


def _refuse_outside(label_path: Path, root: Block, tree: Path) -> None:
    """Refuse a label naming a file outside the trusted tree (its directory, or the root the user
    gave when the label lies in it: ../x, /x, a link leading out): neither pdsgen nor GDAL (which
    follows a detached label's pointer itself) may read it."""
    for keyword, name, _ in every_named_file(root):
        if outside_tree(label_path.parent, name, tree) is not None:
            raise PdsgenError(label_path, f"{keyword} names {name!r}, which lies outside {tree}; not read")


def _raster_path(path: Path, label_path: Path | None, label: dict, root: Path | None = None) -> Path:
    """The file GDAL should open: the JP2 a COMPRESSED_FILE names, else the product."""
    if label_path is None:
        return path
    compressed = label.get("COMPRESSED_FILE")
    if compressed is not None and path.suffix.lower() != ".jp2":
        return _sibling(label_path, str(compressed.get("FILE_NAME", "")), root)
    if path.suffix.lower() == ".img" and label_path != path:
        return label_path  # GDAL opens a detached .IMG through its label
    return path


def _refuse_unreadable(raster_path: Path, label_path: Path | None, label: dict) -> None:
    """PdsgenError when the raster or a file the label's pointers name is no regular file
    (GDAL would block for ever on a FIFO named like the data, or read a device without end),
    is a JPEG 2000 file whose tiles would not fit in memory (formats/jp2_header.py), or is a
    PDS3 label of more objects than GDAL reads in reasonable time (formats/raster.py)."""
    from ..formats.jp2_header import decode_problem
    from ..formats.raster import gdal_label_problem

    named = [raster_path]
    if label_path is not None:  # find_beside passes over what is no regular file; GDAL does not
        names = [value[0] if isinstance(value, (list, tuple)) and value else value
                 for key, value in label.items() if key.startswith("^")]
        named += [label_path.parent / variant for name in names if isinstance(name, str) and name
                  for variant in {name, name.upper(), name.lower()}]  # as GDAL looks a name up
    for path in named:
        if path.exists() and not path.is_file():
            raise PdsgenError(path, "cannot read (not a regular file)")
        problem = decode_problem(path) or (gdal_label_problem(path) if path == raster_path else None)
        if problem is not None:
            raise PdsgenError(path, problem)


def _sibling(label_path: Path, name: str, root: Path | None = None) -> Path:
    """A file the label names, found case-insensitively (archives mix cases); with a `root` the
    label lies in, a name climbing within that tree (../DATA/X.JP2) too."""
    found = find_beside(label_path.parent, name)
    if found is not None:
        return found
    tree = trusted_tree(label_path, root=root)
    if outside_tree(label_path.parent, name, tree) is not None:  # ../x, /x, a link leading out: never read
        raise PdsgenError(label_path, f"the file it names, {name!r}, lies outside {tree}; not read")
    if tree != label_path.parent and (label_path.parent / name).is_file():
        return label_path.parent / name
    raise PdsgenError(label_path, f"the file it names, {name!r}, is missing")


def _image_object(label: dict) -> dict:
    if "IMAGE" in label:
        return label["IMAGE"]
    uncompressed = label.get("UNCOMPRESSED_FILE")
    if uncompressed is not None and "IMAGE" in uncompressed:
        return uncompressed["IMAGE"]
    return {}


def _mission(label: dict, path: Path) -> str:
    """"hrsc" or "hirise" when the label (or an HRSC file name) says so, else ""."""
    facts = LabelFacts(
        instrument_id=str(label.get("INSTRUMENT_ID", "") or ""),
        data_set_id=str(label.get("DATA_SET_ID", "") or ""),
        group_names=frozenset(str(key).upper() for key, value in label.items() if hasattr(value, "keys")),
        file_name=path.name,
    )
    return detect_mission(facts) or ""


def _title(label: dict, path: Path) -> str:
    """The product ID as the label writes it (case and all), for the annotated browses.

    Older labels without PRODUCT_ID name the product by IMAGE_ID (Magellan's
    'F-MIDR.20S145;1'); without either, the file name stands in.
    """
    for key in ("PRODUCT_ID", "IMAGE_ID"):
        value = " ".join(str(label.get(key, "") or "").split())
        if value and value.upper() not in ("N/A", "UNK", "NULL"):
            return value
    return path.stem


def _first_line(exc: BaseException) -> str:
    """A GDAL error's first line, without rasterio's pointer to "the previous exception"."""
    text = (str(exc).splitlines() or [""])[0]
    text = re.sub(r"\s*See previous exception.*$", "", text, flags=re.IGNORECASE).strip()
    cause = exc.__cause__ or exc.__context__
    if not text and cause is not None:
        return _first_line(cause)
    return text or type(exc).__name__


def _product_id(label: dict, path: Path) -> str:
    """PRODUCT_ID without a file extension some archives include (MOLA's "X.IMG").

    HRSC products keep their archive's lower-case names (h1234_0000_dt4), so the
    Extras sit beside them under the same name.
    """
    value = str(label.get("PRODUCT_ID", "") or "").strip()
    if _mission(label, path) == "hrsc":
        value = value.lower() or path.stem.lower()
    if not value or value.upper() in ("N/A", "UNK", "NULL"):
        value = path.stem
    value = re.sub(r"\.(IMG|JP2|LBL|TIF|TIFF)$", "", value, flags=re.IGNORECASE)
    if not re.fullmatch(r"[A-Za-z0-9_.\-]+", value):
        raise PdsgenError(path, f"product ID {value!r} is not usable in a file name")
    return value


def _label_nodata(image: dict, dtype: str, gdal_nodata: float | None) -> float | None:
    """The no-data DN: MISSING_CONSTANT (a float bit pattern for REAL data) or CORE_NULL."""
    for key in ("MISSING_CONSTANT", "CORE_NULL", "NULL"):
        if key in image:
            value = _number(image[key])
            if value is None:
                continue
            sample_type = str(image.get("SAMPLE_TYPE", "")).upper()
            # A REAL image's MISSING_CONSTANT is usually a based integer holding the
            # float's bit pattern (16#FF7FFFFB#); the reader hands it over as a large int.
            # Small integers (-32768, 0) are plain values.
            if (dtype.startswith("float") and isinstance(value, int)
                    and sample_type in _FLOAT_TYPES | {""} and 2**23 <= value < 2**32):
                return struct.unpack(">f", struct.pack(">I", value))[0]
            return float(value)
    return gdal_nodata


def _special_dns(image: dict) -> tuple[float, ...]:
    keys = ("CORE_LOW_REPR_SATURATION", "CORE_LOW_INSTR_SATURATION",
            "CORE_HIGH_REPR_SATURATION", "CORE_HIGH_INSTR_SATURATION")
    values = (_number(image.get(k)) for k in keys)
    return tuple(float(v) for v in values if v is not None)


def _scaling(image: dict, info: dict) -> tuple[float, float]:
    scale = _number(image.get("SCALING_FACTOR"))
    offset = _number(image.get("OFFSET"))
    return (float(scale) if scale is not None else float(info["scale"] or 1.0),
            float(offset) if offset is not None else float(info["offset"] or 0.0))


def _number(value: Any) -> int | float | None:
    value = getattr(value, "value", value)  # a Quantity (a value with a unit)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _physical(value: Any, src: ProductSource) -> float | None:
    number = _number(value)
    return None if number is None else number * src.scale + src.offset


def _same_nodata(a: float | None, b: float | None) -> bool:
    if a is None or b is None:
        return a is b
    if math.isnan(a) and math.isnan(b):
        return True
    return a == b or math.isclose(a, b, rel_tol=1e-7)
