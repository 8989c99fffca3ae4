"""Small georeferenced rasters for the Extras tests, written with real GDAL drivers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import rasterio
from rasterio.transform import from_origin

# A Mars equirectangular CRS (sphere 3396190 m, standard parallel 0).
MARS_EQC = (
    'PROJCS["Mars equirectangular",GEOGCS["Mars",DATUM["D_Mars",SPHEROID["Mars",3396190,0]],'
    'PRIMEM["Reference_Meridian",0],UNIT["degree",0.0174532925199433]],'
    'PROJECTION["Equirectangular"],PARAMETER["standard_parallel_1",0],'
    'PARAMETER["central_meridian",0],PARAMETER["false_easting",0],'
    'PARAMETER["false_northing",0],UNIT["metre",1]]'
)
MARS_NORTH_POLAR = (
    'PROJCS["Mars north polar stereographic",GEOGCS["Mars",DATUM["D_Mars",'
    'SPHEROID["Mars",3376200,0]],PRIMEM["Reference_Meridian",0],'
    'UNIT["degree",0.0174532925199433]],PROJECTION["Polar_Stereographic"],'
    'PARAMETER["latitude_of_origin",90],PARAMETER["central_meridian",0],'
    'PARAMETER["scale_factor",1],PARAMETER["false_easting",0],'
    'PARAMETER["false_northing",0],UNIT["metre",1]]'
)


def crater_field(height: int, width: int, seed: int = 1) -> np.ndarray:
    """Elevations (m) of a sloping plain with a few bowl-shaped craters."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[0:height, 0:width].astype(np.float32)
    z = -4000.0 + 0.05 * cols + 0.02 * rows
    for _ in range(6):
        cr, cc = rng.uniform(0, height), rng.uniform(0, width)
        radius = rng.uniform(0.05, 0.2) * min(height, width)
        d = np.hypot(rows - cr, cols - cc) / radius
        z -= np.where(d < 1.0, 30.0 * (1.0 - d**2), 0.0)
    return z.astype(np.float32)


def write_geotiff(path: Path, data: np.ndarray, *, crs: str = MARS_EQC, pixel: float = 2.0,
                  origin: tuple[float, float] = (100000.0, 50000.0),
                  nodata: float | None = None, driver: str = "GTiff", **options) -> Path:
    """Write a 2-D (one band) or 3-D (bands first) array as a georeferenced raster."""
    bands = data if data.ndim == 3 else data[None]
    profile = {"driver": driver, "width": bands.shape[2], "height": bands.shape[1],
               "count": bands.shape[0], "dtype": bands.dtype.name, "crs": crs,
               "transform": from_origin(origin[0], origin[1], pixel, pixel), **options}
    if nodata is not None:
        profile["nodata"] = nodata
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(bands)
    return path
