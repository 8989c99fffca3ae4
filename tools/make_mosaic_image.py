"""Regenerate docs/images/mosaic_footprints.jpg: a mosaic's browse with its sources' footprints.

Cuts a synthetic south-polar terrain into eight overlapping int16 strips with ragged edges
(as HRSC strips are), mosaics them with the iMars profile (`<ID>_dtm.tif`, `.pvl`, footprint
GeoJSON + Shapefile), makes the mosaic's Extras, and draws each strip's footprint polygon
(read from the Shapefile with pyshp, projected back onto the mosaic's grid) over the
colour-coded browse, each labelled with its strip's product ID.

Run from the repository root: PYTHONPATH=src python tools/make_mosaic_image.py
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np
import rasterio
import shapefile
from affine import Affine
from PIL import Image, ImageDraw
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen.extras import make_extras
from pdsgen.mosaic import write_mosaic

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_readme_images import OUT, save_small  # noqa: E402

POLAR = "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +x_0=0 +y_0=0 +R=3396190 +units=m +no_defs"
PIXEL = 200.0
NODATA = -32768
COLOURS = ["#ffffff", "#111111", "#ff4040", "#40c0ff", "#ffe040", "#a040ff", "#40ff80", "#ff80c0"]


def terrain(lines: int, samples: int) -> np.ndarray:
    """Smooth heights: a polar dome cut by troughs, metres."""
    y, x = np.mgrid[0:lines, 0:samples] / 100.0
    return (2500 * np.exp(-((x - 4.5) ** 2 + (y - 3.2) ** 2) / 8) + 300 * np.sin(1.7 * x + 0.8 * y)
            - 400 * np.abs(np.sin(0.9 * x - 1.3 * y)) - 3000)


def make_strips(folder: Path) -> list[Path]:
    rng = np.random.default_rng(30)
    heights = terrain(640, 640)
    paths = []
    for index in range(8):
        top, left = 25 * (index % 3) + (index // 4) * 270, 130 * (index % 4) + 10 * (index // 4)
        lines, samples = 300, 150
        strip = np.rint(heights[top:top + lines, left:left + samples]).astype(np.int16)
        edge = np.cumsum(rng.integers(-1, 2, lines)) // 2
        columns = np.arange(samples)
        strip[(columns[None, :] < 8 + edge[:, None]) | (columns[None, :] > samples - 9 + edge[:, None])] = NODATA
        transform = Affine(PIXEL, 0, 20000.0 + left * PIXEL, 0, -PIXEL, 64000.0 - top * PIXEL)
        path = folder / f"h{5200 + 11 * index}_0000_da4.tif"
        with rasterio.open(path, "w", driver="GTiff", width=samples, height=lines, count=1, dtype="int16",
                           crs=POLAR, transform=transform, nodata=NODATA) as out:
            out.write(strip, 1)
        paths.append(path)
    return paths


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="pdsgen-mosaic-image-") as tmp:
        work = Path(tmp)
        strips = make_strips(work)
        product = write_mosaic(strips, work / "mosaic", profile="imars", product_id="sprc_mosaic", kind="dtm")
        make_extras([product.tiff_path], work / "extras", browse_width=720)
        browse = Image.open(next((work / "extras").glob("*.cb.jpg"))).convert("RGB")
        with rasterio.open(product.tiff_path) as mosaic:
            to_pixels, crs, width = ~mosaic.transform, mosaic.crs, mosaic.width
        scale = browse.width / width
        draw = ImageDraw.Draw(browse)
        lonlat = CRS.from_wkt((work / "mosaic" / "sprc_mosaic.prj").read_text())
        with shapefile.Reader(str(work / "mosaic" / "sprc_mosaic.shp")) as reader:
            for number, shape_record in enumerate(reader.iterShapeRecords()):
                shape = shape_record.shape
                lon, lat = zip(*shape.points, strict=True)
                xs, ys = warp_transform(lonlat, crs, list(lon), list(lat))
                points = [tuple(v * scale for v in to_pixels * xy) for xy in zip(xs, ys, strict=True)]
                colour = COLOURS[number % len(COLOURS)]
                for start, end in zip(shape.parts, [*shape.parts[1:], len(points)], strict=True):
                    draw.line(points[start:end], fill=colour, width=2)  # each ring on its own
                x, y = min(p[0] for p in points), min(p[1] for p in points)
                draw.text((x + 4, y + 4 + 12 * (number % 2)), shape_record.record["PRODUCT_ID"], fill=colour)
        save_small(browse, OUT / "mosaic_footprints.jpg")


if __name__ == "__main__":
    main()
