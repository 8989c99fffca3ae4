"""The orthoimage product: a lossless JPEG 2000 (.JP2) with a detached PDS3 label.

Data flows one way: read raster -> describe geometry -> decide the DN mapping
(from the data type, --range, or one streamed min/max pass for floats) ->
choose names and keywords -> render the label -> encode the JP2 tile row by
tile row with its GeoJP2 (and optional GMLJP2) box. Both files are staged
together, so either both appear or neither does.
"""

from __future__ import annotations

import functools
import logging
import os
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Future
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from rasterio.io import DatasetReader
from rasterio.windows import Window

from ..dialect import Dialect
from ..errors import ParamsError, PdsgenError, param
from ..formats.geojp2 import geojp2_box, gmljp2_box
from ..formats.jp2 import JP2INFO_NAME, TILE_SIZE, describe_jp2, jp2info_text, require_openjpeg, write_jp2
from ..formats.raster import row_strips
from ..formats.scale_dn import (
    SPECIAL_DNS,
    DnMapping,
    default_bits,
    dtype_fits,
    identity_mapping,
    invalid_mask,
    linear_mapping,
    to_dns,
    valid_range,
)
from ..geo.geometry import MapGeometry
from ..label.render import render_label
from ..label.values import Based, Quantity, Symbol
from ..missions import Mission, ProductIdRequest, ProductKind, get_mission
from ..params import ParamValue, check_source_id, check_version, resolve_params, source_ids
from ..storage.staging import InterruptSafeExecutor
from .agreement import allows_deviations, check_label, label_keywords
from .dispatch import NO_STATEMENT, MissionWriter, ProductStatement, call_mission_writer, stating
from .identification import (
    choose_product_id,
    identification_keywords,
    source_id_values,
    with_unstated_warning,
)
from .opening import Opening, no_valid_pixels, open_product_input
from .options import ProductOptions
from .result import ProductResult

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class OrthoProduct(ProductResult):
    """What `write_ortho` produced, for callers that go on to make Extras or check it."""

    product_id: str
    jp2_path: Path
    label_path: Path
    geometry: MapGeometry
    scaling_factor: float
    offset: float
    bits: int
    bands: int
    label_text: str  # the PDS3 label, or the PDS4 label of a PDS4-only product
    pds4_label_path: Path | None = None  # with the uncompressed primary array beside it (.img)
    warnings: tuple[str, ...] = ()  # dictionary deviations kept (--allow-dictionary-deviations)
    jp2info_path: Path | None = None  # the directory's JP2INFO.TXT, written again with this JP2's entry

    @property
    def files(self) -> tuple[Path, ...]:
        """Every file of this product."""
        pds4 = (self.pds4_label_path.with_suffix(".img"), self.pds4_label_path) if self.pds4_label_path else ()
        return tuple(dict.fromkeys((self.jp2_path, self.label_path, *pds4)))

    @property
    def shared_files(self) -> tuple[Path, ...]:
        """The directory's JP2INFO.TXT, which this product's entry was written into."""
        return (self.jp2info_path,) if self.jp2info_path else ()

    @property
    def summary_facts(self) -> tuple[str, ...]:
        return (f"{self.bands} band(s)", f"{self.bits}-bit DN * {self.scaling_factor:.6g} + {self.offset:.6g}")


# Band names of 1- and 3-band orthoimages, as HiRISE labels write them.
ORTHO_FILTER_NAMES = {1: ("RED",), 3: ("NEAR-INFRARED", "RED", "BLUE-GREEN")}


