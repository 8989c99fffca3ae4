"""`pdsgen mosaic`: pixel for pixel what `gdal_merge.py -n ND -a_nodata ND -init ND` makes from the
same inputs (gdal_merge.py run as the reference), written as each profile's product and read
back by GDAL, OGR, pyshp and pvl; refusals in one line with nothing written."""

from __future__ import annotations

import json
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pvl
import pytest
import rasterio
from affine import Affine
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from pdsgen.mosaic import write_mosaic

from helpers import CRS_EQUIRECTANGULAR, CRS_SOUTH_POLAR, run_cli, stated_keywords, write_raster

pytestmark = pytest.mark.skipif(shutil.which("gdal_merge.py") is None, reason="needs GDAL's gdal_merge.py")

PIXEL = 50.0
FLOAT_ND = -3.4028234663852886e38
KINDS = {"int16": -32768, "uint8": 0, "float32": FLOAT_ND}


def _strip_values(rng, dtype: str, lines: int, samples: int) -> np.ndarray:
    if dtype == "uint8":
        return rng.integers(1, 256, (lines, samples)).astype(np.uint8)
    heights = -3000 + np.cumsum(rng.normal(0, 20, (lines, samples)), axis=1)
    return heights.astype(np.float32) if dtype == "float32" else np.rint(heights).astype(np.int16)


def make_strips(folder: Path, dtype: str, count: int = 4, seed: int = 7, crs: str = CRS_SOUTH_POLAR) -> list[Path]:
    """Overlapping strips on one grid, each with ragged left/right edges and a hole of no-data."""
    rng = np.random.default_rng(seed)
    nodata = KINDS[dtype]
    paths = []
    for index in range(count):
        lines, samples = 40 + 5 * index, 30 - 2 * index
        data = _strip_values(rng, dtype, lines, samples)
        for row in range(lines):
            data[row, : rng.integers(0, 6)] = nodata
            data[row, samples - rng.integers(0, 6):] = nodata
        data[8:14, 10:16] = nodata  # a hole: what lies below must show through
        transform = Affine(PIXEL, 0, -200000.0 + PIXEL * 13 * index, 0, -PIXEL, 150000.0 - PIXEL * 7 * index)
        path = folder / f"h{1000 + index}_0000_{dtype}.tif"
        paths.append(write_raster(path, data, crs, transform, nodata=nodata))
    return paths


def gdal_merge(paths: list[Path], nodata: float, out: Path) -> Path:
    subprocess.run(["gdal_merge.py", "-q", "-o", str(out), "-n", repr(nodata), "-a_nodata", repr(nodata),
                    "-init", repr(nodata), *map(str, paths)], check=True, capture_output=True)
    return out


def read(path: Path) -> tuple[np.ndarray, Affine, float | None]:
    with rasterio.open(path) as dataset:
        return dataset.read(1), dataset.transform, dataset.nodata


@pytest.mark.parametrize("order", ["given", "reverse"])
@pytest.mark.parametrize("dtype", ["int16", "float32"])
def test_generic_dtm_equals_gdal_merge_and_validates(tmp_path, dtype, order):
    strips = make_strips(tmp_path, dtype)
    nodata = KINDS[dtype]
    stacked = strips if order == "given" else strips[::-1]
    reference, ref_transform, _ = read(gdal_merge(stacked, nodata, tmp_path / "merged.tif"))
    product = write_mosaic(strips, tmp_path / "out", product_id="TEST_MOSAIC", kind="dtm", order=order,
                           params=stated_keywords())
    heights, transform, missing = read(product.path)  # GDAL's PDS driver reads the .IMG
    assert transform == ref_transform and heights.shape == reference.shape
    assert np.array_equal(heights == missing, reference == nodata)
    valid = reference != nodata
    assert np.array_equal(heights[valid], reference[valid].astype(np.float32))
    result = run_cli("validate", product.path)
    assert result.returncode == 0 and "0 error(s), 0 warning(s)" in result.stdout, result.stdout
    label = product.path.read_bytes()[: product.records.label_bytes].decode("ascii")
    for strip in strips:
        assert strip.stem in label  # SOURCE_PRODUCT_ID names every source
    assert "Mosaic of 4 products" in label


