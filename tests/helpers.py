"""Builders for small test rasters written with real GDAL (rasterio)."""

from __future__ import annotations

import os
import pty
import subprocess
import sys
from pathlib import Path

import numpy as np
import rasterio
from affine import Affine

MARS_R = 3396190.0
CRS_EQUIRECTANGULAR = f"+proj=eqc +lat_ts=-5 +lat_0=0 +lon_0=180 +R={MARS_R:.0f} +units=m +no_defs"
CRS_SOUTH_POLAR = f"+proj=stere +lat_0=-90 +lon_0=0 +k=1 +x_0=0 +y_0=0 +R={MARS_R:.0f} +units=m +no_defs"
CRS_SINUSOIDAL = f"+proj=sinu +lon_0=30 +x_0=0 +y_0=0 +R={MARS_R:.0f} +units=m +no_defs"

# Upper-left corners (projection metres) that put each test raster somewhere plausible.
ORIGINS = {
    "equirectangular": (CRS_EQUIRECTANGULAR, Affine(1.0, 0, 6123456.0, 0, -1.0, -563210.0)),
    "polar": (CRS_SOUTH_POLAR, Affine(2.0, 0, -150000.0, 0, -2.0, 250000.0)),
    "sinusoidal": (CRS_SINUSOIDAL, Affine(5.0, 0, 850000.0, 0, -5.0, 1200000.0)),
}


def elevation_array(height: int, width: int, seed: int = 1, dtype: str = "float32") -> np.ndarray:
    rng = np.random.default_rng(seed)
    base = np.linspace(-4000, -3000, width, dtype=np.float64)[None, :] + rng.normal(0, 25, (height, width))
    return base.astype(dtype)


def write_raster(path: Path, data: np.ndarray, crs: str | None, transform: Affine, nodata=None,
                 driver: str = "GTiff") -> Path:
    bands = data if data.ndim == 3 else data[None]
    with rasterio.open(
        path, "w", driver=driver, width=bands.shape[2], height=bands.shape[1], count=bands.shape[0],
        dtype=bands.dtype.name, crs=crs, transform=transform, nodata=nodata,
    ) as dataset:
        dataset.write(bands)
    return path


def run_cli(*args: str) -> subprocess.CompletedProcess:
    """Run `python -m pdsgen ARGS` in a fresh process, as a user would."""
    return subprocess.run([sys.executable, "-m", "pdsgen", *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def stderr_on_a_terminal(*args: str) -> tuple[int, str]:
    """Run `python -m pdsgen ARGS` with stderr on a pseudo-terminal (stdout piped), as a user
    at a terminal sees it: the exit status and what the terminal showed."""
    main, secondary = pty.openpty()
    process = subprocess.Popen([sys.executable, "-m", "pdsgen", *map(str, args)], stdout=subprocess.PIPE,
                               stderr=secondary)
    os.close(secondary)
    shown = bytearray()
    while True:
        try:
            chunk = os.read(main, 4096)
        except OSError:  # the process closed the terminal
            break
        if not chunk:
            break
        shown += chunk
    os.close(main)
    process.communicate()
    return process.returncode, shown.decode("ascii", "replace")


def stated_keywords(profile: str = "generic", mission: str = "hirise") -> dict[str, str]:
    """The identification keywords (pdsgen.params.IDENTIFICATION_KEYWORDS) `profile` leaves "UNK",
    stated as a producer's params file states them. A product made without them warns and validates
    with DLV-007 / DLV-008 (issues 44, 49), which is not what most tests look at.

    The values are a registered mission's, the profile `mission`'s (HiRISE's by default: the data
    dictionary knows its host and instrument names, so DICT-013 has nothing to say), and the demo's
    text for the two every profile leaves "UNK"; a keyword the profile states keeps its value."""
    from pdsgen.demo import DEMO_IDENTIFICATION
    from pdsgen.missions import get_mission
    from pdsgen.params import IDENTIFICATION_KEYWORDS

    made = get_mission(profile)
    written = {**(made.ortho_keywords or {}), **made.dtm_keywords}
    registered = {**get_mission(mission).dtm_keywords, **DEMO_IDENTIFICATION}
    return {keyword: registered[keyword] for keyword in IDENTIFICATION_KEYWORDS if written.get(keyword) == "UNK"}


def stated_params(folder: Path, profile: str = "generic") -> Path:
    """stated_keywords(profile) as a params file (folder/stated.toml), for the command line's --params."""
    path = folder / "stated.toml"
    path.write_text("".join(f'{keyword} = "{value}"\n' for keyword, value in stated_keywords(profile).items()))
    return path


# The PDS4 areas a PDS3 label naming no instrument and no target leaves unnamed: migrate writes
# "Unknown" there (it invents none) and validate says so, DLV-008 (issue 49) - a true finding.
UNNAMED = ("Observing_System_Component", "Target_Identification")


def assert_pds4_clean(label: Path, unnamed: tuple[str, ...] = ()) -> None:
    """The PDS4 label passes its XSD and Schematron and the PDS4 checks with no finding but
    DLV-008's, one for each area in `unnamed` (what its PDS3 source does not name)."""
    from pdsgen.validate.pds4.label_checks import validate_pds4

    findings = validate_pds4(label)
    assert [f for f in findings if f.rule != "DLV-008"] == []
    assert sorted(f.message.split(" name ")[0] for f in findings if f.rule == "DLV-008") == sorted(unnamed)


def small_pds4_dtm(root: Path, product_id: str):
    """A 12 x 16 DTM written with its PDS4 label under root/good: `.path` (the label) and
    `.text` (the label as written), the product the PDS4 schema tests edit copies of."""
    from types import SimpleNamespace

    from pdsgen import write_dtm

    crs, transform = ORIGINS["equirectangular"]
    source = write_raster(root / "dtm.tif", elevation_array(12, 16, seed=4), crs, transform, nodata=-9999.0)
    written = write_dtm(source, root / "good", product_id=product_id, label="pds4", params=stated_keywords())
    return SimpleNamespace(path=written.pds4_label_path, text=written.label_text)


def demo_products(root: Path, width: int = 240, height: int = 320) -> Path:
    """The demo's products at a small size in root/products: a HiRISE DTM and an orthoimage
    made on it (PDS3 and PDS4 labels, --label both), with their Extras in products/extras."""
    from pdsgen.extras import make_extras
    from pdsgen.products.dtm import write_dtm
    from pdsgen.products.ortho import write_ortho
    from pdsgen.synthetic import make_scene, write_geotiff

    scene = make_scene(width=width, height=height)
    (root / "in").mkdir()
    dtm_in = write_geotiff(root / "in" / "dtm.tif", scene.elevation, scene.transform, scene.crs, None)
    ortho_in = write_geotiff(root / "in" / "ortho.tif", scene.reflectance, scene.transform, scene.crs, None)
    products = root / "products"
    dtm = write_dtm(dtm_in, products, profile="hirise", source_product_ids=("PSP_008669_1705", "PSP_009025_1705"),
                    institution="U", label="both")
    ortho = write_ortho(ortho_in, products, profile="hirise", observation_id="PSP_008669_1705",
                        source_dtm_id=dtm.product_id, label="both")
    make_extras([dtm.path, ortho.label_path], products / "extras")
    return products
