"""The DTM product: a PDS3 .IMG of float32 elevations with an attached label.

Data flows one way: read raster -> describe geometry -> choose names and
keywords (profile + params) -> render the label -> stream the image.
"""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass
from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal, localcontext
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dialect import Dialect
from ..errors import ParamsError, PdsgenError, param
from ..formats.img import (
    MISSING_BITS,
    RESERVATION_STATISTIC,
    BandStatistics,
    stream_float32_band,
    write_attached_product,
)
from ..formats.raster import require_single_band
from ..geo.geometry import MapGeometry
from ..label.grammar import sample_type
from ..label.render import RecordLayout, render_label, settle_attached_label
from ..label.values import Based, Fixed, Symbol
from ..missions import Mission, ProductIdRequest, ProductKind, get_mission
from ..params import check_version, resolve_params, source_ids
from ..progress import is_large
from .agreement import allows_deviations, check_label, label_keywords
from .dispatch import NO_STATEMENT, MissionWriter, ProductStatement, call_mission_writer, stating
from .identification import choose_product_id, identification_keywords, source_id_values, with_unstated_warning
from .opening import Opening, open_product_input, require_valid
from .options import ProductOptions
from .result import ProductResult

if TYPE_CHECKING:
    from rasterio.io import DatasetReader


@dataclass(frozen=True)
class DtmProduct(ProductResult):
    """What `write_dtm` produced, for callers that go on to make Extras or check it."""

    product_id: str
    path: Path
    geometry: MapGeometry
    valid_minimum: float
    valid_maximum: float
    records: RecordLayout  # label_records 0: a raw PDS4 array file
    label_text: str  # the PDS3 label, or the PDS4 label of a PDS4-only product
    pds4_label_path: Path | None = None
    warnings: tuple[str, ...] = ()  # dictionary deviations kept (--allow-dictionary-deviations)

    @property
    def files(self) -> tuple[Path, ...]:
        """Every file this product wrote."""
        return (self.path,) + ((self.pds4_label_path,) if self.pds4_label_path else ())

    @property
    def summary_facts(self) -> tuple[str, ...]:
        return (f"valid {self.valid_minimum} .. {self.valid_maximum} m",)


def write_dtm(
    input_path: str | os.PathLike[str],
    outdir: str | os.PathLike[str],
    *,
    profile: str = "generic",
    **options: Any,
) -> ProductResult:
    """Write the DTM product of `profile` from a single-band elevation raster.

    Missions with their own product form (hrsc: DT4/DA4 .img, imars: GeoTIFF +
    PVL + footprint) have their writer called with `options`; the others get the
    standard float32 PDS3 .IMG from `write_pds3_dtm` with the mission's names and
    keywords. An option the profile does not use (its mission's declaration) is refused.
    """
    mission = get_mission(profile)
    made = call_mission_writer(dtm_writer(mission), input_path, outdir, ProductOptions.build("dtm", mission, options))
    return with_unstated_warning(made, profile)


def dtm_writer(mission: Mission, statement: ProductStatement | None = None) -> MissionWriter:
    """The writer of the mission's DTMs: its own, or the standard float32 PDS3 .IMG in its words;
    given the `statement` its label makes (a mosaic's: how its sources were put together)."""
    own = mission.writer("dtm")
    return stating(own if own is not None else functools.partial(write_pds3_dtm, mission=mission), statement)


