"""Synthetic Mars terrain for the demo and for tests: craters on rough ground.

Deterministic (seeded), generated in memory at run time; nothing large is ever
committed to the repository.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import rasterio
from affine import Affine
from rasterio.crs import CRS

MARS_SPHERE_RADIUS = 3396190.0
DEMO_CRS = CRS.from_proj4(f"+proj=eqc +lat_ts=-5 +lat_0=0 +lon_0=180 +R={MARS_SPHERE_RADIUS:.0f} +units=m +no_defs")


@dataclass(frozen=True)
class SyntheticScene:
    elevation: np.ndarray  # float32 metres, NaN where missing
    reflectance: np.ndarray  # float32 I/F, NaN where missing
    transform: Affine
    crs: CRS


def fractal_surface(shape: tuple[int, int], rng: np.random.Generator, beta: float = 3.2) -> np.ndarray:
    """Rough ground: noise with a power-law spectrum (steeper beta = smoother)."""
    rows, cols = shape
    fy = np.fft.fftfreq(rows)[:, None]
    fx = np.fft.rfftfreq(cols)[None, :]
    radius = np.hypot(fx, fy)
    radius[0, 0] = 1.0
    spectrum = (rng.normal(size=radius.shape) + 1j * rng.normal(size=radius.shape)) / radius ** (beta / 2)
    spectrum[0, 0] = 0.0
    surface = np.fft.irfft2(spectrum, s=shape)
    return (surface / surface.std()).astype(np.float32)


def add_craters(height: np.ndarray, rng: np.random.Generator, count: int, pixel: float) -> None:
    """Simple bowl craters with raised rims and ejecta, sizes from a power law."""
    rows, cols = height.shape
    diameters = np.clip((rng.pareto(1.6, count) + 1.0) * 30.0, 20.0, min(rows, cols) * 0.45)
    for diameter in diameters:
        radius = diameter / 2.0 / pixel
        cy, cx = rng.uniform(0, rows), rng.uniform(0, cols)
        extent = int(radius * 2.5) + 2
        y0, y1 = max(0, int(cy) - extent), min(rows, int(cy) + extent)
        x0, x1 = max(0, int(cx) - extent), min(cols, int(cx) + extent)
        if y0 >= y1 or x0 >= x1:
            continue
        yy, xx = np.mgrid[y0:y1, x0:x1]
        r = np.hypot(yy - cy, xx - cx) / radius
        depth = 0.2 * diameter
        bowl = np.where(r < 1.0, depth * (r**2 - 1.0), 0.0)
        rim = 0.04 * diameter * np.exp(-((r - 1.0) / 0.18) ** 2)
        ejecta = np.where(r > 1.0, 0.03 * diameter * r ** -3.0, 0.0)
        height[y0:y1, x0:x1] += (bowl + rim + ejecta).astype(np.float32)


def correlation_holes(shape: tuple[int, int], rng: np.random.Generator, count: int) -> np.ndarray:
    """Irregular missing-data blobs, where stereo matching failed."""
    rows, cols = shape
    yy, xx = np.ogrid[:rows, :cols]
    mask = np.zeros(shape, dtype=bool)
    for _ in range(count):
        cy, cx = rng.uniform(0.1, 0.9) * rows, rng.uniform(0.1, 0.9) * cols
        ry, rx = rng.uniform(8, 40), rng.uniform(8, 40)
        mask |= ((yy - cy) / ry) ** 2 + ((xx - cx) / rx) ** 2 < 1.0
    return mask


def ragged_edge(shape: tuple[int, int], rng: np.random.Generator) -> np.ndarray:
    """The no-data collar along the left edge of a map-projected strip."""
    rows, cols = shape
    edge = (np.abs(rng.normal(size=rows).cumsum()) % 40.0 + 5).astype(int)
    return np.arange(cols)[None, :] < edge[:, None]


def make_scene(width: int = 2000, height: int = 3000, pixel: float = 1.0, seed: int = 2026) -> SyntheticScene:
    """A Mars DTM and a matching orthoimage (equirectangular, centre latitude -5)."""
    rng = np.random.default_rng(seed)
    shape = (height, width)
    rows = np.linspace(0.0, 1.0, height, dtype=np.float32)[:, None]
    cols = np.linspace(0.0, 1.0, width, dtype=np.float32)[None, :]
    elevation = -4250.0 + 60.0 * rows - 35.0 * cols + 9.0 * fractal_surface(shape, rng)
    elevation = elevation.astype(np.float32)
    add_craters(elevation, rng, count=140, pixel=pixel)
    edge = ragged_edge(shape, rng)
    holes = correlation_holes(shape, rng, count=6)
    slope_y, slope_x = np.gradient(elevation, pixel)
    shade = np.clip((slope_x - slope_y) / np.sqrt(2.0) * -0.6 + 0.7, 0.05, 1.0)
    albedo = 0.16 + 0.03 * fractal_surface(shape, rng, beta=2.4)
    reflectance = np.clip(albedo * shade, 0.01, 0.4).astype(np.float32)
    elevation[edge | holes] = np.nan
    reflectance[edge] = np.nan  # the orthoimage has no correlation holes
    # Upper-left corner on whole metres, near 9.5 S, 283.3 E.
    ulx = round(MARS_SPHERE_RADIUS * np.radians(283.3 - 180.0) * np.cos(np.radians(-5.0)))
    uly = round(MARS_SPHERE_RADIUS * np.radians(-9.5))
    transform = Affine(pixel, 0.0, float(ulx), 0.0, -pixel, float(uly))
    return SyntheticScene(elevation, reflectance, transform, DEMO_CRS)


def write_geotiff(
    path: str | os.PathLike[str], data: np.ndarray, transform: Affine, crs: CRS, nodata: float | None
) -> Path:
    """A tiled, compressed GeoTIFF (single band or bands-first stack)."""
    bands = data if data.ndim == 3 else data[None]
    profile = {
        "driver": "GTiff", "width": bands.shape[2], "height": bands.shape[1], "count": bands.shape[0],
        "dtype": bands.dtype.name, "crs": crs, "transform": transform, "nodata": nodata,
        "tiled": True, "blockxsize": 256, "blockysize": 256, "compress": "deflate",
    }
    with rasterio.open(path, "w", **profile) as dataset:
        dataset.write(bands)
    return Path(path)
