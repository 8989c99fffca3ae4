"""The iMars delivery form of HRSC-derived DTMs: GeoTIFF + PVL metadata + footprint.

iMars (the EU FP7 project that processed HRSC south-polar and regional DTMs at UCL)
delivered each product as a GeoTIFF (int16 DTM with nodata -32768, byte ORI with
nodata 0) carrying its processing metadata in GeoTIFF tags, a PVL metadata file
`<ID>_<type>4_ucl.pvl` (objects ProductInfo with group Producer, Image,
DataProduct, MapProjection, Algorithm), and a GIS footprint `<ID>.geojson`.
"""

from __future__ import annotations

import datetime as dt
import math
import os
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import pvl
import rasterio
from rasterio.env import get_gdal_config
from rasterio.windows import Window

from .. import __version__, clock
from ..encode import check_pvl_keyword, check_pvl_string
from ..errors import PdsgenError
from ..formats.footprint import footprint_wkt, valid_data_outline, write_footprints, write_shapefile
from ..formats.img import (
    Adjust,
    BandStatistics,
    Encode,
    band_statistics,
    native_strips,
    physical_strips,
    physical_values,
    valid_extremes,
)
from ..formats.nodata import invalid_mask
from ..formats.scale_dn import SPECIAL_DNS, dn_encoder, null_zero_byte_mapping
from ..geo.geometry import MapGeometry
from ..missions import hrsc as hrsc_mission
from ..missions import imars as imars_mission
from ..missions.hrsc import MISSING_DN
from ..missions.hrsc import base_name as hrsc_base_name
from ..params import check_version, resolve_params, source_ids
from .dispatch import NO_STATEMENT, ProductStatement
from .int16_heights import Int16Encoding, areoid_adjustment, check_datum_conversion, choose_encoding
from .opening import Opening, open_product_input, require_valid, single_band
from .options import ProductOptions
from .result import ProductResult

IMARS_INSTITUTION = imars_mission.INSTITUTION
_DTM_DESCRIPTIONS = imars_mission.DTM_DESCRIPTIONS
ORI_OPENING = Opening(check=single_band("an iMars orthoimage"))


@dataclass(frozen=True)
class ImarsProduct(ProductResult):
    """What an iMars writer produced: the GeoTIFF, its PVL metadata and the footprint."""

    label_checked: ClassVar[bool] = False  # PVL metadata and GeoTIFF tags: no PDS3 label to check

    product_id: str
    tiff_path: Path
    pvl_path: Path
    footprint_path: Path
    geometry: MapGeometry
    encoding: Int16Encoding
    valid_minimum: int
    valid_maximum: int
    shapefile_paths: tuple[Path, ...] = ()  # the footprint as .shp .shx .dbf .prj .qpj
    warnings: tuple[str, ...] = ()  # none: nothing is checked against the PDS3 dictionary

    @property
    def files(self) -> tuple[Path, ...]:
        """Every file this product wrote."""
        return (self.tiff_path, self.pvl_path, self.footprint_path, *self.shapefile_paths)

    @property
    def summary_facts(self) -> tuple[str, ...]:
        return (f"DN {self.valid_minimum} .. {self.valid_maximum}",)


# A footprint feature: (product ID, lon/lat polygons, properties).
Feature = tuple[str, list[dict[str, Any]], dict[str, Any]]


@dataclass(frozen=True)
class ImarsMosaic:
    """How a mosaic of strips differs from a strip: `<ID>_dtm.tif` / `<ID>_ori.tif`, the
    number of sources in the PVL (how they were put together is the writer's `statement`),
    and a footprint whose features are the source strips (each outlining its own valid data,
    with its own product ID). `heights_within`: bounds of every valid height the sources' sample
    type and scaling can present (None: not known), which may decide the 16-bit encoding
    without a statistics pass (_known_encoding). The features are first asked for after the
    GeoTIFF is written, so a sequence that traces them then keeps them out of its memory."""

    product_id: str
    features: Sequence[Feature]
    heights_within: tuple[float, float] | None = None

    def stem(self, product_type: str) -> str:
        return imars_mission.mosaic_stem(self.product_id, product_type)


