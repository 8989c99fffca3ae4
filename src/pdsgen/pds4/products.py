"""PDS4 forms of the DTM and orthoimage products, over the same data writers as PDS3.

DTM: `<id>.img` (float32, the PDS3 writer's strip streaming through a ContentTap
that takes the MD5 and statistics on the way) + `<id>.xml`. With a PDS3 product
already written (`--label both`) the PDS4 label describes that `.IMG` instead:
a `Header` for the attached PDS3 label and the array at its byte offset.

Orthoimage: PDS4 takes no JPEG 2000 as primary data, so the primary is an
uncompressed array (`<id>.img`, the same DNs as the JP2) and the lossless JP2
goes in a File_Area_Observational_Supplemental as an Encoded_Image.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, cast

import numpy as np
from rasterio.io import DatasetReader

from .. import __version__
from ..errors import PdsgenError
from ..formats.img import MISSING_CONSTANT, BandStatistics, stream_float32_band
from ..formats.scale_dn import SpecialDns
from ..geo.geometry import MapGeometry
from ..missions import Mission
from ..params import ParamValue
from .content import ArrayStatistics, ContentTap, FileContent
from .context import logical_identifier, observation, source_products
from .label import cartography, render_pds4
from .model import DATA_TYPES, NUMPY_TYPES

ARRAY_ID = "image"
_READ_CHUNK = 8 * 1024 * 1024


@dataclass(frozen=True)
class Pds4Label:
    """A written PDS4 label and what it states about its data file."""

    path: Path
    text: str
    statistics: ArrayStatistics
    content: FileContent


@dataclass(frozen=True)
class ProductDescription:
    """Everything a label needs besides the data: names, keywords, geometry."""

    product_id: str
    mission: Mission
    version: str
    keywords: Mapping[str, ParamValue]
    geometry: MapGeometry
    dataset: DatasetReader
    sources: Sequence[str] = ()  # SOURCE_PRODUCT_ID of the PDS3 label (of the same product)

    def target(self) -> str | None:
        return self.geometry.target_name or str(self.keywords.get("TARGET_NAME", "")) or None


@dataclass(frozen=True)
class StoredArray:
    """How an image's samples are stored: what Element_Array and Special_Constants state,
    and what the product is (its LID collection and the kind of product in its title)."""

    data_type: str  # PDS4 data_type, e.g. IEEE754LSBSingle
    special: tuple[tuple[str, float], ...]  # Special_Constants, in the schema's order
    description: str
    unit: str | None = "m"
    scaling: tuple[float, float] | None = None  # (scaling_factor, value_offset) of integer DNs
    collection: str = "data_dtm"
    kind: str = "digital terrain model"

    @property
    def numpy_type(self) -> str:
        return NUMPY_TYPES[self.data_type]


@dataclass(frozen=True)
class FileHeader:
    """A header before the array in the same file: an attached PDS3 label, a VICAR label.

    The label lists them as Header objects in file order; the array starts after them.
    """

    local_identifier: str
    length: int  # bytes
    parsing_standard_id: str  # a value the PDS4 dictionary allows: "PDS3", "VICAR2" ...
    description: str


def pds3_label_header(length: int) -> FileHeader:
    return FileHeader("pds3_label", length, "PDS3", "The attached PDS3 label of the same product.")


def header_entries(headers: Sequence[FileHeader]) -> tuple[list[dict[str, object]], int]:
    """The Header objects with their offsets, and the offset of the array after them."""
    entries, offset = [], 0
    for header in headers:
        entries.append({"local_identifier": header.local_identifier, "offset": offset, "length": header.length,
                        "parsing_standard_id": header.parsing_standard_id, "description": header.description})
        offset += header.length
    return entries, offset


def float32_dtm(big_endian: bool) -> StoredArray:
    """The standard DTM: float32 elevations, the ISIS NULL as missing_constant."""
    return StoredArray(DATA_TYPES[("f4", big_endian)], (("missing_constant", float(MISSING_CONSTANT)),),
                       "Elevations in metres; samples equal to missing_constant hold no data.")


def write_pds4_dtm(product: ProductDescription, data_path: Path, label_path: Path, data_name: str,
                   big_endian: bool) -> tuple[BandStatistics, Pds4Label]:
    """A float32 DTM as `data_path` (raw samples) + its PDS4 label, in one pass over the input:
    the PDS3 writer's strip streaming, through a ContentTap taking MD5, size and statistics."""
    stored = float32_dtm(big_endian)
    with open(data_path, "wb") as out:
        tap = ContentTap(out, stored.numpy_type, special=tuple(v for _, v in stored.special))
        stats = stream_float32_band(product.dataset, cast(BinaryIO, tap), big_endian)  # it only calls write()
    if stats.valid_count == 0:
        raise PdsgenError(product.dataset.name, "has no valid pixels (all nodata)")
    text = image_label_text(product, data_name, stored, tap.statistics(), tap.content())
    label_path.write_text(text, encoding="utf-8")
    return stats, Pds4Label(label_path, text, tap.statistics(), tap.content())