def test_order_matters_and_equal_grids_put_the_later_on_top(tmp_path):
    base = np.full((20, 20), 5, np.int16)
    top = np.full((20, 20), 9, np.int16)
    top[:, :10] = -32768  # no-data never covers data
    grid = Affine(PIXEL, 0, 1000.0, 0, -PIXEL, 2000.0)
    a = write_raster(tmp_path / "a.tif", base, CRS_SOUTH_POLAR, grid, nodata=-32768)
    b = write_raster(tmp_path / "b.tif", top, CRS_SOUTH_POLAR, grid, nodata=-32768)
    given = write_mosaic([a, b], tmp_path / "g", product_id="G", kind="dtm")
    reverse = write_mosaic([a, b], tmp_path / "r", product_id="R", kind="dtm", order="reverse")
    merged_given, _, _ = read(gdal_merge([a, b], -32768, tmp_path / "mg.tif"))
    merged_reverse, _, _ = read(gdal_merge([b, a], -32768, tmp_path / "mr.tif"))
    assert np.array_equal(read(given.path)[0], merged_given.astype(np.float32))
    assert np.array_equal(read(reverse.path)[0], merged_reverse.astype(np.float32))
    assert set(np.unique(merged_given)) == {5, 9} and set(np.unique(merged_reverse)) == {5}


@pytest.mark.parametrize("order", ["given", "reverse"])
def test_generic_ortho_jp2_equals_gdal_merge(tmp_path, order):
    strips = make_strips(tmp_path, "uint8")
    stacked = strips if order == "given" else strips[::-1]
    reference, ref_transform, _ = read(gdal_merge(stacked, 0, tmp_path / "merged.tif"))
    product = write_mosaic(strips, tmp_path / "out", product_id="ORTHO_MOSAIC", order=order, label="both")
    image, transform, _ = read(product.jp2_path)  # through GDAL's JPEG 2000 driver
    assert np.array_equal(image, reference)
    assert transform.almost_equals(ref_transform)
    label = pvl.load(str(product.label_path))  # "N/A" when a product has no sources: name each strip
    assert list(label["SOURCE_PRODUCT_ID"]) == [s.stem for s in stacked]  # bottom first
    assert "Mosaic of 4 products" in " ".join(product.label_path.read_text().split())


@pytest.fixture()
def imars_mosaic(tmp_path):
    dtm_strips = make_strips(tmp_path, "int16")
    ori_strips = make_strips(tmp_path, "uint8", seed=8)
    dtm = write_mosaic(dtm_strips, tmp_path / "out", profile="imars", product_id="sprc_mosaic", kind="dtm")
    ori = write_mosaic(ori_strips, tmp_path / "out", profile="imars", product_id="sprc_mosaic")
    return tmp_path, dtm_strips, ori_strips, dtm, ori


def test_imars_mosaic_equals_gdal_merge_with_pvl_naming_its_sources(imars_mosaic):
    tmp_path, dtm_strips, ori_strips, dtm, ori = imars_mosaic
    assert dtm.tiff_path.name == "sprc_mosaic_dtm.tif" and ori.tiff_path.name == "sprc_mosaic_ori.tif"
    for product, strips, nodata in ((dtm, dtm_strips, -32768), (ori, ori_strips, 0)):
        reference, ref_transform, _ = read(gdal_merge(strips, nodata, tmp_path / f"m{nodata}.tif"))
        values, transform, written_nodata = read(product.tiff_path)
        assert written_nodata == nodata and transform == ref_transform
        assert np.array_equal(values, reference)  # scale 1, offset 0: the DNs themselves
        metadata = pvl.load(str(product.pvl_path))
        assert list(metadata["ProductInfo"]["SourceProductId"]) == [s.stem for s in strips]
        assert metadata["Image"]["Lines"] == reference.shape[0]
        assert metadata["Image"]["Samples"] == reference.shape[1]
        assert metadata["Image"]["MosaicSourceCount"] == len(strips)
        assert "without resampling" in metadata["Image"]["MosaicMethod"]
    result = run_cli("validate", tmp_path / "out")
    assert result.returncode == 0 and " 0 error(s), 0 warning(s)" in result.stdout, result.stdout