def _pvl_mosaic(mosaic: ImarsMosaic | None, statement: ProductStatement) -> dict[str, Any]:
    """The Image keywords that say a product is a mosaic, of what and how it was put together."""
    if mosaic is None:
        return {}
    return {imars_mission.MOSAIC_KEYWORD: len(mosaic.features), "MosaicMethod": statement.mosaic}


def _footprint_features(mosaic: ImarsMosaic | None, product_id: str, polygons, properties) -> list[Feature]:
    """The strip's own outline, or the mosaic's sources' outlines."""
    if mosaic is None:
        return [(product_id, polygons(), properties)]
    return [(fid, outline, {**extra, **{k: v for k, v in properties.items() if k == "type"}})
            for fid, outline, extra in mosaic.features]


def write_imars_dtm(
    input_path: str | os.PathLike[str],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
    *,
    mosaic: ImarsMosaic | None = None,
    statement: ProductStatement = NO_STATEMENT,
) -> ImarsProduct:
    """Write `<ID>_<kind>4_ucl.tif` (int16), its `.pvl` and the scene footprint
    (a mosaic: `<ID>_dtm.tif`, its `.pvl` and its sources' footprints; `statement`: how
    they were put together).

    `vertical_datum` says what the input heights are measured from (default: the
    datum of `kind`); when it differs from the kind's, `areoid` converts, as for HRSC.
    """
    product_id, source_product_ids, kind, vertical_datum = (options.product_id, options.source_product_ids,
                                                            options.kind, options.vertical_datum)
    areoid, precision, params, version, overwrite = (options.areoid, options.precision, options.params,
                                                     options.version, options.overwrite)
    kind = kind[:2] if kind in ("dt4", "da4") else kind  # the CLI's --kind dt4/da4 names them too
    version = check_version(version)
    output_datum = "areoid" if kind == "da" else "sphere"
    check_datum_conversion(f"{kind}4", output_datum, vertical_datum or output_datum, areoid)
    keywords = resolve_params(params)
    sources = source_ids(source_product_ids, keywords)
    if mosaic is None:
        base, _ = hrsc_base_name(product_id, sources)
        stem, ident = imars_mission.product_stem(base, kind), f"{base}_{kind}4"
    else:
        base, stem = mosaic.product_id, mosaic.stem("DTM")
        ident = stem
    input_path = Path(input_path)
    with open_product_input(input_path) as opened:
        dataset, geometry = opened.dataset, opened.geometry
        adjust = None
        if vertical_datum is not None and vertical_datum != output_datum:
            adjust = areoid_adjustment(areoid, dataset, +1.0 if output_datum == "sphere" else -1.0)
        known = _known_encoding(mosaic, precision, adjust)
        encoding = known or choose_encoding(opened.scan(adjust), precision, str(input_path))
        existed = Path(outdir).is_dir()
        out = opened.output_dir(outdir)
        tiff, metadata = out / f"{stem}.tif", out / imars_mission.metadata_name(ident)
        facts = imars_facts(ident, "DTM", keywords, geometry.target_name or "MARS")

        def tags(encoding: Int16Encoding) -> dict[str, str]:
            return _processing_tags(ident, _DTM_DESCRIPTIONS[kind], encoding.scaling_factor,
                                    encoding.offset, MISSING_DN, keywords, sources, facts)

        def choose(stats: BandStatistics) -> Int16Encoding:  # as the statistics pass chooses
            return choose_encoding(require_valid(stats, input_path), precision, str(input_path))

        footprint = out / imars_mission.footprint_name(base)
        shapes = {part: out / name for part, name in imars_mission.footprint_shapefile_names(base).items()}
        with _no_directory_if_refused(out, existed or known is None), \
                opened.stage([tiff, metadata], overwrite, shared=[footprint, *shapes.values()]) as staged:
            encoding, low, high = _write_heights(dataset, staged.path(tiff), encoding, tags, adjust,
                                                 choose if known else None)
            with rasterio.open(staged.path(tiff)) as written:
                written_crs = written.crs
                text = imars_pvl_text(written, tiff.name, ident, "DTM", geometry, keywords, sources,
                                      version, {"ValidMinimum": low, "ValidMaximum": high,
                                                "HeightReference": _DTM_DESCRIPTIONS[kind],
                                                "Precision": pvl.Quantity(encoding.scaling_factor, "m"),
                                                **_pvl_mosaic(mosaic, statement)},
                                      facts)
                features = _footprint_features(
                    mosaic, ident, lambda: valid_data_outline(written, lambda a: a != MISSING_DN),
                    {"type": "DTM", "file": tiff.name})
            staged.path(metadata).write_text(text)
            collection = write_footprints(footprint, staged.path(footprint), features,
                                          geometry.target_name or "MARS")
            write_shapefile(collection, {part: staged.path(path) for part, path in shapes.items()},
                            footprint_wkt(written_crs), dt.date.fromisoformat(facts["date"]))
    return ImarsProduct(ident, tiff, metadata, footprint, geometry, encoding, low, high,
                        tuple(shapes.values()))


