"""Turn one product into its preview images (browse, annotated browse, thumbnail).

A DTM gives three renderings (greyscale elevation, shaded relief, colour-coded
elevation over shaded relief); an orthoimage gives one (its bands, each stretched on
its own). Each rendering is made once at browse size from a single decimated read;
the thumbnail is reduced from that browse, so both share one stretch and colour
range. No-data pixels are black in every rendering; valid data never maps to pure
black in the greyscale and shaded DTM renderings (they use 1..255).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from PIL import Image
from rasterio.transform import Affine

from ..errors import PdsgenError
from ..formats.preview_size import thumbnail_size
from ..missions import hirise
from .annotate import Annotation, Layout, Legend, annotate
from .colour_ramp import RAMP_NAME, blend_with_shade, ramp_colours
from .decimate import PreviewGrid, preview_grid, read_physical, statistics_sample
from .full_stretch import full_resolution_stretches, streams_whole_numbers
from .ground_scale import GroundScale, ground_scale_at
from .hillshade import auto_exaggeration, shade_from_slopes, slopes
from .product_source import DTM, ProductSource
from .stretch import (
    DTM_HIGH_PERCENT,
    DTM_LOW_PERCENT,
    ORTHO_HIGH_PERCENT,
    ORTHO_LOW_PERCENT,
    Stretch,
    percentile_stretch,
)

DTM_BROWSE_WIDTH = 1024
ORTHO_BROWSE_WIDTH = 2048
THUMB_WIDTH = 128


@dataclass(frozen=True)
class Rendering:
    """One rendering: file suffixes and what it shows (for README.TXT and the subtitle)."""

    key: str
    browse: str
    annotated: str
    thumb: str
    description: str


DTM_RENDERINGS = (
    Rendering("grey", "br", "ab", "th", "Heights as grey levels (dark low, light high)"),
    Rendering("shade", "sb", "sa", "st", "Shaded relief"),
    Rendering("colour", "cb", "ca", "ct",
              f"Colour-coded heights ({RAMP_NAME} ramp) over shaded relief"),
)
ORTHO_RENDERING = Rendering("ortho", "browse", "abrowse", "thumb", "Orthoimage")
# The full-scale quick-look JPEG 2000 of an orthoimage (see `qlook`).
QLOOK_SUFFIX = "QLOOK.JP2"
QLOOK_DESCRIPTION = ("Orthoimage quick look, full scale, lossy JPEG 2000, stretched as the "
                     "browse, georeferenced (GeoJP2)")


NOMAP_FILE_DESCRIPTIONS = {
    "JP2": "NOMAP full scale, stretched, lossy JPEG 2000",
    "browse.jpg": "NOMAP browse (no scale bar, no north arrow)",
}


def nomap_file_names(product_id: str) -> list[tuple[str, str]]:
    """(file name, what it is) of a HiRISE NOMAP product's Extras (`<OBS>_RGB.NOMAP`)."""
    return [(f"{product_id}.{suffix}", NOMAP_FILE_DESCRIPTIONS[suffix])
            for suffix in hirise.NOMAP_SUFFIXES]


def extras_file_names(product_id: str, is_dtm: bool) -> list[tuple[str, str]]:
    """(file name, what it is) of every Extras file of one product, in README order."""
    names = []
    for r in DTM_RENDERINGS if is_dtm else (ORTHO_RENDERING,):
        names += [(f"{product_id}.{r.browse}.jpg", f"{r.description}, browse"),
                  (f"{product_id}.{r.annotated}.jpg", f"{r.description}, annotated browse"),
                  (f"{product_id}.{r.thumb}.jpg", f"{r.description}, thumbnail")]
    if not is_dtm:
        names.append((f"{product_id}.{QLOOK_SUFFIX}", QLOOK_DESCRIPTION))
    return names


@dataclass
class Preview:
    """A rendering's browse, annotated browse and thumbnail, ready to save."""

    rendering: Rendering
    browse: Image.Image
    annotated: Image.Image
    thumb: Image.Image
    layout: Layout            # where the annotations went in `annotated`


@dataclass
class ProductPreviews:
    """All previews of one product plus the numbers README.TXT reports about them."""

    source: ProductSource
    previews: list[Preview]
    grid: PreviewGrid
    scale: GroundScale
    display_range: tuple[float, float] | None
    exaggeration: float = 1.0
    stretches: tuple[Stretch | None, ...] = ()   # orthoimages: per band, as the browse


def render_product(src: ProductSource, *, credit: str, browse_width: int | None,
                   thumb_width: int, azimuth: float, altitude: float,
                   exaggeration: float | None = None) -> ProductPreviews:
    """Make every preview of one product in memory (nothing is written here).

    `exaggeration` None chooses the shaded relief's vertical exaggeration
    automatically (1 unless the relief is too faint at preview scale).
    """
    if src.kind == DTM:
        return _render_dtm(src, credit, browse_width or DTM_BROWSE_WIDTH, thumb_width,
                           azimuth, altitude, exaggeration)
    return _render_ortho(src, credit, browse_width or ORTHO_BROWSE_WIDTH, thumb_width)


def _grid_scale(src: ProductSource, grid: PreviewGrid) -> GroundScale:
    """True ground scale and north at the centre of the preview grid."""
    transform = src.transform @ Affine.scale(grid.step_x, grid.step_y)
    try:
        return ground_scale_at(src.crs, transform, grid.width / 2.0, grid.height / 2.0)
    except PdsgenError as exc:
        raise PdsgenError(src.path, exc.problem) from None