def write_ortho(
    input_path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    outdir: str | os.PathLike[str],
    *,
    profile: str = "generic",
    **options: Any,
) -> ProductResult:
    """Write the orthoimage product of `profile`.

    Missions with their own form (hrsc: 8-bit ND4 .img, imars: GeoTIFF + PVL +
    footprint) have their writer called with `options` (their images are 8-bit:
    `bits` other than 8 is refused); the others get the JP2 + .LBL of
    `write_jp2_ortho` with the mission's names and keywords. `threads=N` caps the
    cores the JPEG 2000 encoder uses (default: all; a batch running several
    products at once gives each a share); the other forms use one core anyway. An option the
    profile does not use (its mission's declaration) is refused.
    """
    mission = get_mission(profile)
    built = ProductOptions.build("ortho", mission, options)
    if mission.writer("ortho") is None and not isinstance(input_path, (str, os.PathLike)):
        raise PdsgenError(None, f"the {profile} profile takes one input file")
    return with_unstated_warning(call_mission_writer(ortho_writer(mission, built, profile), input_path, outdir, built),
                                 profile)


def ortho_writer(mission: Mission, built: ProductOptions, profile: str,
                 statement: ProductStatement | None = None) -> MissionWriter:
    """The writer of the mission's orthoimages: its own (8-bit: `bits` other than 8 refused,
    naming `profile`), or the standard JP2 + .LBL in its words; given the `statement` its label
    makes (a mosaic's: how its sources were put together)."""
    own = mission.writer("ortho")
    if own is None:
        return stating(functools.partial(write_jp2_ortho, mission=mission), statement)
    if built.bits not in (None, 8):
        raise ParamsError(None, f"{param('profile', profile)} orthoimages are 8-bit; "
                                f"{param('bits', built.bits)} does not apply")
    return stating(own, statement)


