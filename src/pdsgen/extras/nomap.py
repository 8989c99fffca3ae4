"""HiRISE NOMAP Extras: the RED, IRB and RGB mosaics in the camera's own geometry.

A HiRISE observation's NOMAP mosaics are its CCD images stitched without a map
projection: RED (up to 10 RED CCDs, one band) and IRB (near-infrared, red and
blue-green, IR and BG warped onto RED, three bands), 10-bit DNs in 16-bit samples
as the RDRs hold them, or I/F floats from ISIS. From them the release makes six
Extras (names in `missions.hirise`): `<OBS>_RED.NOMAP.JP2`, `<OBS>_IRB.NOMAP.JP2`,
`<OBS>_RGB.NOMAP.JP2` and a `.browse.jpg` of each. RGB shows RED, BG and a
synthetic blue = 2 x BG - 0.3 x RED of the IRB mosaic.

Every band of every product is a linear combination of input bands (an `OutputBand`),
computed in floating point, then stretched on its own (the lowest 0.1 % to black,
the highest 0.01 % to white) and clipped to 8 bits: a synthetic blue beyond the
stretch saturates, it never wraps. The stretch points come from histograms filled
block by block (`stretch.StreamingStretch`, two passes), the JP2s are written one
row of tiles at a time from tile-sized windows, and the browse is one GDAL
decimated read, so memory does not grow with the mosaic (a real observation is
20,000 x 60,000). A NOMAP image has no map scale and its north is only roughly
known (about 7 degrees from straight down), so its browse carries no scale bar and
no north arrow: it is the plain image, 2048 pixels wide (never enlarged).
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import rasterio
from PIL import Image
from rasterio.enums import Resampling
from rasterio.errors import RasterioError
from rasterio.transform import Affine
from rasterio.windows import Window

from ..errors import InputError, ParamsError, param
from ..formats.jp2 import choose_settings, write_jp2
from ..formats.kind import NOMAP
from ..formats.raster import bounded_windows, streaming_cache_mb
from ..missions import hirise
from ..progress import advance, is_large
from ..storage.staging import StagedOutputs, prepare_output_dir
from .decimate import preview_grid
from .product_source import ProductSource, quiet_gdal
from .qlook import QLOOK_RATIO
from .readme_index import publish_readme, read_readme
from .readme_txt import NOMAP_TYPE, Entry, empty_entry
from .stretch import ORTHO_HIGH_PERCENT, ORTHO_LOW_PERCENT, StreamingStretch, Stretch

# ISIS special pixels (LIS, LRS, HIS, HRS besides NULL) are floats near -3.4e38: flags.
SPECIAL_MAGNITUDE = 1e30
STATISTICS_STRIP_BYTES = 4 * 1024 * 1024
BROWSE_STRIP_ROWS = 256
WINDOW_PIXELS = 1 << 20  # statistics read at most this many pixels a band at once


@dataclass(frozen=True)
class OutputBand:
    """One output band: sum of weight x input band (1-based band numbers)."""

    name: str
    terms: tuple[tuple[int, float], ...]

    @property
    def bands(self) -> tuple[int, ...]:
        return tuple(band for band, _ in self.terms)

    def values(self, data: Mapping[int, np.ndarray], valid: Mapping[int, np.ndarray]
               ) -> tuple[np.ndarray, np.ndarray]:
        """The channel in float32 and where it is valid (every band it uses is)."""
        first = self.terms[0][0]
        total = np.zeros(data[first].shape, dtype=np.float32)
        ok = np.ones(data[first].shape, dtype=bool)
        for band, weight in self.terms:
            total += np.float32(weight) * data[band]
            ok &= valid[band]
        return total, ok


IR = OutputBand("IR", ((1, 1.0),))
IRB_RED = OutputBand("RED", ((2, 1.0),))
BG = OutputBand("BG", ((3, 1.0),))
SYNTHETIC_BLUE = OutputBand("synthetic blue", ((3, hirise.SYNTHETIC_BLUE_BG),
                                            (2, hirise.SYNTHETIC_BLUE_RED)))
RED = OutputBand("RED", ((1, 1.0),))
# Product -> (the input mosaic it is made from, its bands).
PRODUCTS: dict[str, tuple[str, tuple[OutputBand, ...]]] = {
    "RED": ("RED", (RED,)),
    "IRB": ("IRB", (IR, IRB_RED, BG)),
    "RGB": ("IRB", (IRB_RED, BG, SYNTHETIC_BLUE)),
}
BAND_TEXT = {
    "RED": "1: RED (the RED CCDs)",
    "IRB": "1: IR, 2: RED, 3: BG (as the IRB mosaic; shown as red, green, blue)",
    "RGB": (f"1: RED, 2: BG, 3: synthetic blue = {hirise.SYNTHETIC_BLUE_BG:g} x BG - "
            f"{-hirise.SYNTHETIC_BLUE_RED:g} x RED (of the IRB mosaic, per pixel)"),
}


def make_nomap_extras(paths: Sequence[str | os.PathLike[str]], outdir: str | os.PathLike[str],
                      *, product_id: str | None, credit: Callable[[ProductSource], str],
                      keywords: Mapping[str, str], browse_width: int | None,
                      overwrite: bool, jpeg_quality: int,
                      report: Callable[[str], None] | None = None) -> list[Path]:
    """Write the NOMAP Extras of one observation's RED and/or IRB mosaics; return the paths.

    Every input is checked before anything is written; the files then appear all
    together with README.TXT, or not at all (the caller publishes them together).
    """
    with quiet_gdal():
        observation, inputs = open_inputs(paths, product_id)
        credits = {role: credit(src) for role, src in inputs.items()}  # a bad --credit: before writing
        read_readme(Path(outdir))  # an unreadable README.TXT stops the run before writing
        out = prepare_output_dir(outdir)
        made = [name for name, (role, _) in PRODUCTS.items() if role in inputs]
        width = browse_width or hirise.NOMAP_BROWSE_WIDTH
        paths_out = [out / f"{hirise.nomap_product_id(observation, name)}.{suffix}"
                     for name in made for suffix in hirise.NOMAP_SUFFIXES]
        entries = []
        shown = is_large(sum(s.width * s.height for s in inputs.values()), len(made))
        # Entered first: files in the way (without --overwrite) stop the run before the
        # statistics passes, not after them.
        with StagedOutputs(paths_out, overwrite) as staged:
            stretches = {role: input_stretches(src, _channels_of(role, made))
                         for role, src in inputs.items()}
            for done, name in enumerate(made, start=1):
                role, channels = PRODUCTS[name]
                src = inputs[role]
                bands = [stretches[role][c] for c in channels]
                pid = hirise.nomap_product_id(observation, name)
                write_nomap_jp2(src, channels, bands, staged.path(out / f"{pid}.JP2"))
                nomap_browse(src, channels, bands, width).save(  # one browse alive at a time
                    staged.path(out / f"{pid}.browse.jpg"), format="JPEG", quality=jpeg_quality)
                entries.append(nomap_entry(pid, name, src, bands, credits[role]))
                if shown:
                    advance(done, len(made), "products")
        readme = publish_readme(out, entries, dict(keywords))
    if report is not None:
        for role, src in inputs.items():
            report(f"{src.path}: taken as the {role} NOMAP mosaic of {observation} "
                   f"({src.kind_reason})")
    return [*paths_out, readme]


def _channels_of(role: str, made: Sequence[str]) -> list[OutputBand]:
    """Every distinct channel the products made from input ROLE need."""
    channels: list[OutputBand] = []
    for name in made:
        if PRODUCTS[name][0] == role:
            channels += [c for c in PRODUCTS[name][1] if c not in channels]
    return channels


# -- inputs --------------------------------------------------------------------------------

def open_inputs(paths: Sequence[str | os.PathLike[str]], product_id: str | None
                ) -> tuple[str, dict[str, ProductSource]]:
    """The observation ID and the RED and/or IRB mosaic by role, each checked."""
    if not 1 <= len(paths) <= 2:
        raise ParamsError(None, f"{param('kind', 'nomap')} takes one observation's RED and/or IRB NOMAP "
                                f"mosaic (got {len(paths)} files)")
    observation = _observation([Path(p) for p in paths], product_id)
    inputs: dict[str, ProductSource] = {}
    for path in map(Path, paths):
        role, src = _open_input(path, observation)
        if role in inputs:
            raise InputError(path, f"is a second {role} NOMAP mosaic (the first is "
                                   f"{inputs[role].path}); give one RED and one IRB")
        inputs[role] = src
    return observation, inputs


def _observation(paths: list[Path], product_id: str | None) -> str:
    """The observation ID: product_id, else the one every file name carries."""
    if product_id is not None:
        text = product_id.strip()
        if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_\-]*", text):
            raise ParamsError(None, f"{param('product_id', product_id)} is not usable in file names "
                                    "(letters, digits, '_' and '-' only)")
        return hirise.observation_in_name(text) or text
    found: dict[str, Path] = {}
    for path in paths:
        observation = hirise.observation_in_name(path.name)
        if observation is None:
            raise InputError(path, "names no HiRISE observation ID (like PSP_005000_1000); "
                                   f"give {param('product_id')}")
        found.setdefault(observation, path)
    if len(found) > 1:
        (a, pa), (b, pb) = list(found.items())[:2]
        raise InputError(pb, f"is of observation {b}, but {pa} is of {a}; give one "
                             "observation's mosaics")
    return next(iter(found))


def _open_input(path: Path, observation: str) -> tuple[str, ProductSource]:
    if not path.exists():
        raise InputError(path, "no such file")
    if not path.is_file():  # a FIFO would block GDAL for ever
        raise InputError(path, "cannot read (not a regular file)")
    from ..formats.jp2_header import decode_problem

    problem = decode_problem(path)
    if problem is not None:
        raise InputError(path, problem)
    try:
        with rasterio.open(path) as ds:
            count, dtype, nodata = ds.count, ds.dtypes[0], ds.nodata
            width, height = ds.width, ds.height
    except RasterioError:
        raise InputError(path, "not a raster GDAL can read") from None
    role, reason = _role(path, count)
    wanted = 1 if role == "RED" else 3
    if count != wanted:
        what = "a RED NOMAP mosaic has 1 band" if role == "RED" else (
            "an IRB NOMAP mosaic needs 3 (IR, RED, BG)")
        raise InputError(path, f"has {count} bands; {what}")
    if nodata is None and np.issubdtype(np.dtype(dtype), np.integer):
        nodata = float(hirise.CORE_NULL)  # HiRISE DN 0 is no data (CORE_NULL)
    return role, ProductSource(
        path=path, raster_path=path, label_path=None,
        product_id=hirise.nomap_product_id(observation, role), kind=NOMAP,
        width=width, height=height, band_count=count, dtype=dtype, crs=None,
        transform=Affine.identity(), nodata=nodata, special_dns=(), gdal_nodata=None,
        mission="hirise", title=observation, kind_reason=reason, georeferencing="none")


def _role(path: Path, bands: int) -> tuple[str, str]:
    """RED or IRB: from the file name (`..._IRB.NOMAP.cub`), else from the band count."""
    named = re.search(r"_(RED|IRB)(?![A-Z0-9])", path.name.upper())
    if named:
        return named.group(1), f"its name says {named.group(1)}"
    if bands == 1:
        return "RED", "one band"
    return "IRB", f"{bands} bands"


# -- statistics and rendering ---------------------------------------------------------------

def _read_bands(ds: rasterio.io.DatasetReader, bands: Sequence[int], window: Window
                ) -> tuple[dict[int, np.ndarray], dict[int, np.ndarray]]:
    """Float32 values and validity of BANDS in WINDOW (no data, NaN, ISIS specials invalid)."""
    dn = ds.read(list(bands), window=window, masked=True)
    return _split(np.ma.getdata(dn), np.ma.getmaskarray(dn), bands)


def _split(data: np.ndarray, mask: np.ndarray, bands: Sequence[int]
           ) -> tuple[dict[int, np.ndarray], dict[int, np.ndarray]]:
    values, valid = {}, {}
    for i, band in enumerate(bands):
        v = data[i].astype(np.float32)
        ok = ~mask[i] & np.isfinite(v) & (np.abs(v) < SPECIAL_MAGNITUDE)
        v[~ok] = 0.0
        values[band], valid[band] = v, ok
    return values, valid


def input_stretches(src: ProductSource, channels: Sequence[OutputBand]) -> dict[OutputBand, Stretch | None]:
    """Each channel's 0.1 % / 0.01 % stretch over the whole input, streamed in strips."""
    bands = sorted({b for c in channels for b in c.bands})
    stats = {c: StreamingStretch() for c in channels}
    with src.open() as ds, rasterio.Env(GDAL_CACHEMAX=streaming_cache_mb(ds)):
        for first_pass in (True, False):
            for window in bounded_windows(ds, STATISTICS_STRIP_BYTES, WINDOW_PIXELS):
                data, valid = _read_bands(ds, bands, window)
                for channel, stat in stats.items():
                    values, ok = channel.values(data, valid)
                    if first_pass:
                        stat.see_range(values[ok])
                    else:
                        stat.count(values[ok])
    return {c: s.stretch(ORTHO_LOW_PERCENT, ORTHO_HIGH_PERCENT) for c, s in stats.items()}