def _render_dtm(src: ProductSource, credit: str, browse_width: int, thumb_width: int,
                azimuth: float, altitude: float, exaggeration: float | None) -> ProductPreviews:
    grid = preview_grid(src, browse_width)
    elevation = read_physical(src, grid, [1])
    valid = ~np.ma.getmaskarray(elevation[0])
    if not valid.any():
        raise PdsgenError(src.path, "has no valid pixels (all no-data)")
    sample = statistics_sample(src, elevation, [1])
    stretch = percentile_stretch(sample[0], DTM_LOW_PERCENT, DTM_HIGH_PERCENT)
    assert stretch is not None  # the browse has valid pixels, so the sample does
    scale = _grid_scale(src, grid)
    z = elevation[0]

    grey = np.where(valid, stretch.apply(z.data, out_low=1), 0).astype(np.uint8)
    dz_east, dz_up, _ = slopes(z, scale.metres_per_column, scale.metres_per_row)
    factor = exaggeration if exaggeration is not None else auto_exaggeration(dz_east, dz_up, valid)
    shade = shade_from_slopes(dz_east * np.float32(factor), dz_up * np.float32(factor), valid,
                              azimuth, altitude)
    shade_dn = np.clip(np.rint(1.0 + 254.0 * shade.data), 1, 255).astype(np.uint8)
    shaded = np.where(valid, shade_dn, 0).astype(np.uint8)
    colour = blend_with_shade(ramp_colours(z.data, stretch.low, stretch.high), shade.data,
                              altitude)
    colour[~valid] = 0

    datum = src.heights.datum if src.heights else ""
    legend = Legend(stretch.low, stretch.high, datum)
    images = {"grey": Image.fromarray(grey, "L"), "shade": Image.fromarray(shaded, "L"),
              "colour": Image.fromarray(colour, "RGB")}
    subtitles = {
        "grey": f"Height above {datum}, grey levels from {stretch.low:.0f} m (dark) to "
                f"{stretch.high:.0f} m (light)",
        "shade": f"Shaded relief, light from azimuth {azimuth:g} deg, altitude "
                 f"{altitude:g} deg{_exaggeration_text(factor)}",
        "colour": f"Colour-coded heights over shaded relief (light {azimuth:g}/"
                  f"{altitude:g} deg{_exaggeration_text(factor)})",
    }
    previews = []
    for rendering in DTM_RENDERINGS:
        note = Annotation(src.title or src.product_id, subtitles[rendering.key], credit,
                          scale.metres_per_column, scale.north_deg,
                          legend if rendering.key == "colour" else None)
        previews.append(_preview(rendering, images[rendering.key], note, thumb_width))
    return ProductPreviews(src, previews, grid, scale, (stretch.low, stretch.high), factor)


def _exaggeration_text(factor: float) -> str:
    return "" if factor == 1.0 else f", vertical exaggeration {factor:g}x"


def _render_ortho(src: ProductSource, credit: str, browse_width: int,
                  thumb_width: int) -> ProductPreviews:
    grid = preview_grid(src, browse_width)
    bands = [1, 2, 3] if src.band_count >= 3 else [1]
    data = read_physical(src, grid, bands)
    if np.ma.getmaskarray(data).all():
        raise PdsgenError(src.path, "has no valid pixels (all no-data)")
    channels = []
    if hirise.is_rdr(str(src.label.get("DATA_SET_ID", ""))) and streams_whole_numbers(src):
        # A HiRISE RDR: the release's 0.1 % / 0.01 % points exactly, from every pixel.
        stretches = full_resolution_stretches(src, bands, ORTHO_LOW_PERCENT, ORTHO_HIGH_PERCENT)
    else:
        sample = statistics_sample(src, data, bands)
        stretches = tuple(percentile_stretch(sample[i], ORTHO_LOW_PERCENT, ORTHO_HIGH_PERCENT)
                          for i in range(len(bands)))
    for i, stretch in enumerate(stretches):
        if stretch is None:
            channels.append(np.zeros(data.shape[1:], np.uint8))
            continue
        channels.append(np.where(np.ma.getmaskarray(data[i]), 0,
                                 stretch.apply(data[i].data)).astype(np.uint8))
    if len(channels) == 3:
        image = Image.fromarray(np.dstack(channels), "RGB")
        subtitle = "Orthoimage, bands 1-3 as red, green, blue, each stretched on its own"
    else:
        image = Image.fromarray(channels[0], "L")
        subtitle = "Orthoimage, linear stretch (0.1 % to black, 0.01 % to white)"
    scale = _grid_scale(src, grid)
    note = Annotation(src.title or src.product_id, subtitle, credit, scale.metres_per_column,
                      scale.north_deg)
    preview = _preview(ORTHO_RENDERING, image, note, thumb_width)
    return ProductPreviews(src, [preview], grid, scale, None, stretches=stretches)


def _preview(rendering: Rendering, browse: Image.Image, note: Annotation,
             thumb_width: int) -> Preview:
    annotated, layout = annotate(browse, note)
    return Preview(rendering, browse, annotated, thumbnail(browse, thumb_width), layout)


def thumbnail(browse: Image.Image, thumb_width: int) -> Image.Image:
    """The browse reduced to `thumb_width` (never enlarged), aspect kept."""
    size = thumbnail_size(browse.width, browse.height, thumb_width)  # the one home of the arithmetic
    return browse.resize(size, Image.Resampling.LANCZOS, reducing_gap=3.0)