# Checked by the tests that write a mosaic both ways; False: every mosaic takes the statistics pass.
TRUST_SOURCE_RANGE = True


def _known_encoding(mosaic: ImarsMosaic | None, precision: float, adjust: Adjust | None) -> Int16Encoding | None:
    """The encoding the statistics pass would choose, when the sources already decide it (None: not known).

    choose_encoding takes offset 0 whenever every valid height fits 16 bits at `precision` from
    0; when the bounds of what the sources can hold (their sample type and scaling: strips of
    one release) fit so, every height they hold does, and the pass can only choose that. Its
    refusals (no valid heights, too coarse a precision) are judged after the write on the same
    statistics, gathered as it writes (_write_heights). Heights changed on the way (`adjust`:
    a datum conversion) are not bounded by the sources'."""
    if mosaic is None or mosaic.heights_within is None or adjust is not None or not TRUST_SOURCE_RANGE:
        return None
    low, high = mosaic.heights_within
    try:
        guess = choose_encoding(BandStatistics(2, low, high), precision, "")
    except PdsgenError:  # a precision the pass refuses, or bounds that do not fit: the pass says why
        return None
    return guess if guess.offset == 0.0 else None


class _GatheringEncoder:
    """An encoder that gathers, as it encodes, the statistics scan_band would give of the same
    physical values: the write is then the statistics pass too."""

    def __init__(self, encode: Encode) -> None:
        self._encode = encode
        self._count, self._low, self._high = 0, math.inf, -math.inf

    def __call__(self, values: np.ndarray, invalid: np.ndarray | None) -> np.ndarray:
        self.add(*valid_extremes(values, invalid))
        return self._encode(values, invalid)

    def add(self, count: int, low: float, high: float) -> None:
        """Count and extremes of more valid values (_KeptDns: the samples' own)."""
        self._count, self._low, self._high = self._count + count, min(self._low, low), max(self._high, high)

    def statistics(self) -> BandStatistics:
        return band_statistics(self._count, self._low, self._high)


# The encoding of heights stored as they are read: DN = rint((height - 0) / 1) = height.
SAME_DNS = Int16Encoding(1.0, 0.0)


