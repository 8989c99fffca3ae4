"""Extras of the four HRSC-AX products: DEM greyscale, shaded relief and colour heights; pan,
RGB and CIR browses (colour for the composites, bands in their order); README.TXT saying
what the heights are above."""

from __future__ import annotations

import numpy as np
from PIL import Image

from pdsgen import write_dtm, write_ortho
from pdsgen.extras import make_extras

from hrsc_ax_tiles import dtm_group, map_group, tile_name, write_vicar

LINES, SAMPLES = 240, 320


def _tile(tmp_path):
    stem = tile_name(430, 8765, 1000, 0.2)
    rows, cols = np.mgrid[0:LINES, 0:SAMPLES]
    heights = (200 + 80 * np.sin(rows / 30.0) * np.cos(cols / 40.0)).astype(np.float32)
    dem = write_vicar(tmp_path / f"{stem}.dsm", heights, {
        "MAP": map_group(430000.0, 8765000.0, 0.5),
        "DIGITAL_TERRAIN_MODEL": dtm_group(0.0, 1.0, -100.0, 1500.0)})
    texture = (60 + (rows + cols) % 120).astype(np.uint8)
    channels = {}
    # One channel bright, the others dark: the browse must show the bright one as its own colour.
    for extension, level in (("pan", 1.0), ("re", 1.0), ("gr", 0.2), ("bl", 0.2),
                             ("cir_re", 0.2), ("cir_gr", 0.2), ("cir_bl", 1.0)):
        data = np.clip(texture * level + (150 if level == 1.0 else 0), 1, 254).astype(np.uint8)
        channels[extension] = write_vicar(tmp_path / f"{stem}.{extension}", data,
                                          {"MAP": map_group(430000.0, 8765000.0, 0.2)})
    return dem, channels


def test_extras_for_all_four_products(tmp_path):
    dem, ch = _tile(tmp_path)
    out = tmp_path / "out"
    products = [write_dtm(dem, out, profile="hrsc-ax").path]
    for inputs in ([ch["pan"]], [ch["re"], ch["gr"], ch["bl"]], [ch["cir_re"], ch["cir_gr"], ch["cir_bl"]]):
        products.append(write_ortho(inputs if len(inputs) > 1 else inputs[0], out, profile="hrsc-ax").label_path)
    written = {p.name for p in make_extras(products, tmp_path / "extras", browse_width=200)}
    dem_id = products[0].stem
    for suffix in ("br", "ab", "th", "sb", "sa", "st", "cb", "ca", "ct"):
        assert f"{dem_id}.{suffix}.jpg" in written
    for kind in ("PAN", "RGB", "CIR"):
        product_id = f"HRSCAX_430_8765_0_2X0_2KM_{kind}"
        assert {f"{product_id}.browse.jpg", f"{product_id}.thumb.jpg", f"{product_id}.abrowse.jpg"} <= written
    rgb = np.asarray(Image.open(tmp_path / "extras" / "HRSCAX_430_8765_0_2X0_2KM_RGB.browse.jpg").convert("RGB"),
                     dtype=float).reshape(-1, 3).mean(axis=0)
    assert rgb[0] > rgb[1] + 40 and rgb[0] > rgb[2] + 40  # red channel first: the browse is red
    cir = np.asarray(Image.open(tmp_path / "extras" / "HRSCAX_430_8765_0_2X0_2KM_CIR.browse.jpg").convert("RGB"),
                     dtype=float).reshape(-1, 3).mean(axis=0)
    assert cir[2] > cir[0] + 40 and cir[2] > cir[1] + 40  # the bright .cir_bl is shown blue
    readme = (tmp_path / "extras" / "README.TXT").read_text()
    assert "6378.14 x 6356.75 km ellipsoid" in readme and "+36.5 m" in readme