def render(data: Mapping[int, np.ndarray], valid: Mapping[int, np.ndarray],
           channels: Sequence[OutputBand], stretches: Sequence[Stretch | None]) -> np.ndarray:
    """8-bit (rows, cols) or (rows, cols, 3): each channel stretched and clipped, no data 0."""
    out = []
    for channel, stretch in zip(channels, stretches, strict=True):
        values, ok = channel.values(data, valid)
        if stretch is None:
            out.append(np.zeros(values.shape, dtype=np.uint8))
            continue
        out.append(np.where(ok, stretch.apply(values), 0).astype(np.uint8))
    return out[0] if len(out) == 1 else np.dstack(out)


def write_nomap_jp2(src: ProductSource, channels: Sequence[OutputBand],
                    stretches: Sequence[Stretch | None], path: str | os.PathLike[str]) -> None:
    """The product at full scale, 8 bits per band, lossy as the QLOOK.JP2 (no GeoJP2: no map)."""
    settings = replace(choose_settings(src.height, src.width), reversible=False,
                       compression_ratio=QLOOK_RATIO)
    tile_cols = settings.tile_shape[1]
    bands = sorted({b for c in channels for b in c.bands})
    with src.open() as ds, rasterio.Env(GDAL_CACHEMAX=streaming_cache_mb(ds)):
        def tile_row(first: int, count: int) -> np.ndarray:
            parts = []
            for left in range(0, src.width, tile_cols):
                window = Window(left, first, min(tile_cols, src.width - left), count)
                data, valid = _read_bands(ds, bands, window)
                parts.append(render(data, valid, channels, stretches))
            return np.concatenate(parts, axis=1)

        write_jp2(Path(path), src.height, src.width, len(channels), 8, tile_row,
                  settings=settings)