def write_jp2_ortho(
    input_path: str | os.PathLike[str],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
    *,
    mission: Mission,
    filter_names: Sequence[str] | None = None,
    statement: ProductStatement = NO_STATEMENT,
) -> OrthoProduct:
    """Convert a 1-band (RED) or 3-band (IRB) orthoimage into `<PRODUCT_ID>.JP2` + `.LBL`.

    `threads` limits how many cores the JPEG 2000 encoder uses (default: all).
    The directory's JP2INFO.TXT gets this JP2's encoding facts.
    label "pds4" writes the PDS4 form instead of the .LBL: the uncompressed DNs as the
    primary array `<PRODUCT_ID>.img`, the JP2 as a supplemental Encoded_Image, and
    `<PRODUCT_ID>.xml`; "both" writes the .LBL and the PDS4 form.
    `filter_names`: the bands' FILTER_NAMEs in band order, for missions whose bands are not
    HiRISE's (default: RED, or NEAR-INFRARED, RED, BLUE-GREEN).
    `statement`: what the label says beyond the mission's own words (a mosaic's sources, an
    HRSC-AX tile's bands and offsets).
    """
    product_id, bits, value_range, gmljp2 = options.product_id, options.bits, options.value_range, options.gmljp2
    observation_id, sequence, source_dtm_id = options.observation_id, options.sequence, options.source_dtm_id
    dialect = Dialect.of(options.label)
    chosen = mission
    if chosen.ortho_keywords is None:
        raise PdsgenError(None, f"the {chosen.name} profile writes orthoimages in its own form, not as JP2 + LBL")
    version = check_version(options.version)
    _check_source_dtm(chosen, source_dtm_id)
    keywords = resolve_params(options.params)
    require_openjpeg()
    allow = allows_deviations(options.allow_dictionary_deviations, keywords)
    keywords = label_keywords(keywords)
    input_path = Path(input_path)
    with open_product_input(input_path, ORTHO_OPENING, options.any_kind) as opened:
        dataset, geometry = opened.dataset, opened.geometry
        bits = bits or _default_bits(dataset, chosen)
        mapping = _choose_mapping(dataset, input_path, bits, value_range)
        log.info("DNs: %d-bit, value = DN * %.6g + %.6g%s", bits, mapping.scaling_factor, mapping.offset,
                 "" if mapping.keeps_values else f" (input {mapping.low:.6g} .. {mapping.high:.6g} mapped)")
        sources = _source_ids(keywords, observation_id, source_dtm_id)
        ident = identification_keywords(chosen.ortho_keywords, keywords, geometry, version)
        product_id = choose_product_id(product_id, chosen.ortho_product_id, ProductIdRequest(
            input_path.stem, geometry, sources, None, version, dataset.count, observation_id, sequence,
        ))
        outdir = opened.output_dir(outdir)
        jp2_final, label_final = outdir / f"{product_id}.JP2", outdir / f"{product_id}.LBL"
        img_final, xml_final = outdir / f"{product_id}.img", outdir / f"{product_id}.xml"
        context = _label_context(chosen, product_id, ident, sources, geometry, dataset.count, mapping,
                                 jp2_final.name, filter_names, statement)
        boxes = [geojp2_box(dataset.crs, dataset.transform)]
        if gmljp2:
            boxes.append(gmljp2_box(dataset.crs, dataset.transform, dataset.height, dataset.width))
        info_final = outdir / JP2INFO_NAME
        finals = [jp2_final] + ([label_final] if dialect.pds3 else []) + (
            [img_final, xml_final] if dialect.pds4 else [])
        with opened.stage(finals, options.overwrite, shared=[info_final]) as staged, ExitStack() as files, \
                InterruptSafeExecutor(1, "pdsgen-label-check") as checker:
            # The label is rendered and checked (the validator's first use loads it: a fifth of
            # a second) while the first tiles are encoded; a refusal stops the encoding at the
            # next row of tiles.
            label_check = checker.submit(_render_and_check, context, label_final.name, allow)
            reader = _TileRowReader(dataset, mapping, str(input_path))
            rows: Callable[[int, int], np.ndarray] = reader
            tap = None
            if dialect.pds4:  # the same DNs also go, uncompressed, into the PDS4 primary array
                from ..pds4.products import ArrayRowTap  # PDS4 code loads only when asked for

                array_file = files.enter_context(open(staged.path(img_final), "wb"))
                rows = tap = ArrayRowTap(reader, array_file, mapping.special)
            settings = write_jp2(
                staged.path(jp2_final), dataset.height, dataset.width, dataset.count,
                mapping.special.bits, _until_refused(rows, label_check), boxes, threads=options.threads,
            )
            text, warnings = label_check.result()
            if not reader.any_valid:
                raise no_valid_pixels(input_path)
            files.close()
            if dialect.pds3:
                staged.path(label_final).write_bytes(text.encode("ascii"))
            if tap is not None:
                from ..pds4.content import digest_file
                from ..pds4.products import ProductDescription, ortho_label_text

                description = ProductDescription(product_id, chosen, version, ident, geometry, dataset, sources)
                pds4_text = ortho_label_text(description, img_final.name, tap, jp2_final.name,
                                             digest_file(staged.path(jp2_final)), mapping.scaling_factor,
                                             mapping.offset)
                staged.path(xml_final).write_text(pds4_text, encoding="utf-8")
                text = pds4_text if not dialect.pds3 else text
            entry = describe_jp2(jp2_final.name, settings, dataset.height, dataset.width, dataset.count,
                                 mapping.special.bits, ["GeoJP2", "GMLJP2"][:len(boxes)])
            previous = info_final.read_text("ascii", "replace") if info_final.is_file() else None
            staged.path(info_final).write_bytes(jp2info_text(previous, entry, lambda name: (outdir / name).is_file()))
    return OrthoProduct(
        product_id=product_id,
        jp2_path=jp2_final,
        label_path=xml_final if not dialect.pds3 else label_final,
        geometry=geometry,
        scaling_factor=mapping.scaling_factor,
        offset=mapping.offset,
        bits=bits,
        bands=dataset.count,
        label_text=text,
        pds4_label_path=xml_final if dialect.pds4 else None,
        warnings=warnings,
        jp2info_path=info_final,
    )