def test_imars_footprint_has_one_polygon_per_source_inside_the_mosaic(imars_mosaic):
    tmp_path, dtm_strips, ori_strips, dtm, _ = imars_mosaic
    shp = tmp_path / "out" / "sprc_mosaic.shp"
    expected = sorted(s.stem for s in dtm_strips + ori_strips)
    ogr = subprocess.run(["ogrinfo", "-ro", "-al", "-q", str(shp)], capture_output=True, text=True, check=True)
    assert sorted(line.split("=")[1].strip() for line in ogr.stdout.splitlines()
                  if line.strip().startswith("PRODUCT_ID (String)")) == expected
    assert ogr.stdout.count("POLYGON") == len(expected)
    import shapefile

    with shapefile.Reader(str(shp)) as reader:
        ids = [record["PRODUCT_ID"] for record in reader.records()]
        shapes = reader.shapes()
    assert sorted(ids) == expected
    with rasterio.open(dtm.tiff_path) as mosaic:
        left, bottom, right, top = mosaic.bounds
        crs = mosaic.crs
    lonlat = CRS.from_wkt((tmp_path / "out" / "sprc_mosaic.prj").read_text())
    for shape in shapes:
        lon, lat = zip(*shape.points, strict=True)
        xs, ys = warp_transform(lonlat, crs, list(lon), list(lat))
        slack = 2 * PIXEL * 1.01  # the outline is traced on the source's own pixel edges
        assert min(xs) >= left - slack and max(xs) <= right + slack
        assert min(ys) >= bottom - slack and max(ys) <= top + slack
    collection = json.loads((tmp_path / "out" / "sprc_mosaic.geojson").read_text())
    assert sorted(f["id"] for f in collection["features"]) == expected
    collection["features"] = [f for f in collection["features"] if f["id"] != dtm_strips[1].stem]
    (tmp_path / "out" / "sprc_mosaic.geojson").write_text(json.dumps(collection))
    result = run_cli("validate", dtm.pvl_path)
    assert result.returncode == 1 and "IMARS-011" in result.stdout and dtm_strips[1].stem in result.stdout


def test_cli_mosaic_and_resampling_is_stated(tmp_path):
    strips = make_strips(tmp_path, "float32", count=2)
    shifted = tmp_path / "shifted.tif"
    with rasterio.open(strips[1]) as dataset:
        data, t = dataset.read(1), dataset.transform
    write_raster(shifted, data, CRS_SOUTH_POLAR, Affine(t.a, 0, t.c + 17.0, 0, t.e, t.f), nodata=FLOAT_ND)
    refused = run_cli("mosaic", strips[0], shifted, "-o", tmp_path / "no", "--product-id", "X", "--kind", "dtm")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1
    assert "not aligned" in refused.stderr and str(shifted) in refused.stderr and str(strips[0]) in refused.stderr
    assert "--resampling" in refused.stderr and not (tmp_path / "no").exists()
    done = run_cli("mosaic", strips[0], shifted, "-o", tmp_path / "yes", "--product-id", "RESAMPLED",
                   "--kind", "dtm", "--resampling", "bilinear")
    assert done.returncode == 0, done.stderr
    label = (tmp_path / "yes" / "RESAMPLED.IMG").read_bytes()[:20000].decode("ascii", "replace")
    assert "bilinear" in label


def _refusal(tmp_path, inputs, *extra) -> str:
    out = tmp_path / "refused"
    result = run_cli("mosaic", *inputs, "-o", out, "--product-id", "X", *extra)
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert not out.exists() or not any(out.iterdir())
    return result.stderr


def test_refusals_are_one_line_and_write_nothing(tmp_path):
    polar = make_strips(tmp_path, "float32", count=2)
    other = tmp_path / "eqc"
    other.mkdir()
    equirectangular = make_strips(other, "float32", count=1, crs=CRS_EQUIRECTANGULAR)
    assert "different CRS" in _refusal(tmp_path, [polar[0], equirectangular[0]], "--kind", "dtm")
    images = make_strips(other, "uint8", count=1)
    assert "a mosaic is of one kind" in _refusal(tmp_path, [polar[0], images[0]])
    unreadable = tmp_path / "broken.tif"
    unreadable.write_bytes(b"II*\x00 not really a TIFF")
    assert str(unreadable) in _refusal(tmp_path, [polar[0], unreadable], "--kind", "dtm")
    coarse = tmp_path / "coarse.tif"
    write_raster(coarse, np.zeros((5, 5), np.float32), CRS_SOUTH_POLAR,
                 Affine(2 * PIXEL, 0, -200000.0, 0, -2 * PIXEL, 150000.0), nodata=FLOAT_ND)
    assert "grids differ" in _refusal(tmp_path, [polar[0], coarse], "--kind", "dtm")


MEMORY_PROBE = """
import sys, tracemalloc
from pathlib import Path
from pdsgen.formats import raster
from pdsgen.mosaic import write_mosaic
raster.row_strips.__defaults__ = (2 ** 20,)  # strips of 1 MB: many of them at a test's size
paths = sorted(Path(sys.argv[1]).glob("*.tif"))
tracemalloc.start()
write_mosaic(paths, sys.argv[2], product_id="M", kind="dtm")
print(tracemalloc.get_traced_memory()[1])
"""