def write_pds3_dtm(
    input_path: str | os.PathLike[str],
    outdir: str | os.PathLike[str],
    options: ProductOptions,
    *,
    mission: Mission,
    statement: ProductStatement = NO_STATEMENT,
) -> DtmProduct:
    """Convert a single-band elevation raster into `OUTDIR/<PRODUCT_ID>.IMG` (float32).

    `statement`: what the label says beyond the mission's own words (a mosaic's sources, an
    HRSC-AX tile's heights and offsets).

    label: "pds3" the .IMG with its attached label; "pds4" `<PRODUCT_ID>.img` (raw samples)
    + `<PRODUCT_ID>.xml`; "both" the PDS3 .IMG and a PDS4 `.xml` describing that same file.
    """
    product_id, byte_order, overwrite = options.product_id, options.byte_order, options.overwrite
    dialect = Dialect.of(options.label)
    chosen = mission
    version = check_version(options.version)
    keywords = resolve_params(options.params)
    allow = allows_deviations(options.allow_dictionary_deviations, keywords)
    keywords = label_keywords(keywords)
    input_path = Path(input_path)
    with open_product_input(input_path, DTM_OPENING, options.any_kind) as opened:
        dataset, geometry = opened.dataset, opened.geometry
        sources = source_ids(options.source_product_ids, keywords)
        ident = identification_keywords(chosen.dtm_keywords, keywords, geometry, version)
        product_id = choose_product_id(product_id, chosen.dtm_product_id, ProductIdRequest(
                input_path.stem, geometry, sources, options.institution, str(ident["PRODUCT_VERSION_ID"])
            ),
        )
        context = {
            "product_id": product_id,
            "ident": ident,
            "source_product_id": source_id_values(sources),
            "geometry": geometry,
            "note": stated_datum(str(keywords.get("DTM_NOTE", statement.note(chosen))), chosen,
                                 options.vertical_datum, geometry),
            "map_projection_note": statement.projection_note(chosen),
            "bit_mask": Based(0xFFFFFFFF, 2, 32),
            "sample_type": Symbol(sample_type(byte_order == "msb", "f")),
            "missing_constant": Based(MISSING_BITS, 16, 8),
        }

        def render(records: RecordLayout, stats: BandStatistics) -> str:
            return render_label(
                "dtm.lbl.j2",
                {
                    **context,
                    "records": records,
                    "valid_minimum": valid_bound(stats.minimum, chosen.valid_range_decimals, "minimum"),
                    "valid_maximum": valid_bound(stats.maximum, chosen.valid_range_decimals, "maximum"),
                },
            )

        def write_data(handle) -> BandStatistics:
            return require_valid(stream_float32_band(dataset, handle, big_endian=byte_order == "msb"), input_path)

        outdir = opened.output_dir(outdir)
        if dialect.pds4:  # the PDS4 writer (lxml, its templates) is loaded only for a PDS4 label
            from ..pds4.products import (
                ProductDescription,
                float32_dtm,
                pds3_label_header,
                write_image_pds4_label,
                write_pds4_dtm,
            )

            description = ProductDescription(product_id, chosen, version, ident, geometry, dataset, sources)
        big_endian = byte_order == "msb"
        xml_final = outdir / f"{product_id}.xml"
        warnings: tuple[str, ...] = ()
        if not dialect.pds3:
            final = outdir / f"{product_id}.img"
            with opened.stage([final, xml_final], overwrite) as staged:
                stats, pds4 = write_pds4_dtm(description, staged.path(final), staged.path(xml_final), final.name,
                                             big_endian)
            records, text = RecordLayout(dataset.width * 4, 0, dataset.height), pds4.text
        else:
            final = outdir / f"{product_id}.IMG"
            if is_large(dataset.width * dataset.height):
                # Refuse before a long data pass what the final label would be refused for; a small
                # product's pass costs less than rendering and checking a second label.
                _, provisional = settle_attached_label(
                    lambda records: render(records, BandStatistics(0, 0.0, 0.0)), dataset.width * 4, dataset.height
                )
                check_label(provisional, final.name, allow_deviations=allow)
            with opened.stage([final] + ([xml_final] if dialect.pds4 else []), overwrite) as staged:
                records, text, stats = write_attached_product(
                    staged.path(final), render, dataset.width * 4, dataset.height, write_data
                )
                warnings = check_label(text, final.name, allow_deviations=allow)
                if dialect.pds4:
                    write_image_pds4_label(description, staged.path(xml_final), staged.path(final), final.name,
                                           float32_dtm(big_endian), [pds3_label_header(records.label_bytes)])
    return DtmProduct(
        product_id=product_id,
        path=final,
        geometry=geometry,
        valid_minimum=stats.minimum,
        valid_maximum=stats.maximum,
        records=records,
        label_text=text,
        pds4_label_path=xml_final if dialect.pds4 else None,
        warnings=warnings,
    )


def stated_datum(note: str, mission: Mission, vertical_datum: str | None, geometry: MapGeometry) -> str:
    """The DTM's NOTE, stating what its heights are above when the user said so (`vertical_datum`).

    A mission whose DTMs are all above one surface (HiRISE: the Mars 2000 areoid) states it in
    its own NOTE already; naming another is refused rather than written beside it."""
    if vertical_datum is None:
        return note
    fixed = mission.dtm_height_datum("") if mission.dtm_height_datum is not None else None
    if fixed is not None:
        if vertical_datum not in fixed:
            raise ParamsError(None, f"{mission.name} DTM heights are above {fixed}, not a {vertical_datum}; "
                                    f"leave out {param('vertical_datum')}")
        return note
    if vertical_datum not in ("sphere", "areoid"):
        raise ParamsError(None, f"{param('vertical_datum')} must be sphere or areoid, not {vertical_datum!r}")
    body = (geometry.target_name or "").strip().title()
    surface = (f"the {body} areoid".replace("the  ", "the ") if vertical_datum == "areoid"
               else f"the {geometry.a_axis_km:g} km sphere")
    return f"{note} Heights are above {surface}."


def _check_heights(dataset: DatasetReader, path: Path) -> None:
    """One band of real numbers: heights."""
    require_single_band(dataset)
    if np.dtype(dataset.dtypes[0]).kind not in "iuf":
        raise PdsgenError(path, f"sample type {dataset.dtypes[0]} is not a real number type")


DTM_OPENING = Opening(check=_check_heights, kind=ProductKind.DTM)


def valid_bound(value: float, decimals: int | None, bound: str) -> float | Fixed:
    """VALID_MINIMUM/MAXIMUM (`bound` "minimum" or "maximum") as the mission writes them.

    Exact (shortest round-trip text) unless the mission states a number of
    decimals (HiRISE: two, as the release and hidtmgen write them); then the
    sample's float32 decimal (1.26, not 1.2599999904632568) is rounded outwards,
    down for the minimum and up for the maximum, so that it still bounds every
    valid value.
    """
    if decimals is None or value == RESERVATION_STATISTIC:  # the label-size reservation: widest as it is
        return value
    rounding = {"minimum": ROUND_FLOOR, "maximum": ROUND_CEILING}[bound]
    with localcontext() as context:
        context.prec = 80  # room for any float32 (39 integer digits) and the decimals
        stated = Decimal(str(np.float32(value))).quantize(Decimal(1).scaleb(-decimals), rounding=rounding)
    return Fixed(float(stated) + 0.0, decimals)  # + 0.0: a zero is written "0.00", not "-0.00"


__all__ = ["DtmProduct", "dtm_writer", "write_dtm", "write_pds3_dtm"]