def _check_input(dataset: DatasetReader, path: Path) -> None:
    """1 or 3 bands of one real number type."""
    if dataset.count not in ORTHO_FILTER_NAMES:
        raise PdsgenError(
            path, f"has {dataset.count} bands; an orthoimage has 1 (RED) or 3 (near-infrared, red, blue-green)"
        )
    kinds = {np.dtype(dt).kind for dt in dataset.dtypes}
    if not kinds <= set("iuf") or len(set(dataset.dtypes)) != 1:
        raise PdsgenError(path, f"sample types {', '.join(dataset.dtypes)} are not one real number type")


ORTHO_OPENING = Opening(check=_check_input, kind=ProductKind.ORTHO)


def _default_bits(dataset: DatasetReader, mission: Mission) -> int:
    """Integers keep their width; floats get the mission's default (HiRISE 10 bits, else 16)."""
    dtype = np.dtype(dataset.dtypes[0])
    if dtype.kind == "f":
        return mission.default_ortho_bits_for_float
    return default_bits(dtype)


def _choose_mapping(
    dataset: DatasetReader, path: Path, bits: int, value_range: tuple[float, float] | None
) -> DnMapping:
    special = SPECIAL_DNS[bits]
    if value_range is not None:
        low, high = (float(v) for v in value_range)
        if not high > low:
            raise PdsgenError(None, f"{param('value_range')} needs MIN < MAX, got {low:g} {high:g}")
        return linear_mapping(special, low, high)
    dtype = np.dtype(dataset.dtypes[0])
    if dtype_fits(dtype, bits):
        return identity_mapping(special)
    found = valid_range(dataset, row_strips(dataset))
    if found is None:
        raise no_valid_pixels(path)
    low, high = found
    if dtype.kind in "iu" and low >= 0 and high <= special.max_dn:
        return identity_mapping(special)
    return linear_mapping(special, low, high)


class _TileRowReader:
    """Reads one row of tiles of every band and turns it into DNs."""

    def __init__(self, dataset: DatasetReader, mapping: DnMapping, source: str) -> None:
        self.dataset = dataset
        self.mapping = mapping
        self.source = source
        self.any_valid = False

    def __call__(self, first_line: int, lines: int) -> np.ndarray:
        dataset, special = self.dataset, self.mapping.special
        native = dataset.read(window=Window(0, first_line, dataset.width, lines))
        if self.mapping.keeps_values and native.dtype == special.dtype and dataset.count == 1:
            return self._null_in_place(native[0])
        out = np.empty((lines, dataset.width, dataset.count), dtype=special.dtype)
        for band, nodata in enumerate(dataset.nodatavals):
            for start in range(0, dataset.width, TILE_SIZE):  # bounds float64 scratch to one tile
                block = to_dns(native[band, :, start:start + TILE_SIZE], nodata, self.mapping, self.source)
                out[:, start:start + TILE_SIZE, band] = block
        del native
        self._note_valid(out)
        return out[:, :, 0] if dataset.count == 1 else out

    def _null_in_place(self, band: np.ndarray) -> np.ndarray:
        """DNs kept as read: only nodata pixels change (saves a copy of the tile row)."""
        invalid = invalid_mask(band, self.dataset.nodatavals[0])
        if invalid is not None:
            band[invalid] = self.mapping.special.null
        self._note_valid(band)
        return band

    def _note_valid(self, dns: np.ndarray) -> None:
        # Checked only until the first valid pixel turns up: no per-row mask afterwards.
        if not self.any_valid:
            self.any_valid = bool((dns != self.mapping.special.null).any())


def _render_and_check(context: Mapping[str, object], file_name: str, allow: bool) -> tuple[str, tuple[str, ...]]:
    """The PDS3 label's text and the dictionary deviations kept in it (see check_label)."""
    text = render_label("ortho.lbl.j2", context)
    return text, check_label(text, file_name, allow_deviations=allow)


def _until_refused(
    rows: Callable[[int, int], np.ndarray], label_check: Future[tuple[str, tuple[str, ...]]]
) -> Callable[[int, int], np.ndarray]:
    """`rows`, raising the label check's refusal as soon as it is known."""

    def read(first_line: int, lines: int) -> np.ndarray:
        if label_check.done():
            label_check.result()  # raises ParamsError when the label was refused
        return rows(first_line, lines)

    return read