def test_memory_stays_flat_as_inputs_grow(tmp_path):
    """Strips stacked one below the other: 6 or 24 of them, the mosaic four times as tall; the
    peak of what Python and numpy hold stays that of a few strips of the output (strips of
    1 MB of input here, so that both mosaics are many strips tall; lines of 8,000 bytes, so
    that the label takes one record whatever its statistics and the writer never moves the data)."""
    peaks = {}
    for count in (6, 24):
        folder = tmp_path / f"in{count}"
        folder.mkdir()
        for index in range(count):
            data = np.full((400, 2000), index, np.int16)
            write_raster(folder / f"s{index:02d}.tif", data, CRS_SOUTH_POLAR,
                         Affine(PIXEL, 0, 0.0, 0, -PIXEL, -400 * PIXEL * index), nodata=-32768)
        probe = subprocess.run([sys.executable, "-c", MEMORY_PROBE, str(folder), str(tmp_path / f"out{count}")],
                               capture_output=True, text=True, check=True)
        peaks[count] = int(probe.stdout.strip())
    assert peaks[24] <= 1.1 * peaks[6] + 2**20, peaks
    assert peaks[24] < 24 * 2 ** 20, peaks  # the mosaic itself: 77 MB of float32


def test_a_mosaic_job_in_a_batch_takes_the_strips_its_after_jobs_made(tmp_path):
    """[[dtm]] strips, then a [[mosaic]] of their products (no inputs of its own: the products
    of the jobs it follows), then [[validate]] of it, on a real Dask cluster."""
    strips = make_strips(tmp_path, "float32", count=3)
    dtm_jobs = "".join(f'[[dtm]]\nid = "strip{n}"\ninput = "{path}"\nproduct_id = "STRIP_{n}"\n\n'
                       for n, path in enumerate(strips))
    manifest = tmp_path / "batch.toml"
    manifest.write_text(
        '[batch]\noutdir = "out"\n\n' + dtm_jobs
        + '[[mosaic]]\nid = "all"\nafter = ["strip0", "strip1", "strip2"]\nproduct_id = "ALL_STRIPS"\n'
          'outdir = "mosaic"\n\n'
          '[[validate]]\nafter = ["all"]\nformat = "json"\noutput = "reports/all.json"\n', encoding="utf-8")
    result = run_cli("batch", manifest, "--workers", "1", "-q")
    assert result.returncode == 0, result.stdout + result.stderr
    report = json.loads((tmp_path / "out" / "reports" / "all.json").read_text())
    assert report["summary"]["errors"] == 0
    reference, ref_transform, _ = read(gdal_merge(strips, FLOAT_ND, tmp_path / "merged.tif"))
    heights, transform, missing = read(tmp_path / "out" / "mosaic" / "ALL_STRIPS.IMG")
    assert transform == ref_transform
    assert np.array_equal(heights == missing, reference == FLOAT_ND)
    assert np.array_equal(heights[reference != FLOAT_ND], reference[reference != FLOAT_ND])


def test_hrsc_ax_tiles_become_one_area_product_equal_to_merging_their_own_products(tmp_path):
    """Two adjacent HRSC-AX DEM tiles (VICAR, written by the tests' own writer) read by the
    HRSC-AX reader: the mosaic equals gdal_merge.py of the two tiles' own `pdsgen dtm` products."""
    from hrsc_ax_tiles import dtm_group, map_group, tile_name, write_vicar

    lines, samples, pixel = 40, 48, 0.5
    tiles = []
    for index, east in enumerate((430000.0, 430000.0 + samples * pixel - 4 * pixel)):  # overlapping by 4
        stored = (np.arange(lines * samples, dtype=np.float32).reshape(lines, samples) * (index + 1)) % 997
        stored[3 + index, 7] = -32768.0
        tiles.append(write_vicar(tmp_path / f"{tile_name(430 + index, 8765, lines, pixel)}.dsm", stored, {
            "MAP": map_group(east, 8765000.0, pixel),
            "DIGITAL_TERRAIN_MODEL": dtm_group(100.0, 0.25, -500.0, 2000.0)}))
    singles = []
    for index, tile in enumerate(tiles):
        made = run_cli("dtm", tile, "-o", tmp_path / f"single{index}", "--profile", "hrsc-ax")
        assert made.returncode == 0, made.stderr
        singles.append(next((tmp_path / f"single{index}").glob("*.IMG")))
    with rasterio.open(singles[0]) as first:
        nodata = float(first.nodata)
    reference, ref_transform, _ = read(gdal_merge(singles, nodata, tmp_path / "merged.tif"))
    result = run_cli("mosaic", *tiles, "-o", tmp_path / "area", "--profile", "hrsc-ax", "--product-id", "HRSCAX_AREA")
    assert result.returncode == 0, result.stderr
    heights, transform, missing = read(tmp_path / "area" / "HRSCAX_AREA.IMG")
    assert transform == ref_transform and heights.shape == (lines, 2 * samples - 4)
    assert np.array_equal(heights == missing, reference == nodata)
    assert np.array_equal(heights[reference != nodata], reference[reference != nodata])