class _KeptDns:
    """The encoding SAME_DNS of int16 samples: rint((float32(DN) - 0) / 1) is DN, so the stored
    samples are the samples read with no-data set to MISSING_DN (`keep`), without float32 values
    or their temporaries; the heights' statistics are the stored DNs', exactly (`gathering`). As
    an encoder of float32 values (with an `adjust`) it is SAME_DNS's own."""

    def __init__(self, gathering: _GatheringEncoder | None) -> None:
        self.gathering = gathering

    def __call__(self, values: np.ndarray, invalid: np.ndarray | None) -> np.ndarray:
        return self.gathering(values, invalid) if self.gathering else SAME_DNS.encode(values, invalid)

    @staticmethod
    def keep(native: np.ndarray, invalid: np.ndarray | None, stored: np.ndarray) -> None:
        np.copyto(stored, native)
        if invalid is not None:
            np.copyto(stored, MISSING_DN, where=invalid)


def _write_heights(dataset, path: Path, encoding: Int16Encoding, tags: Callable[[Int16Encoding], dict[str, str]],
                   adjust: Adjust | None, verify: Callable[[BandStatistics], Int16Encoding] | None,
                   ) -> tuple[Int16Encoding, int, int]:
    """Write the heights with `encoding`; return it with the valid DN range.

    `verify`: the encoding was known without a statistics pass, so the write gathers the
    statistics the pass would have given and chooses from them as it does - raising its
    refusals, and writing again should it choose another encoding (which _known_encoding rules
    out), so the file is always the one the pass would have made."""
    gathering = _GatheringEncoder(encoding.encode) if verify else None
    encode: Encode = gathering or encoding.encode
    if encoding == SAME_DNS and np.dtype(dataset.dtypes[0]) == np.int16:
        encode = _KeptDns(gathering)
    low, high = _write_geotiff(dataset, path, "int16", MISSING_DN, encode, encoding.scaling_factor,
                               encoding.offset, tags(encoding), adjust)
    if verify is None or gathering is None:
        return encoding, low, high
    chosen = verify(gathering.statistics())
    if chosen == encoding:
        return encoding, low, high
    return _write_heights(dataset, path, chosen, tags, adjust, None)


@contextmanager
def _no_directory_if_refused(out: Path, keep: bool) -> Iterator[None]:
    """OUTDIR made for a product refused after it was opened (a refusal judged during the write)
    is removed again when empty, as if the refusal had come first (`keep`: it existed, or any
    refusal did come first)."""
    try:
        yield
    except PdsgenError:
        if not keep and out.is_dir() and not any(out.iterdir()):
            out.rmdir()
        raise


def _compression_threads() -> str:
    """Threads GDAL compresses the GeoTIFF's blocks on: GDAL_NUM_THREADS when configured (a batch
    job's share of the machine), else every core. GDAL writes the blocks in order whatever the
    count, so the file's bytes do not depend on it."""
    return str(get_gdal_config("GDAL_NUM_THREADS", normalize=False) or "ALL_CPUS")


def _write_geotiff(dataset, path: Path, dtype: str, nodata: int, encode, scale: float, offset: float,
                   tags: dict[str, str], adjust: Adjust | None = None) -> tuple[int, int]:
    """Stream encoded samples into a tiled, compressed GeoTIFF; return the valid DN range."""
    profile = {
        "driver": "GTiff", "width": dataset.width, "height": dataset.height, "count": 1, "dtype": dtype,
        "crs": dataset.crs, "transform": dataset.transform, "nodata": nodata, "tiled": True,
        "blockxsize": 256, "blockysize": 256, "compress": "deflate", "predictor": 2, "BIGTIFF": "IF_SAFER",
        "NUM_THREADS": _compression_threads(),
    }
    low, high = np.iinfo(dtype).max, np.iinfo(dtype).min
    with rasterio.open(path, "w", **profile) as out:
        out.scales = (scale,)
        out.offsets = (offset,)
        out.update_tags(**tags)
        for stored, count, lo, hi, window in _encoded_strips(dataset, dtype, encode, adjust):
            if count:
                low, high = min(low, int(lo)), max(high, int(hi))
            out.write(stored, 1, window=window)
    return low, high


