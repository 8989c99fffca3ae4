"""A label is parsed once per `pdsgen deliver` run: the scan that groups the files into
products, the PDS4 labels migrated for PDS3-only products, the validation of the delivery
(each label's own checks and the DLV checks across them) and the review page all read it
from the run's label cache (label/read.py LabelCache), the hard-linked copy in the delivery
included."""

from __future__ import annotations

import re
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from pdsgen.deliver import make_delivery
from pdsgen.label import parser
from pdsgen.products.dtm import write_dtm
from pdsgen.products.ortho import write_ortho
from pdsgen.synthetic import make_scene, write_geotiff

TEMPLATE_ID = "DTEEC_008669_1705_009025_1705_U01"
COPY_ID = "DTEEC_000001_1705_009025_1705_U01"  # same length: the attached label's layout holds


@pytest.fixture(scope="module")
def products(tmp_path_factory) -> tuple[Path, list[str]]:
    """Two DTMs (attached labels) and an orthoimage (a detached .LBL and its JP2), PDS3 labels only."""
    root = tmp_path_factory.mktemp("parse-once")
    scene = make_scene(width=64, height=64)
    heights = (-4000.0 + np.arange(32 * 32, dtype="float32").reshape(32, 32)).astype("float32")
    dtm_in = write_geotiff(root / "dtm.tif", heights, scene.transform, scene.crs, None)
    ortho_in = write_geotiff(root / "ortho.tif", scene.reflectance, scene.transform, scene.crs, None)
    source = root / "products"
    dtm = write_dtm(dtm_in, source, profile="hirise", source_product_ids=("PSP_008669_1705", "PSP_009025_1705"),
                    institution="U", label="pds3")
    assert dtm.product_id == TEMPLATE_ID
    (source / f"{COPY_ID}.IMG").write_bytes(dtm.path.read_bytes().replace(TEMPLATE_ID.encode(), COPY_ID.encode()))
    ortho = write_ortho(ortho_in, source, profile="hirise", observation_id="PSP_008669_1705",
                        source_dtm_id=dtm.product_id, label="pds3")
    return source, [TEMPLATE_ID, COPY_ID, ortho.product_id]


def _count_parses(monkeypatch) -> Counter[str]:
    """Every parse of a label text by any module of pdsgen (each holds its own name for the
    parser's function), counted by the text."""
    parsed: Counter[str] = Counter()
    original = parser.parse_label

    def counting(text, *args, **kwargs):
        parsed[text] += 1
        return original(text, *args, **kwargs)

    for name, module in list(sys.modules.items()):
        if name.startswith("pdsgen") and getattr(module, "parse_label", None) is original:
            monkeypatch.setattr(module, "parse_label", counting)
    return parsed


@pytest.mark.parametrize("dialect", ["pds3", "both"])
def test_each_label_is_parsed_once_in_one_deliver_run(products, tmp_path, monkeypatch, dialect):
    import pdsgen.migrate.product  # noqa: F401  (loaded, so that its parser name is counted too)
    import pdsgen.review  # noqa: F401

    source, product_ids = products
    parsed = _count_parses(monkeypatch)
    make_delivery(source, tmp_path / "delivery", dialect=dialect, volume_id="TEST_0001",
                  bundle_lid="urn:nasa:pds:test")
    assert (tmp_path / "delivery" / "REVIEW.html").is_file()
    for product_id in product_ids:
        own = re.compile(rf'^\s*PRODUCT_ID\s*=\s*"?{product_id}"?\s*$', re.MULTILINE)
        texts = [text for text in parsed if text.lstrip().startswith("PDS_VERSION_ID") and own.search(text)]
        assert texts, product_id
        assert sum(parsed[text] for text in texts) == 1, product_id


def test_the_cache_keeps_labels_only_up_to_its_bound(tmp_path):
    """Memory stays bounded whatever the number of labels: past the bound a label is read again
    by each step that asks, and what was kept is still read once."""
    from pdsgen.label.read import LabelCache

    text = "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\nEND\r\n"
    paths = []
    for n in range(3):
        paths.append(tmp_path / f"L{n}.LBL")
        paths[-1].write_text(text)
    cache = LabelCache(text_bytes=2 * len(text))  # room for two labels' text
    for _ in range(2):
        for path in paths:
            assert cache.open_pds3(path) is not None
    assert cache.parses == {paths[0]: 1, paths[1]: 1, paths[2]: 2}