def _check_source_dtm(mission: Mission, source_dtm_id: str | None) -> None:
    """The DTM an orthoimage was orthorectified on, where the mission names its DTMs one way
    (HiRISE: DTEEC_..._U01): another kind of product's ID is refused, not written."""
    if source_dtm_id is None or mission.source_dtm_id is None:
        return
    check_source_id(source_dtm_id, "source_dtm_id")
    if not mission.source_dtm_id(source_dtm_id):
        raise ParamsError(None, f"{param('source_dtm_id')} {source_dtm_id} is not a {mission.name} DTM product ID "
                                "(e.g. DTEEC_008669_1705_009025_1705_U01)")


def _source_ids(
    keywords: Mapping[str, ParamValue], observation_id: str | None, source_dtm_id: str | None
) -> list[str]:
    """SOURCE_PRODUCT_ID in hidtmgen's order: the DTM, then the observation, then any others."""
    sources = source_ids((), keywords)
    if observation_id is not None:
        check_source_id(observation_id, "observation_id")
    if source_dtm_id is not None:
        check_source_id(source_dtm_id, "source_dtm_id")
    first = [s for s in (source_dtm_id, observation_id) if s]
    return first + [s for s in sources if s not in first]


def _label_context(
    mission: Mission,
    product_id: str,
    ident: Mapping[str, ParamValue],
    sources: Sequence[str],
    geometry: MapGeometry,
    bands: int,
    mapping: DnMapping,
    jp2_name: str,
    filter_names: Sequence[str] | None = None,
    statement: ProductStatement = NO_STATEMENT,
) -> dict[str, object]:
    special = mapping.special
    sample_bits = 8 if special.bits == 8 else 16
    record_bytes = geometry.samples * sample_bits // 8
    file_records = geometry.lines * bands
    filters = tuple(filter_names) if filter_names else ORTHO_FILTER_NAMES[bands]
    known = mission.filter_wavelengths_nm
    wavelengths = tuple(known[name] for name in filters) if known else None
    return {
        "product_id": product_id,
        "ident": ident,
        "source_product_id": source_id_values(sources),
        "geometry": geometry,
        "jp2_name": jp2_name,
        "jp2info_name": JP2INFO_NAME,
        "img_name": f"{product_id}.IMG",
        "record_bytes": record_bytes,
        "file_records": file_records,
        "required_storage_bytes": record_bytes * file_records,
        "description": statement.description(mission),
        "bands": bands,
        "sample_type": Symbol("UNSIGNED_INTEGER" if sample_bits == 8 else "MSB_UNSIGNED_INTEGER"),
        "sample_bits": sample_bits,
        "bit_mask": Based((1 << special.bits) - 1, 2, sample_bits),
        "scaling_factor": float(mapping.scaling_factor),
        "offset": float(mapping.offset),
        "special": special,
        "filter_name": filters[0] if bands == 1 else list(filters),
        "center_wavelength": _wavelengths(wavelengths, bands),
        "standard_parallels_na": mission.ortho_standard_parallels_na,
        "map_projection_note": statement.projection_note(mission),
        "stretch_namespace": mission.ortho_stretch_namespace,
        # The linear display stretch of the valid DNs (the release: 3 and 1021 for 10-bit data).
        "minimum_stretch": special.valid_min if bands == 1 else [special.valid_min] * bands,
        "maximum_stretch": special.valid_max if bands == 1 else [special.valid_max] * bands,
    }


def _wavelengths(wavelengths: tuple[int, ...] | None, bands: int) -> object:
    if wavelengths is None:
        return "UNK" if bands == 1 else ["UNK"] * bands
    quantities = [Quantity(nm, "NM") for nm in wavelengths]
    return quantities[0] if bands == 1 else quantities


__all__ = ["OrthoProduct", "ortho_writer", "write_jp2_ortho", "write_ortho"]