def test_imars_strips_with_a_scale_mosaic_to_the_same_heights(tmp_path):
    """Strips storing heights as DN * 0.5 + 0 (as an iMars strip of 0.5 m precision does): the
    mosaic's heights are gdal_merge.py's DNs times that scale, and it keeps the precision."""
    strips = make_strips(tmp_path, "int16", count=3)
    for strip in strips:
        with rasterio.open(strip, "r+") as dataset:
            dataset.scales = (0.5,)
            dataset.units = ("m",)
    reference, _, _ = read(gdal_merge(strips, -32768, tmp_path / "merged.tif"))
    product = write_mosaic(strips, tmp_path / "out", profile="imars", product_id="scaled")
    with rasterio.open(product.tiff_path) as dataset:
        dn, scale, offset = dataset.read(1), dataset.scales[0], dataset.offsets[0]
    assert scale == 0.5
    valid = reference != -32768
    assert np.array_equal(dn == -32768, ~valid)
    assert np.array_equal(dn[valid] * scale + offset, reference[valid] * 0.5)


def test_extras_and_deliver_take_a_mosaic_like_any_product(tmp_path):
    strips = make_strips(tmp_path, "int16", count=3)
    assert run_cli("mosaic", *strips, "--kind", "dtm", "--product-id", "SITE_MOSAIC", "-o",
                   tmp_path / "products").returncode == 0
    extras = run_cli("extras", tmp_path / "products" / "SITE_MOSAIC.IMG", "-o", tmp_path / "products", "-q")
    assert extras.returncode == 0, extras.stderr
    delivered = run_cli("deliver", tmp_path / "products", "--volume-id", "MOSAIC_0001", "-o", tmp_path / "vol", "-q")
    assert delivered.returncode == 0, delivered.stderr
    checked = run_cli("validate", tmp_path / "vol")
    assert checked.returncode == 0 and " 0 error(s)" in checked.stdout, checked.stdout
    assert (tmp_path / "vol" / "DATA" / "SITE_MOSAIC.IMG").exists()