def nomap_browse(src: ProductSource, channels: Sequence[OutputBand],
                 stretches: Sequence[Stretch | None], width: int) -> Image.Image:
    """The browse: `width` wide (never wider than the mosaic), GDAL-averaged, same stretch.

    Made BROWSE_STRIP_ROWS browse rows at a time (each from the source rows it
    covers, rounded to whole rows), so the float temporaries of a 2048 x 6144
    browse never exist at once.
    """
    grid = preview_grid(src, width)
    bands = sorted({b for c in channels for b in c.bands})
    shape = (grid.height, grid.width) + ((len(channels),) if len(channels) > 1 else ())
    image = np.zeros(shape, dtype=np.uint8)  # filled in place: one copy of the browse
    with src.open((grid.height, grid.width)) as ds:
        scale_y = ds.height / grid.height
        for first in range(0, grid.height, BROWSE_STRIP_ROWS):
            rows = min(BROWSE_STRIP_ROWS, grid.height - first)
            top, bottom = round(first * scale_y), round((first + rows) * scale_y)
            window = Window(0, top, ds.width, max(1, bottom - top))
            reduced = ds.read(bands, window=window, out_shape=(len(bands), rows, grid.width),
                              resampling=Resampling.average, masked=True)
            data, valid = _split(np.ma.getdata(reduced), np.ma.getmaskarray(reduced), bands)
            image[first:first + rows] = render(data, valid, channels, stretches)
    return Image.fromarray(image, "L" if image.ndim == 2 else "RGB")


# -- README.TXT -----------------------------------------------------------------------------

def nomap_entry(pid: str, name: str, src: ProductSource, stretches: Sequence[Stretch | None],
                credit: str) -> Entry:
    """README.TXT's entry of one NOMAP product."""
    _, channels = PRODUCTS[name]
    points = "; ".join(
        f"{c.name} {s.low:.5g} .. {s.high:.5g}" if s is not None else f"{c.name} no valid data"
        for c, s in zip(channels, stretches, strict=True))
    nodata = "no no-data value" if src.nodata is None else (
        f"DN {src.nodata:.10g} (black in the previews)")
    return {**empty_entry(), "product_id": pid, "title": "",
            "kind_text": NOMAP_TYPE, "file_name": src.path.name,
            "size": f"{src.width} samples x {src.height} lines x {len(channels)} "
                    f"band{'s' if len(channels) > 1 else ''}",
            "bands": BAND_TEXT[name],
            "stretch": f"{points} (input values to 0 and 255)",
            "projection": "none (NOMAP: the camera's geometry, see below)",
            "nodata": nodata, "credit": credit}


__all__ = ["make_nomap_extras", "open_inputs", "input_stretches", "render", "PRODUCTS",
           "SYNTHETIC_BLUE"]
