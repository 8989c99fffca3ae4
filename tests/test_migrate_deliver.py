"""`pdsgen deliver --pds4` on PDS3-only products: it migrates them itself (pdsgen migrate), the data
files unchanged, and the bundle validates (the shipped XSD + Schematron and pdsgen validate)."""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

import pytest
from affine import Affine

from pdsgen.extras import make_extras
from pdsgen.products.dtm import write_dtm
from pdsgen.products.ortho import write_ortho
from pdsgen.synthetic import make_scene, write_geotiff
from pdsgen.validate.pds4 import schematron
from pdsgen.validate.pds4.label_checks import validate_pds4

from helpers import elevation_array, run_cli, write_raster

needs_saxon = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")


@pytest.fixture(scope="module")
def pds3_only(tmp_path_factory) -> Path:
    """The demo's HiRISE DTM and orthoimage (with Extras) and an HRSC DT4, PDS3 labels only."""
    root = tmp_path_factory.mktemp("pds3_only")
    scene = make_scene(width=120, height=160)
    (root / "in").mkdir()
    dtm_in = write_geotiff(root / "in" / "dtm.tif", scene.elevation, scene.transform, scene.crs, None)
    ortho_in = write_geotiff(root / "in" / "ortho.tif", scene.reflectance, scene.transform, scene.crs, None)
    products = root / "products"
    dtm = write_dtm(dtm_in, products, profile="hirise", source_product_ids=("PSP_008669_1705", "PSP_009025_1705"),
                    institution="U")
    ortho = write_ortho(ortho_in, products, profile="hirise", observation_id="PSP_008669_1705",
                        source_dtm_id=dtm.product_id)
    make_extras([dtm.path, ortho.label_path], products / "extras")
    hrsc_in = write_raster(root / "in" / "hrsc.tif", elevation_array(40, 30, seed=2),
                           "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs",
                           Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0))
    write_dtm(hrsc_in, products, profile="hrsc", precision=0.05, product_id="h1234_0000")
    assert not list(products.glob("*.xml"))  # PDS3 only
    return products


def _digests(directory: Path) -> dict[str, str]:
    return {p.name: hashlib.md5(p.read_bytes()).hexdigest() for p in directory.iterdir()
            if p.suffix.upper() in (".IMG", ".JP2")}


@needs_saxon
def test_deliver_pds4_migrates_pds3_only_products_and_the_bundle_validates(pds3_only, tmp_path):
    source = tmp_path / "products"
    shutil.copytree(pds3_only, source)
    before = _digests(source)
    out = tmp_path / "bundle"
    made = run_cli("deliver", source, "--pds4", "-o", out, "--bundle-lid", "urn:nasa:pds:migrated_demo")
    assert made.returncode == 0, made.stderr
    assert "SKIPPED" not in made.stdout
    data = out / "DATA"
    labels = ["DTEEC_008669_1705_009025_1705_U01.xml", "PSP_008669_1705_RED_C_01_ORTHO.xml", "h1234_0000_dt4.xml"]
    assert _digests(data) == before  # the data files travel unchanged
    for name in labels:
        assert validate_pds4(data / name) == [], name
        assert "urn:nasa:pds:migrated_demo:data:" in (data / name).read_text()
    checked = run_cli("validate", out)
    assert checked.returncode == 0, checked.stdout
    assert " 0 error(s)" in checked.stdout
    assert "PDS4-" not in checked.stdout  # no finding on any PDS4 label
    assert not list(tmp_path.glob(".bundle.migrate-*"))  # the staged labels are gone