def test_the_readme_examples_run_as_written(tmp_path):
    """README "Mosaics": each `pdsgen mosaic` line, run by the shell (its globs) on inputs made
    as a user would have them: iMars strips and site DTMs made by pdsgen, HRSC-AX tiles."""
    import docs_text

    from hrsc_ax_tiles import dtm_group, map_group, write_vicar
    body = docs_text.section("Mosaics")
    examples = [line for block in re.findall(r"```sh\n(.*?)```", body, re.S)
                for line in block.splitlines() if line.startswith("pdsgen ")]
    assert len(examples) == 4
    heights, images = make_strips(tmp_path, "float32", count=3), make_strips(tmp_path, "uint8", count=3)
    made = [(command, path, "--profile", "imars", "--product-id", f"h{1000 + n}_0000")
            for command, paths in (("dtm", heights), ("ortho", images)) for n, path in enumerate(paths)]
    made += [("dtm", path, "--product-id", f"SITE_{'ABC'[n]}") for n, path in enumerate(heights)]
    for command, *args in made:
        result = run_cli(command, *args, "-o", tmp_path)
        assert result.returncode == 0, result.stderr
    for east in (430, 435):
        write_vicar(tmp_path / f"{east}-8765_5.0x5.0km.dsm", np.full((50, 50), 7.0, np.float32),
                    {"MAP": map_group(east * 1000.0, 8765000.0, 100.0),
                     "DIGITAL_TERRAIN_MODEL": dtm_group(0.0, 1.0, -500.0, 2000.0)})
    for example in examples:
        command = f"{shlex.quote(sys.executable)} -m {example}"
        result = subprocess.run(command, shell=True, cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, f"{example}\n{result.stderr}"
    written = {p.name for p in (tmp_path / "out").iterdir()}
    assert {"sprc_mosaic_dtm.tif", "sprc_mosaic_ori.tif", "sprc_mosaic.shp", "SITE_MOSAIC.IMG",
            "SITE_MOSAIC.xml", "HRSCAX_AREA.IMG"} <= written


def _mosaic_options() -> set[str]:
    help_text = run_cli("mosaic", "--help").stdout
    return set(re.findall(r"(--[a-z][a-z-]+)", help_text))


def test_an_hrsc_refusal_names_an_option_of_mosaic_and_that_option_works(tmp_path):
    """HRSC strips not yet on the HRSC sphere and projection: the refusal the HRSC writer gives
    names an option `pdsgen mosaic` has, and with it the mosaic is warped as `pdsgen dtm` warps
    one strip (heights above the 3396.19 km sphere end 190 m higher above the 3396.0 km one)."""
    equirectangular = "+proj=eqc +lat_ts=0 +lon_0=0 +R=3396190 +units=m +no_defs"
    heights = np.full((30, 40), -1000.0, np.float32)
    strips = [write_raster(tmp_path / f"s{n}.tif", heights + 100 * n, equirectangular,
                           Affine(100.0, 0, 4000000.0 + 3000.0 * n, 0, -100.0, -1200000.0), nodata=FLOAT_ND)
              for n in range(2)]
    refused = _refusal(tmp_path, strips, "--profile", "hrsc", "--kind", "dtm")
    named = set(re.findall(r"(--[a-z][a-z-]+)", refused))
    assert named and named <= _mosaic_options(), refused
    done = run_cli("mosaic", *strips, "-o", tmp_path / "out", "--profile", "hrsc", "--product-id", "h0002_0001",
                   "--kind", "dtm", "--reproject", "--precision", "0.1")
    assert done.returncode == 0, done.stderr
    with rasterio.open(tmp_path / "out" / "h0002_0001_dt4.img") as out:
        assert out.crs.to_dict()["proj"] == "sinu"
        restored = out.read(1, masked=True) * out.scales[0] + out.offsets[0]
    assert restored.count() > 0 and abs(restored.min() - (-1000 + 190)) <= 1
    assert abs(restored.max() - (-900 + 190)) <= 1
    note = " ".join(str(pvl.load(str(tmp_path / "out" / "h0002_0001_dt4.img"))["IMAGE"]["NOTE"]).split())
    assert "Mosaic of 2 products" in note and "warped" in note and "without resampling" not in note


def test_a_dictionary_refusal_names_an_option_of_mosaic_and_that_option_works(tmp_path):
    strips = make_strips(tmp_path, "int16", count=2)
    params = tmp_path / "p.toml"
    params.write_text(f'producer_full_name = "{"A PRODUCER NAME LONGER THAN THE DICTIONARY ALLOWS " * 2}"\n')
    refused = _refusal(tmp_path, strips, "--kind", "dtm", "--params", params)
    named = set(re.findall(r"(--[a-z][a-z-]+)", refused))
    assert "PRODUCER_FULL_NAME" in refused and named and named <= _mosaic_options(), refused
    kept = run_cli("mosaic", *strips, "-o", tmp_path / "out", "--product-id", "KEPT", "--kind", "dtm",
                   "--params", params, "--allow-dictionary-deviations")
    assert kept.returncode == 0, kept.stderr
    assert "PRODUCER_FULL_NAME" in kept.stderr and (tmp_path / "out" / "KEPT.IMG").exists()


def test_an_hrsc_mosaic_takes_its_own_product_id_never_its_first_strips(tmp_path):
    """HRSC names a product by orbit and sequence; a mosaic given another ID is refused, not
    silently named after its first source strip (which would take that strip's own file name)."""
    sinusoidal = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"
    strips = [write_raster(tmp_path / f"h{1111 * (n + 1)}_0000_dt4.tif", np.full((20, 30), 100.0 * n, np.float32),
                           sinusoidal, Affine(50.0, 0, 4000000.0 + 1000.0 * n, 0, -50.0, 0.0), nodata=FLOAT_ND)
              for n in range(2)]
    refused = run_cli("mosaic", *strips, "-o", tmp_path / "no", "--profile", "hrsc", "--product-id", "MY_MOSAIC")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1, refused.stderr
    assert "--product-id" in refused.stderr and "--source-product-id" not in refused.stderr
    assert not (tmp_path / "no").exists() or not any((tmp_path / "no").iterdir())
    done = run_cli("mosaic", *strips, "-o", tmp_path / "yes", "--profile", "hrsc", "--product-id", "h3333_0000")
    assert done.returncode == 0, done.stderr
    assert [p.name for p in (tmp_path / "yes").glob("*.img")] == ["h3333_0000_dt4.img"]


@pytest.mark.parametrize("vicar_offsets", ["standard", "dlr"])
def test_an_hrsc_ax_area_says_what_its_tiles_products_say(tmp_path, vicar_offsets):
    """The area product's label says what each tile's own `pdsgen dtm` product says: that the
    heights are ellipsoid heights (not geoid), and how the VICAR offsets were read; with
    --vicar-offsets dlr the area lies where the tiles' own dlr products lie."""
    from hrsc_ax_tiles import dtm_group, map_group, tile_name, write_vicar

    lines, samples, pixel = 20, 24, 0.5
    tiles = [write_vicar(tmp_path / f"{tile_name(430 + n, 8765, lines, pixel)}.dsm",
                         np.full((lines, samples), 40.0 * (n + 1), np.float32),
                         {"MAP": map_group(430000.0 + n * samples * pixel, 8765000.0, pixel),
                          "DIGITAL_TERRAIN_MODEL": dtm_group(100.0, 0.25, -500.0, 2000.0)})
             for n in range(2)]
    single = run_cli("dtm", tiles[0], "-o", tmp_path / "single", "--profile", "hrsc-ax",
                     "--vicar-offsets", vicar_offsets)
    assert single.returncode == 0, single.stderr
    area = run_cli("mosaic", *tiles, "-o", tmp_path / "area", "--profile", "hrsc-ax", "--product-id", "AREA",
                   "--vicar-offsets", vicar_offsets)
    assert area.returncode == 0, area.stderr
    single_path = next((tmp_path / "single").glob("*.IMG"))
    area_path = tmp_path / "area" / "AREA.IMG"
    texts = [" ".join(path.read_bytes()[:30000].decode("ascii", "replace").split()) for path in (single_path,
                                                                                               area_path)]
    own_note = texts[0].split('NOTE = "', 1)[1].split('"', 1)[0]
    assert own_note.startswith("Pixel values are ellipsoid heights") and own_note in texts[1]
    offsets_comment = re.search(r"/\* The source tile's VICAR .*?\*/ /\*.*?\*/ /\*.*?\*/", texts[0])
    assert offsets_comment and ("DLR" in offsets_comment.group(0)) == (vicar_offsets == "dlr")
    assert offsets_comment.group(0) in texts[1]
    with rasterio.open(single_path) as one, rasterio.open(area_path) as both:
        assert both.transform == one.transform  # the first tile's corner is the area's
        assert float(both.read(1)[0, 0]) == float(one.read(1)[0, 0])


def test_an_hrsc_ax_colour_channel_is_refused_naming_the_file(tmp_path):
    """A mosaic takes HRSC-AX tiles of one file each (.dsm, .pan); one channel of an RGB tile is
    refused in one line that names it."""
    from hrsc_ax_tiles import map_group, write_vicar

    red = write_vicar(tmp_path / "430-8765_5.0x5.0km.re", np.full((10, 10), 7, np.uint8),
                      {"MAP": map_group(430000.0, 8765000.0, 500.0)})
    stderr = _refusal(tmp_path, [red], "--profile", "hrsc-ax")
    assert str(red) in stderr and ".pan" in stderr and ".dsm" in stderr


def test_an_hrsc_ax_area_refusal_names_the_users_tiles_not_temporary_files(tmp_path):
    from hrsc_ax_tiles import dtm_group, map_group, write_vicar

    tiles = [write_vicar(tmp_path / f"{east}-8765_5.0x5.0km.dsm", np.full((10, 10), -32768.0, np.float32),
                         {"MAP": map_group(east * 1000.0, 8765000.0, 500.0),
                          "DIGITAL_TERRAIN_MODEL": dtm_group(0.0, 1.0, -500.0, 2000.0)})
             for east in (430, 435)]
    stderr = _refusal(tmp_path, tiles, "--profile", "hrsc-ax")
    assert "no valid pixels" in stderr and all(str(tile) in stderr for tile in tiles)
    assert ".vrt" not in stderr


def _dem_xml(path: Path, offset: float) -> Path:
    path.write_text("<ImageLabel><DIGITAL_TERRAIN_MODEL>"
                    f"<DTM_OFFSET>{offset}</DTM_OFFSET><DTM_SCALING_FACTOR>0.25</DTM_SCALING_FACTOR>"
                    "<DTM_RANGE>(-500, 2000)</DTM_RANGE></DIGITAL_TERRAIN_MODEL></ImageLabel>")
    return path


def test_each_hrsc_ax_tile_takes_its_own_xml_image_label(tmp_path):
    """Tiles whose heights are scaled by the keywords of their own XML image labels: each tile of
    the area has the heights its own `pdsgen dtm --source-label` product has (the labels are
    given one per tile, in the tiles' order), and a count that does not match is refused."""
    from hrsc_ax_tiles import map_group, write_vicar

    tiles, labels = [], []
    for n, east in enumerate((430, 435)):
        tiles.append(write_vicar(tmp_path / f"{east}-8765_5.0x5.0km.dsm", np.full((10, 10), 40.0, np.float32),
                                 {"MAP": map_group(east * 1000.0, 8765000.0, 500.0)}))
        labels.append(_dem_xml(tmp_path / f"tile{n}.xml", 100.0 * (n + 1)))
    area = run_cli("mosaic", *tiles, "-o", tmp_path / "area", "--profile", "hrsc-ax", "--product-id", "AREA",
                   "--source-label", labels[0], "--source-label", labels[1])
    assert area.returncode == 0, area.stderr
    with rasterio.open(tmp_path / "area" / "AREA.IMG") as dataset:
        heights = dataset.read(1)
    for n, tile in enumerate(tiles):
        single = run_cli("dtm", tile, "-o", tmp_path / f"single{n}", "--profile", "hrsc-ax",
                         "--source-label", labels[n])
        assert single.returncode == 0, single.stderr
        with rasterio.open(next((tmp_path / f"single{n}").glob("*.IMG"))) as dataset:
            own = dataset.read(1)
        assert np.array_equal(heights[:, 10 * n: 10 * (n + 1)], own)  # 100 + 40 * 0.25, then 200 + ...
    stderr = _refusal(tmp_path, tiles, "--profile", "hrsc-ax", "--source-label", labels[0])
    assert "--source-label" in stderr and "2 tiles" in stderr


@pytest.mark.parametrize("kind", ["dtm", "ortho"])
def test_an_hrsc_mosaic_label_states_the_mosaic_and_its_resampling(tmp_path, kind):
    """HRSC's own DT4 and ND4 writers: the NOTE says the product is a mosaic of which sources and
    that they were resampled with the method asked for, as the generic label's NOTE does."""
    sinusoidal = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"
    values = (np.arange(600, dtype=np.float32).reshape(20, 30) % 97) + (0 if kind == "dtm" else 1)
    if kind == "ortho":
        values = (values / 100.0).astype(np.float32)
    strips = [write_raster(tmp_path / f"h{1111 * (n + 1)}_0000_x.tif", values, sinusoidal,
                           Affine(50.0, 0, 4000000.0 + 1017.0 * n, 0, -50.0, 0.0), nodata=FLOAT_ND)
              for n in range(2)]
    done = run_cli("mosaic", *strips, "-o", tmp_path / "out", "--profile", "hrsc", "--product-id", "h3333_0000",
                   "--kind", kind, "--resampling", "bilinear")
    assert done.returncode == 0, done.stderr
    product = next((tmp_path / "out").glob("*.img"))
    note = " ".join(str(pvl.load(str(product))["IMAGE"]["NOTE"]).split())
    assert "Mosaic of 2 products (h1111_0000_x, h2222_0000_x)" in note and "bilinear" in note


def test_an_inputs_own_no_data_never_covers_data_when_no_nodata_is_given(tmp_path):
    """Strips from two producers, no-data -32768 and -9999: without --nodata each strip's own
    no-data value is no data (never a height of -9999 m lying over the first strip's heights);
    with --nodata ND one value for all, as gdal_merge.py -n ND."""
    grid = Affine(PIXEL, 0, 1000.0, 0, -PIXEL, 2000.0)
    first = write_raster(tmp_path / "a.tif", np.full((10, 10), 5.0, np.float32), CRS_SOUTH_POLAR, grid,
                         nodata=-32768.0)
    top = np.full((10, 10), 9.0, np.float32)
    top[:, :5] = -9999.0
    second = write_raster(tmp_path / "b.tif", top, CRS_SOUTH_POLAR, grid, nodata=-9999.0)
    product = write_mosaic([first, second], tmp_path / "own", product_id="OWN", kind="dtm")
    heights, _, _ = read(product.path)
    assert np.array_equal(heights[:, :5], np.full((10, 5), 5.0)) and np.array_equal(heights[:, 5:], top[:, 5:])
    product = write_mosaic([first, second], tmp_path / "one", product_id="ONE", kind="dtm", nodata=-32768.0)
    reference, _, _ = read(gdal_merge([first, second], -32768.0, tmp_path / "merged.tif"))
    assert np.array_equal(read(product.path)[0], reference)  # -9999 is data to gdal_merge.py -n -32768