def image_label_text(product: ProductDescription, data_name: str, stored: StoredArray, statistics: ArrayStatistics,
                     content: FileContent, headers: Sequence[FileHeader] = ()) -> str:
    """The PDS4 label of a one-band image (a DTM, or HRSC's ND4) stored in `data_name`,
    after the `headers` the file holds before it (an attached PDS3 label, a VICAR label)."""
    entries, array_offset = header_entries(headers)
    array = {
        "element": "Array_2D_Image",
        "bands": None,
        "local_identifier": ARRAY_ID,
        "offset": array_offset,
        "description": stored.description,
        "data_type": stored.data_type,
        "unit": stored.unit,
        "scaling_factor": stored.scaling[0] if stored.scaling else None,
        "value_offset": stored.scaling[1] if stored.scaling else None,
        "lines": product.geometry.lines,
        "samples": product.geometry.samples,
        "special": stored.special,
        "statistics": statistics,
    }
    return render_pds4("dtm.xml.j2", {
        **_common(product, stored.collection, stored.kind),
        "data_file": _file_entry(data_name, content),
        "array": array,
        "headers": entries,
    })


def write_image_pds4_label(product: ProductDescription, label_path: Path, data_path: Path, data_name: str,
                           stored: StoredArray, headers: Sequence[FileHeader] = ()) -> Pds4Label:
    """Describe an already written image file (PDS3 `.IMG` with attached label, HRSC's
    PDS3 + VICAR headed `.img`, or raw) in a PDS4 label.

    Reads the file once for its MD5 and statistics: it was written before this label.
    """
    itemsize = np.dtype(stored.numpy_type).itemsize
    _, array_offset = header_entries(headers)
    with open(data_path, "rb") as handle:
        tap = ContentTap(None, stored.numpy_type, special=tuple(v for _, v in stored.special), start=array_offset)
        while block := handle.read(_READ_CHUNK - _READ_CHUNK % itemsize):
            tap.write(block)
    text = image_label_text(product, data_name, stored, tap.statistics(), tap.content(), headers)
    label_path.write_text(text, encoding="utf-8")
    return Pds4Label(label_path, text, tap.statistics(), tap.content())


def _common(product: ProductDescription, collection: str, kind: str) -> dict[str, object]:
    geometry, dataset = product.geometry, product.dataset
    target = product.target()
    summary = f"{kind.capitalize()} {product.product_id}, written by pdsgen {__version__}."
    obs = observation(product.mission, target, summary, product.keywords)
    return {
        "ident": {
            "lid": logical_identifier(product.mission, collection, product.product_id),
            "version_id": product.version,
            "title": f"{product.product_id}: {kind} of {obs['target_name']}",
        },
        "obs": obs,
        "sources": source_products(product.sources, product.mission.pds4.curating_facility),
        "cart": cartography(geometry, dataset.crs, dataset.transform, str(obs["target_name"])),
        "array_id": ARRAY_ID,
    }


