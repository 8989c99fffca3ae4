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

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from rasterio.io import DatasetReader

from .. import __version__
from ..errors import PdsgenError
from ..geometry import MapGeometry
from ..params import ParamValue
from ..write_image import MISSING_CONSTANT, BandStatistics, stream_float32_band
from .content import ArrayStatistics, ContentTap, FileContent, digest_file
from .context import logical_identifier, observation
from .label import cartography, render_pds4
from .model import DATA_TYPES

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
    profile: str
    version: str
    keywords: Mapping[str, ParamValue]
    geometry: MapGeometry
    dataset: DatasetReader

    def target(self) -> str | None:
        return self.geometry.target_name or str(self.keywords.get("TARGET_NAME", "MARS"))


def write_dtm_data(dataset: DatasetReader, out: BinaryIO, big_endian: bool
                   ) -> tuple[BandStatistics, ArrayStatistics, FileContent]:
    """Stream the DTM samples into `out`, taking MD5, size and Object_Statistics in the same pass."""
    tap = ContentTap(out, (">" if big_endian else "<") + "f4", missing=float(MISSING_CONSTANT))
    stats = stream_float32_band(dataset, tap, big_endian=big_endian)
    if stats.valid_count == 0:
        raise PdsgenError(dataset.name, "has no valid pixels (all nodata)")
    return stats, tap.statistics(), tap.content()


def dtm_label_text(product: ProductDescription, data_name: str, big_endian: bool, statistics: ArrayStatistics,
                   content: FileContent, header_bytes: int = 0) -> str:
    """The PDS4 label of a float32 DTM stored in `data_name` (after `header_bytes` of PDS3 label)."""
    array = {
        "local_identifier": ARRAY_ID,
        "offset": header_bytes,
        "description": "Elevations in metres; samples equal to missing_constant hold no data.",
        "data_type": DATA_TYPES[("f4", big_endian)],
        "unit": "m",
        "scaling_factor": None,
        "lines": product.geometry.lines,
        "samples": product.geometry.samples,
        "special": [("missing_constant", float(MISSING_CONSTANT))],
        "statistics": statistics,
    }
    return render_pds4("dtm.xml.j2", {
        **_common(product, "data_dtm", "digital terrain model"),
        "data_file": _file_entry(data_name, content),
        "array": array,
        "pds3_header": header_bytes,
    })


def write_dtm_pds4_label(product: ProductDescription, label_path: Path, data_path: Path, data_name: str,
                         big_endian: bool, header_bytes: int = 0) -> Pds4Label:
    """Describe an already written DTM file (PDS3 `.IMG` with attached label, or raw) in a PDS4 label.

    Reads the file once for its MD5 and statistics: it was written before this label.
    """
    dtype = (">" if big_endian else "<") + "f4"
    with open(data_path, "rb") as handle, open(Path("/dev/null"), "wb") as sink:
        tap = ContentTap(sink, dtype, missing=float(MISSING_CONSTANT), start=header_bytes)
        while block := handle.read(_READ_CHUNK - _READ_CHUNK % 4):
            tap.write(block)
    text = dtm_label_text(product, data_name, big_endian, tap.statistics(), tap.content(), header_bytes)
    label_path.write_text(text, encoding="utf-8")
    return Pds4Label(label_path, text, tap.statistics(), tap.content())


def _common(product: ProductDescription, collection: str, kind: str) -> dict[str, object]:
    geometry, dataset = product.geometry, product.dataset
    target = product.target()
    summary = f"{kind.capitalize()} {product.product_id}, written by pdsgen {__version__}."
    obs = observation(product.profile, target, summary, product.keywords)
    return {
        "ident": {
            "lid": logical_identifier(product.profile, collection, product.product_id),
            "version_id": product.version,
            "title": f"{product.product_id}: {kind} of {obs['target_name']}",
        },
        "obs": obs,
        "cart": cartography(geometry, dataset.crs, dataset.transform, str(obs["target_name"])),
        "array_id": ARRAY_ID,
    }


def _file_entry(name: str, content: FileContent) -> dict[str, object]:
    return {"name": name, "local_identifier": "data_file", "size": content.size, "md5": content.md5}


def write_dtm_pds4(
    input_path: str | Path,
    outdir: str | Path,
    *,
    profile: str = "generic",
    product_id: str | None = None,
    byte_order: str = "lsb",
    version: str = "1.0",
    overwrite: bool = False,
) -> Pds4Label:
    """A DTM as a PDS4 product only: `<id>.img` + `<id>.xml` in OUTDIR."""
    from ..dtm import BYTE_ORDERS
    from ..geometry import describe_geometry
    from ..profiles import check_product_id, generic_product_id
    from ..read_raster import open_raster, require_single_band
    from ..staging import StagedOutputs, prepare_output_dir

    if byte_order not in BYTE_ORDERS:
        raise PdsgenError(None, f"byte order must be one of {', '.join(BYTE_ORDERS)}")
    input_path = Path(input_path)
    product_id = check_product_id(product_id) if product_id else generic_product_id(input_path.stem)
    big_endian = byte_order == "msb"
    with open_raster(input_path) as dataset:
        require_single_band(dataset)
        geometry = describe_geometry(dataset.crs, dataset.transform, dataset.width, dataset.height,
                                     str(input_path))
        product = ProductDescription(product_id, profile, version, {}, geometry, dataset)
        outdir = prepare_output_dir(outdir)
        data_final, label_final = outdir / f"{product_id.lower()}.img", outdir / f"{product_id.lower()}.xml"
        with StagedOutputs([data_final, label_final], overwrite) as staged:
            with open(staged.path(data_final), "wb") as handle:
                _, statistics, content = write_dtm_data(dataset, handle, big_endian)
            text = dtm_label_text(product, data_final.name, big_endian, statistics, content)
            staged.path(label_final).write_text(text, encoding="utf-8")
    return Pds4Label(label_final, text, statistics, content)