# Pixels of a strip converted and encoded at a time (whole lines): 4 MB of float32 values and a few
# temporaries of that size, whatever the width, instead of several times the strip. Measured on a
# mosaic 17,800 wide: peak 168 MB; 2**18 gave 174-184 MB (more small blocks kept by the allocator).
PART_PIXELS = 2**20


def _encoded_strips(dataset, dtype: str, encode: Encode, adjust: Adjust | None,
                    ) -> Iterator[tuple[np.ndarray, int, float, float, Window]]:
    """Each strip physical_strips reads, encoded, with the count and extremes of its valid samples.

    Without `adjust`, a strip is converted and encoded a part of its lines at a time into one
    array of stored samples: every conversion and encoding is pixel by pixel, so the samples
    are the same, and GDAL reads and writes the same strips (the file's bytes depend on
    that), while the float32 values, masks and temporaries of a whole strip - most of the
    writer's memory - are never held at once. An `adjust` (areoid resampled onto the strip)
    takes the whole strip, as GDAL's warp of a part may differ."""
    if adjust is not None:
        for values, invalid, window in physical_strips(dataset, adjust):
            stored = encode(values, invalid)
            yield (stored, *valid_extremes(stored, invalid), window)
        return
    buffer: np.ndarray | None = None  # the stored samples of every strip, as native_strips' `reuse`
    for native, window in native_strips(dataset, reuse=True):
        if buffer is None:
            buffer = np.empty(native.shape, dtype)
        stored = buffer[:native.shape[0]]
        count, low, high = 0, math.inf, -math.inf
        step = max(1, PART_PIXELS // max(1, native.shape[1]))
        for row in range(0, native.shape[0], step):
            part = stored[row:row + step]
            if isinstance(encode, _KeptDns):
                invalid = invalid_mask(native[row:row + step], dataset.nodata)  # as physical_values
                encode.keep(native[row:row + step], invalid, part)
            else:
                values, invalid = physical_values(dataset, native[row:row + step])
                part[...] = encode(values, invalid)
            n, lo, hi = valid_extremes(part, invalid)
            count, low, high = count + n, min(low, lo), max(high, hi)
            if isinstance(encode, _KeptDns) and encode.gathering:
                encode.gathering.add(n, lo, hi)
        yield stored, count, low, high, window  # written before the next strip is asked for


def _processing_tags(product: str, description: str, scale: float, offset: float, missing: int, keywords,
                     sources, facts: Mapping[str, str]) -> dict[str, str]:
    return {
        **fact_tags(facts),
        "TIFFTAG_SOFTWARE": f"pdsgen {__version__}",
        "TIFFTAG_IMAGEDESCRIPTION": f"{product} iMars HRSC {description}, value = DN * {scale:g} + {offset:g}",
        "PRODUCT_ID": product,
        "DESCRIPTION": description,
        "SCALING_FACTOR": repr(scale),
        "OFFSET": repr(offset),
        "MISSING_DN": str(missing),
        "PRODUCER": str(keywords.get("PRODUCER_INSTITUTION_NAME", IMARS_INSTITUTION)),
        "SOURCE_PRODUCT_ID": ",".join(sources) or "N/A",
        "ALGORITHM": str(keywords.get("EXTRACTION_METHOD", "UNK")),
    }


def write_imars_ori(
    input_path: str | os.PathLike[str],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
    *,
    mosaic: ImarsMosaic | None = None,
    statement: ProductStatement = NO_STATEMENT,
) -> ImarsProduct:
    """Write the orthoimage `<ID>_nd4_ucl.tif` (byte, nodata 0), its `.pvl` and the scene footprint
    (a mosaic: `<ID>_ori.tif`, its `.pvl` and its sources' footprints; `statement`: how they
    were put together)."""
    product_id, source_product_ids, value_range, overwrite = (options.product_id, options.source_product_ids,
                                                              options.value_range, options.overwrite)
    version = check_version(options.version)
    keywords = resolve_params(options.params)
    sources = source_ids(source_product_ids, keywords)
    if mosaic is None:
        base, _ = hrsc_base_name(product_id, sources)
        stem, ident = imars_mission.product_stem(base, "nd"), f"{base}_nd4"
    else:
        base, stem = mosaic.product_id, mosaic.stem("ORI")
        ident = stem
    input_path = Path(input_path)
    special = SPECIAL_DNS[8]
    with open_product_input(input_path, ORI_OPENING) as opened:
        dataset, geometry = opened.dataset, opened.geometry
        mapping = null_zero_byte_mapping(dataset, value_range, str(input_path))

        encode = dn_encoder(mapping, str(input_path))
        out = opened.output_dir(outdir)
        tiff, metadata = out / f"{stem}.tif", out / imars_mission.metadata_name(ident)
        facts = imars_facts(ident, "ORI", keywords, geometry.target_name or "MARS")
        tags = _processing_tags(ident, "ORTHOIMAGE", mapping.scaling_factor, mapping.offset,
                                special.null, keywords, sources, facts)
        footprint = out / imars_mission.footprint_name(base)
        shapes = {part: out / name for part, name in imars_mission.footprint_shapefile_names(base).items()}
        with opened.stage([tiff, metadata], overwrite, shared=[footprint, *shapes.values()]) as staged:
            low, high = _write_geotiff(dataset, staged.path(tiff), "uint8", special.null, encode,
                                       mapping.scaling_factor, mapping.offset, tags)
            with rasterio.open(staged.path(tiff)) as written:
                written_crs = written.crs
                text = imars_pvl_text(written, tiff.name, ident, "ORI", geometry, keywords, sources,
                                      version, {"ValidMinimum": low, "ValidMaximum": high,
                                                **_pvl_mosaic(mosaic, statement)},
                                      facts)
                features = _footprint_features(
                    mosaic, ident, lambda: valid_data_outline(written, lambda a: a != special.null),
                    {"type": "ORI", "file": tiff.name})
            staged.path(metadata).write_text(text)
            collection = write_footprints(footprint, staged.path(footprint), features,
                                          geometry.target_name or "MARS")
            write_shapefile(collection, {part: staged.path(path) for part, path in shapes.items()},
                            footprint_wkt(written_crs), dt.date.fromisoformat(facts["date"]))
    encoding = Int16Encoding(mapping.scaling_factor, mapping.offset)
    return ImarsProduct(ident, tiff, metadata, footprint, geometry, encoding, low, high,
                        tuple(shapes.values()))


def processing_date() -> str:
    """The day of making (pdsgen.clock: SOURCE_DATE_EPOCH's day when set, else today, UTC): the
    ProcessingDate of the .pvl and GeoTIFF tags, and the footprint .dbf's date of last update."""
    return clock.today()


# The facts the real iMars files give twice: PVL (object, keyword) and GeoTIFF metadata tag.
# One table; the tags are derived from it, so the two cannot drift apart.
FACT_PLACES = {
    "software_name": ("Producer", "SoftwareName", "PRODUCER.SOFTWARE_NAME"),
    "software_version": ("Producer", "SoftwareVersion", "PRODUCER.SOFTWARE_VERSION"),
    "institution": ("Producer", "ProducerInstitutionName", "PRODUCER.INSTITUTION_NAME"),
    "organisation": ("Producer", "ProcessingOrganisation", "PRODUCER.PROCESSING_ORGANISATION"),
    "contact": ("Producer", "ContactPerson", "PRODUCER.CONTACT_PERSON"),
    "product_id": ("DataProduct", "ID", "PRODUCT.ID"),
    "host_name": ("DataProduct", "InstrumentHostName", "PRODUCT.INSTRUMENT_HOST_NAME"),
    "host_id": ("DataProduct", "InstrumentHostID", "PRODUCT.INSTRUMENT_HOST_ID"),
    "target": ("DataProduct", "TargetName", "PRODUCT.TARGET_NAME"),
    "instrument_name": ("DataProduct", "InstrumentName", "PRODUCT.INSTRUMENT_NAME"),
    "instrument_id": ("DataProduct", "InstrumentID", "PRODUCT.INSTRUMENT_ID"),
    "level": ("DataProduct", "ProcessingLevel", "PRODUCT.PROCESSING_LEVEL"),
    "type_name": ("DataProduct", "ProductTypeName", "PRODUCT.TYPE_NAME"),
    "type_id": ("DataProduct", "ProductTypeID", "PRODUCT.TYPE_ID"),
    "data_set": ("DataProduct", "DataSetName", "PRODUCT.DATA_SET_NAME"),
    "date": ("DataProduct", "ProcessingDate", "PRODUCT.PROCESSING_DATE"),
}


def imars_facts(product_id: str, product_type: str, keywords: Mapping[str, Any], target: str) -> dict[str, str]:
    """Producer and product facts of one delivery, from the missions and the params."""
    type_name, type_id = imars_mission.PRODUCT_TYPES[product_type]
    hrsc = hrsc_mission.KEYWORDS
    return {
        "software_name": imars_mission.SOFTWARE_NAME,
        "software_version": __version__,
        "institution": str(keywords.get("PRODUCER_INSTITUTION_NAME", IMARS_INSTITUTION)),
        "organisation": imars_mission.PROCESSING_ORGANISATION,
        "contact": str(keywords.get("TECHNICAL_CONTACT", keywords.get("PRODUCER_FULL_NAME", "UNK"))),
        "product_id": product_id,
        "host_name": hrsc["INSTRUMENT_HOST_NAME"],
        "host_id": hrsc["INSTRUMENT_HOST_ID"],
        "target": target,
        "instrument_name": hrsc["INSTRUMENT_NAME"],
        "instrument_id": hrsc["INSTRUMENT_ID"],
        "level": imars_mission.PROCESSING_LEVEL,
        "type_name": type_name,
        "type_id": type_id,
        "data_set": str(keywords.get("DATA_SET_NAME", imars_mission.DATA_SET_NAME)),
        "date": processing_date(),
    }


def fact_tags(facts: Mapping[str, str]) -> dict[str, str]:
    """The facts as GeoTIFF metadata tags (PRODUCER.INSTITUTION_NAME, PRODUCT.PROCESSING_DATE ...)."""
    return {tag: facts[name] for name, (_, _, tag) in FACT_PLACES.items()}


def _facts_of(facts: Mapping[str, str], place: str) -> list[tuple[str, object]]:
    """The facts of one PVL object or group (the processing date as a PVL date)."""
    return [(key, dt.date.fromisoformat(facts[name]) if name == "date" else facts[name])
            for name, (where, key, _) in FACT_PLACES.items() if where == place]


def imars_pvl_text(
    written, file_name: str, product_id: str, product_type: str, geometry: MapGeometry, keywords: Mapping[str, Any],
    sources: list[str], version: str, image_extra: Mapping[str, Any], facts: Mapping[str, str],
) -> str:
    """The metadata file, built from the GeoTIFF as written so the two cannot disagree.

    Shaped like the real iMars files (ProductInfo with group Producer, Image,
    DataProduct, MapProjection, Algorithm and their keywords); the keywords the
    validator's IMARS rules read (Samples, NoData, PixelResolution, Proj4 ...) are
    kept beside the real ones.
    """
    transform = written.transform
    resolution = pvl.Quantity(transform.a, "m")
    module = pvl.PVLModule([
        ("ProductInfo", pvl.PVLObject([
            ("ProductId", product_id),
            ("ProductType", product_type),
            ("ProductVersionId", version),
            ("SourceProductId", sources or ["N/A"]),
            ("Producer", pvl.PVLGroup(_facts_of(facts, "Producer"))),
        ])),
        ("Image", pvl.PVLObject([
            ("FileName", file_name),
            ("Format", "GeoTIFF"),
            ("Lines", written.height),
            ("LineSample", written.width),
            ("Band", written.count),
            ("BitDepth", np.dtype(written.dtypes[0]).itemsize * 8),
            ("DTMResolution" if product_type == "DTM" else "ORIResolution", resolution),
            ("Unit", "m" if product_type == "DTM" else "DN"),
            ("NodataValue", int(written.nodata)),
            ("Projection", geometry.projection_type),
            ("Samples", written.width),
            ("Bands", written.count),
            ("SampleType", written.dtypes[0]),
            ("NoData", int(written.nodata)),
            ("ScalingFactor", float(written.scales[0])),
            ("Offset", float(written.offsets[0])),
            *image_extra.items(),
        ])),
        ("DataProduct", pvl.PVLObject([
            *_facts_of(facts, "DataProduct"),
            ("FileName", file_name),
            ("Format", "GeoTIFF"),
            ("Units", "m" if product_type == "DTM" else "DN"),
        ])),
        ("MapProjection", pvl.PVLObject([
            ("MapProjectionType", geometry.projection_type),
            ("TargetName", geometry.target_name or "MARS"),
            ("AAxisRadius", pvl.Quantity(geometry.a_axis_km, "km")),
            ("BAxisRadius", pvl.Quantity(geometry.b_axis_km, "km")),
            ("CAxisRadius", pvl.Quantity(geometry.c_axis_km, "km")),
            ("CenterLatitude", geometry.center_latitude),
            ("CenterLongitude", geometry.center_longitude),
            ("MapScale", pvl.Quantity(geometry.map_scale, "m/pixel")),
            ("PixelResolution", resolution),
            ("UpperLeftCornerX", pvl.Quantity(transform.c, "m")),
            ("UpperLeftCornerY", pvl.Quantity(transform.f, "m")),
            ("MinimumLatitude", geometry.minimum_latitude),
            ("MaximumLatitude", geometry.maximum_latitude),
            ("MinimumLongitude", geometry.westernmost_longitude),
            ("MaximumLongitude", geometry.easternmost_longitude),
            ("Proj4", proj4_string(written.crs)),
        ])),
        ("Algorithm", pvl.PVLObject([
            ("Name", str(keywords.get("EXTRACTION_METHOD", "UNK"))),
            *[(key, value) for key, value in dict(keywords.get("MATCHER_PARAMETERS", {}) or {}).items()],
        ])),
    ])
    _check_pvl(module, imars_mission.metadata_name(product_id))
    text: str = pvl.dumps(module, encoder=pvl.encoder.ISISEncoder())
    return text


def _check_pvl(node: Mapping[str, Any], source: str, where: str = "") -> None:
    """Every keyword of the .pvl a PVL keyword and every text value one a PVL string can carry
    (encode's PVL rules), before pvl writes it: a MATCHER_PARAMETERS name holding a line break
    and `END_OBJECT` would otherwise write a second, forged ProductInfo object."""
    for key, value in node.items():
        keyword = f"{where}{key}"
        check_pvl_keyword(str(key), keyword, source)
        if isinstance(value, Mapping):
            _check_pvl(value, source, f"{keyword}.")
        for item in value if isinstance(value, (list, tuple)) and not isinstance(value, pvl.Quantity) else (value,):
            if isinstance(item, str):
                check_pvl_string(item, keyword, source)


def proj4_string(crs) -> str:
    """The CRS as a PROJ string in PROJ's own spelling (`+no_defs`, not `+no_defs=True`)."""
    return " ".join(f"+{key}" if value is True else f"+{key}={value}" for key, value in crs.to_dict().items())
