"""The steps every product writer takes around its own: open the input, check it, describe its
geometry, scan it, stage the output.

They are written once here, so every writer refuses the same input in the same words and names
it the same way (a local file or an s3:// object, through formats/raster.py). A mission supplies
a hook where its products differ (`Opening`): the check of the opened file (band count, sample
type), the grid the writer reads (HRSC: the input warped into its own projection) and the
description of that grid (HRSC: refused in another projection or on another body) - and the
kind of product it makes (`Opening.kind`): an input that is plainly the other kind (`pdsgen dtm`
of an 8-bit image, `pdsgen ortho` of heights) is refused, the Extras' own decision
(formats/kind.py) telling which, unless the caller says `any_kind`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator
from contextlib import AbstractContextManager, contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rasterio.io import DatasetReader

from ..errors import PdsgenError, param
from ..formats.img import Adjust, BandStatistics, scan_band
from ..formats.kind import decide_kind, raster_facts, sampled_range
from ..formats.raster import open_raster, require_single_band
from ..geo.geometry import MapGeometry, describe_geometry
from ..missions import ProductKind
from ..missions.hrsc import is_dtm_name as is_hrsc_dtm_name
from ..storage.staging import StagedOutputs, prepare_output_dir

# The hooks: check the opened file; the grid the writer reads from it; that grid's geometry.
Check = Callable[[DatasetReader, Path], None]
Grid = Callable[[DatasetReader], AbstractContextManager[DatasetReader]]
Describe = Callable[[DatasetReader, Path], MapGeometry]


def single_band(what: str = "a DTM") -> Check:
    """The check of most products: one band (`what` names the product in the refusal)."""

    def check(dataset: DatasetReader, path: Path) -> None:
        require_single_band(dataset, what)

    return check


@contextmanager
def as_opened(dataset: DatasetReader) -> Iterator[DatasetReader]:
    """The grid of most products: the input's own."""
    yield dataset


def map_geometry(grid: DatasetReader, path: Path) -> MapGeometry:
    """The geometry of most products: the grid described, any refusal naming the input."""
    return describe_geometry(grid.crs, grid.transform, grid.width, grid.height, str(path))


@dataclass(frozen=True)
class Opening:
    """How a writer opens its input: the steps where missions differ, as hooks."""

    check: Check = single_band()
    grid: Grid = as_opened
    describe: Describe = map_geometry
    kind: ProductKind | None = None  # the kind of product made: an input plainly the other is refused


@dataclass(frozen=True)
class ProductInput:
    """An opened, checked and described input, and the steps that follow on it."""

    path: Path  # as given: refusals name it
    source: DatasetReader  # the file as opened
    dataset: DatasetReader  # the grid the writer reads (the source, or a mission's warp of it)
    geometry: MapGeometry

    def scan(self, adjust: Adjust | None = None) -> BandStatistics:
        """One pass over the valid values (changed by `adjust`), for an encoding that needs
        their range before writing; an input without any is refused."""
        return require_valid(scan_band(self.dataset, adjust), self.path)

    def output_dir(self, outdir: str | os.PathLike[str]) -> Path:
        """OUTDIR, created if needed and writable; made only once the input was accepted."""
        return prepare_output_dir(outdir)

    def stage(self, finals: Iterable[Path], overwrite: bool, shared: Iterable[Path] = ()) -> StagedOutputs:
        """The product's files written under temporary names and published together, or not at
        all (`shared`: files other products of the directory share, such as JP2INFO.TXT)."""
        return StagedOutputs(finals, overwrite, shared=shared)


def require_valid(stats: BandStatistics, path: str | os.PathLike[str]) -> BandStatistics:
    """`stats`, or the refusal of an input whose every pixel is no data."""
    if stats.valid_count == 0:
        raise no_valid_pixels(path)
    return stats


def no_valid_pixels(path: str | os.PathLike[str]) -> PdsgenError:
    """The refusal of an input whose every pixel is no data, in every writer's words."""
    return PdsgenError(path, "has no valid pixels (all nodata)")


_WHAT = {ProductKind.DTM: "a DTM", ProductKind.ORTHO: "an orthoimage"}


def refuse_other_kind(dataset: DatasetReader, path: Path, kind: ProductKind) -> None:
    """PdsgenError when the input is plainly the other kind of product than `kind`, as the
    Extras decide it (its metadata, else its sample type and values): a DTM of 8-bit DNs or of
    reflectance, an orthoimage of heights. Integers wider than 8 bits without metadata are
    taken as heights for a DTM (whole metres, as MOLA's int16 DEMs hold them), and an input
    the decision cannot place is taken as the user says."""
    dtype = np.dtype(dataset.dtypes[0])
    if kind is ProductKind.DTM and dtype.kind in "iu" and dtype.itemsize > 1:
        return
    facts = raster_facts(dataset)
    try:
        decision = decide_kind({}, {}, facts, path, lambda: sampled_range(dataset, facts["scale"], facts["offset"]),
                               named_dtm=is_hrsc_dtm_name(path.stem))
    except PdsgenError:
        return
    if decision.kind != kind.value:
        other = ProductKind.ORTHO if kind is ProductKind.DTM else ProductKind.DTM
        raise PdsgenError(path, f"looks like {_WHAT[other]}, not {_WHAT[kind]} ({decision.reason}); "
                                f"give {param('any_kind', True)} to make {_WHAT[kind]} of it anyway")


@contextmanager
def open_product_input(input_path: str | os.PathLike[str], opening: Opening = Opening(),
                       any_kind: bool = False) -> Iterator[ProductInput]:
    """Open the input (a file or an s3:// object), check it, present the grid the writer reads
    and describe it, each step the mission's `opening` hook; refusals come before any output.
    `any_kind`: make the product whatever kind the input looks like (see `refuse_other_kind`)."""
    path = Path(input_path)
    with open_raster(path) as source:
        opening.check(source, path)
        if opening.kind is not None and not any_kind:
            refuse_other_kind(source, path, opening.kind)
        with opening.grid(source) as grid:
            yield ProductInput(path, source, grid, opening.describe(grid, path))


__all__ = ["Opening", "ProductInput", "as_opened", "map_geometry", "no_valid_pixels", "open_product_input",
           "refuse_other_kind", "require_valid", "single_band"]
