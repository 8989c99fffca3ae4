"""iMars deliveries shaped like the real ones: the PVL objects, groups and keywords the
issue lists (from the real iMars files), the same producer/processing facts as GeoTIFF
metadata tags, and the footprint as a Shapefile beside the GeoJSON, read back by
GDAL/OGR (ogrinfo, when gdal-bin is installed) and by pyshp's reader.
"""

from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pvl
import pytest
import rasterio
import shapefile
from affine import Affine

from pdsgen.products.dtm import write_dtm

from helpers import elevation_array, write_raster

SOUTH_POLAR = "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +R=3396000 +units=m +no_defs"
EXPECTED = {
    ("ProductInfo", "Producer"): ("SoftwareName", "SoftwareVersion", "ProducerInstitutionName",
                                  "ProcessingOrganisation", "ContactPerson"),
    ("Image",): ("FileName", "Format", "Lines", "LineSample", "Band", "BitDepth", "DTMResolution", "Unit",
                 "NodataValue", "Projection"),
    ("DataProduct",): ("ID", "InstrumentHostName", "InstrumentHostID", "TargetName", "InstrumentName",
                       "InstrumentID", "ProcessingLevel", "ProductTypeName", "ProductTypeID", "DataSetName",
                       "ProcessingDate"),
    ("MapProjection",): ("MapProjectionType", "AAxisRadius", "CAxisRadius", "CenterLatitude", "CenterLongitude",
                         "MapScale", "MinimumLatitude", "MaximumLatitude", "MinimumLongitude", "MaximumLongitude"),
}
TAGS = {  # GeoTIFF tag -> (PVL path)
    "PRODUCER.INSTITUTION_NAME": ("ProductInfo", "Producer", "ProducerInstitutionName"),
    "PRODUCER.CONTACT_PERSON": ("ProductInfo", "Producer", "ContactPerson"),
    "PRODUCER.SOFTWARE_VERSION": ("ProductInfo", "Producer", "SoftwareVersion"),
    "PRODUCT.PROCESSING_DATE": ("DataProduct", "ProcessingDate"),
    "PRODUCT.TYPE_ID": ("DataProduct", "ProductTypeID"),
    "PRODUCT.INSTRUMENT_ID": ("DataProduct", "InstrumentID"),
}


@pytest.fixture
def delivery(tmp_path):
    heights = elevation_array(90, 70, seed=11)
    heights[:5, :] = np.nan
    heights[40:50, 30:40] = np.nan  # a hole in the valid data
    source = write_raster(tmp_path / "in.tif", heights, SOUTH_POLAR, Affine(100.0, 0, -20000.0, 0, -100.0, 150000.0))
    params = tmp_path / "p.toml"
    params.write_text('technical_contact = "J. Doe"\n[matcher_parameters]\nwindow = 11\nthreshold = 0.6\n')
    return write_dtm(source, tmp_path / "out", profile="imars", product_id="h0022_0000", precision=0.1, params=params)


def _at(label, path):
    for name in path:
        label = label[name]
    return label


def test_pvl_has_the_real_groups_and_keywords(delivery):
    label = pvl.load(str(delivery.pvl_path))
    for path, keys in EXPECTED.items():
        missing = [key for key in keys if key not in _at(label, path)]
        assert missing == [], (path, missing)
    assert label["MapProjection"]["AAxisRadius"].units == "km"
    assert dict(label["Algorithm"])["window"] == 11
    assert label["ProductInfo"]["Producer"]["ContactPerson"] == "J. Doe"


def test_geotiff_tags_carry_the_same_facts(delivery):
    label = pvl.load(str(delivery.pvl_path))
    with rasterio.open(delivery.tiff_path) as tiff:
        tags = tiff.tags()
    for tag, path in TAGS.items():
        assert tags[tag] == str(_at(label, path)), tag


def _rings_area(shape) -> float:
    points = np.array(shape.points)
    total = 0.0
    for start, end in zip(shape.parts, list(shape.parts[1:]) + [len(points)], strict=True):
        x, y = points[start:end, 0], points[start:end, 1]
        total += 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return total


def test_footprint_shapefile_beside_the_geojson(delivery):
    folder = delivery.footprint_path.parent
    parts = sorted(p.suffix for p in folder.glob("h0022_0000.*") if p.suffix != ".geojson")
    assert parts == [".dbf", ".prj", ".qpj", ".shp", ".shx"]
    assert all(path in delivery.files for path in delivery.shapefile_paths)
    features = json.loads(delivery.footprint_path.read_text())["features"]
    with shapefile.Reader(str(folder / "h0022_0000.shp")) as reader:
        assert len(reader) == len(features) == 1
        record, shape = reader.record(0), reader.shape(0)
        assert record["PRODUCT_ID"] == "h0022_0000_da4" and record["TYPE"] == "DTM"
        assert len(shape.parts) == 2  # the outline and the hole
        geojson = features[0]["geometry"]["coordinates"]
        outer = np.array(geojson[0])
        bbox = [outer[:, 0].min(), outer[:, 1].min(), outer[:, 0].max(), outer[:, 1].max()]
        np.testing.assert_allclose(shape.bbox, bbox, atol=1e-9)
        # outer ring clockwise (negative shoelace area), hole counter-clockwise, as the format wants
        assert _rings_area(shape) < 0
    assert "3396000" in (folder / "h0022_0000.prj").read_text()  # longitude/latitude on the Mars sphere


@pytest.mark.skipif(shutil.which("ogrinfo") is None, reason="GDAL's ogrinfo (gdal-bin) is not installed")
def test_ogr_reads_the_shapefile(delivery):
    shp = delivery.footprint_path.with_suffix(".shp")
    result = subprocess.run(["ogrinfo", "-ro", "-al", "-so", str(shp)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert "Geometry: Polygon" in result.stdout and "Feature Count: 1" in result.stdout
    assert "PRODUCT_ID: String (40.0)" in result.stdout
    assert "3396000" in result.stdout  # the Mars sphere from the .prj