def _file_entry(name: str, content: FileContent) -> dict[str, object]:
    return {"name": name, "local_identifier": "data_file", "size": content.size, "md5": content.md5}



class ArrayRowTap:
    """Wraps the JP2 writer's tile-row reader: every row of DNs it hands out is also
    written to the uncompressed primary array (several bands interleaved by pixel, as
    the JP2 encoder takes them: axes Line, Sample, Band)."""

    def __init__(self, reader: Callable[[int, int], np.ndarray], out: BinaryIO, special: SpecialDns) -> None:
        self._reader = reader
        self.stored = np.dtype(np.uint8) if special.bits <= 8 else np.dtype(">u2")
        self.special = special_constants(special)
        self.tap = ContentTap(out, self.stored.str, special=tuple(v for _, v in self.special
                                                                 if _ in _EXCLUDED_FROM_STATISTICS))

    def __call__(self, first_line: int, lines: int) -> np.ndarray:
        rows = self._reader(first_line, lines)  # (lines, samples) or (lines, samples, bands)
        self.tap.write(np.ascontiguousarray(rows.astype(self.stored, copy=False)))
        return rows


# Special DNs that are not data: left out of Object_Statistics, as the validator does.
_EXCLUDED_FROM_STATISTICS = ("missing_constant", "high_instrument_saturation", "high_representation_saturation",
                             "low_instrument_saturation", "low_representation_saturation")


def special_constants(special: SpecialDns) -> list[tuple[str, int]]:
    """Special_Constants of an orthoimage, in the schema's order; a saturation DN that is
    also a valid DN (8-bit low saturation = 1) is not declared, so no valid pixel is hidden."""
    entries = [("missing_constant", special.null), ("valid_maximum", special.valid_max),
               ("high_instrument_saturation", special.high_instr),
               ("high_representation_saturation", special.high_repr), ("valid_minimum", special.valid_min),
               ("low_instrument_saturation", special.low_instr),
               ("low_representation_saturation", special.low_repr)]
    valid = range(special.valid_min, special.valid_max + 1)
    seen: set[int] = set()
    kept = []
    for name, value in entries:
        if name in _EXCLUDED_FROM_STATISTICS and (value in valid or value in seen):
            continue
        seen.add(value)
        kept.append((name, value))
    return kept


def ortho_label_text(product: ProductDescription, data_name: str, tap: ArrayRowTap, jp2_name: str,
                     jp2: FileContent, scaling_factor: float, offset: float) -> str:
    """The PDS4 label of an orthoimage: uncompressed DNs primary, the JP2 supplemental."""
    identity = scaling_factor == 1.0 and offset == 0.0
    bands = product.dataset.count
    array = {
        "element": "Array_2D_Image" if bands == 1 else "Array_3D_Image",
        "bands": None if bands == 1 else bands,
        "local_identifier": ARRAY_ID,
        "offset": 0,
        "description": "Orthoimage DNs" + ("" if identity else "; I/F = DN * scaling_factor + value_offset") + ".",
        "data_type": DATA_TYPES[(tap.stored.kind + str(tap.stored.itemsize), tap.stored.itemsize > 1)],
        "unit": None,
        "scaling_factor": None if identity else scaling_factor,
        "value_offset": offset,
        "lines": product.geometry.lines,
        "samples": product.geometry.samples,
        "special": tap.special,
        "statistics": tap.tap.statistics() if tap.tap.count else None,
    }
    return render_pds4("ortho.xml.j2", {
        **_common(product, "data_ortho", "orthoimage"),
        "data_file": _file_entry(data_name, tap.tap.content()),
        "jp2_file": {**_file_entry(jp2_name, jp2), "local_identifier": "jp2_file"},
        "array": array,
    })
