"""JP2INFO.TXT: the encoding facts beside the orthoimages, pointed to by their labels, true to the files."""

from __future__ import annotations

import re

import glymur
import numpy as np
import pvl
from affine import Affine
from rasterio.crs import CRS

from pdsgen import write_ortho
from pdsgen.synthetic import write_geotiff
from pdsgen.validate import validate_paths

EQC = CRS.from_proj4("+proj=eqc +lat_ts=-5 +lat_0=0 +lon_0=180 +R=3396190 +units=m +no_defs")
TRANSFORM = Affine(0.5, 0.0, 6099776.0, 0.0, -0.5, -563110.0)


def _input(tmp_path, shape, name):
    yy, xx = np.mgrid[: shape[0], : shape[1]]
    data = (120 + 100 * np.sin(yy / 23.0) * np.cos(xx / 31.0)).astype(np.uint8)
    return write_geotiff(tmp_path / name, data, TRANSFORM, EQC, None)


def _entry(text, name):
    block = text.split(name + "\r\n", 1)[1].split("\r\n\r\n", 1)[0]
    return dict(re.match(r"\s+([^:]+):\s+(.*)", line).groups() for line in block.split("\r\n") if line)


def test_jp2info_states_what_the_code_stream_holds(tmp_path):
    out = tmp_path / "out"
    big = write_ortho(_input(tmp_path, (600, 700), "big.tif"), out)
    small = write_ortho(_input(tmp_path, (90, 120), "small.tif"), out, gmljp2=True)
    raw = (out / "JP2INFO.TXT").read_bytes()
    text = raw.decode("ascii")
    lines = text.split("\r\n")
    assert raw.endswith(b"\r\n") and "\n" not in text.replace("\r\n", "")
    assert max(len(line) for line in lines) <= 80
    for product in (big, small):  # both products are described, each by its own label's pointer
        label = pvl.load(str(product.label_path))
        assert label["COMPRESSED_FILE"]["^DESCRIPTION"] == "JP2INFO.TXT"
        entry = _entry(text, product.jp2_path.name)
        codestream = glymur.Jp2k(product.jp2_path).get_codestream()
        siz = next(s for s in codestream.segment if s.marker_id == "SIZ")
        cod = next(s for s in codestream.segment if s.marker_id == "COD")
        assert entry["Tiles"].startswith(f"{siz.xtsiz} x {siz.ytsiz} samples")
        assert entry["Resolution levels"].startswith(f"{cod.num_res + 1} ")
        assert entry["Code blocks"] == "{1} x {0}".format(*cod.code_block_size)
        assert entry["Code-block style"].startswith("BYPASS") and cod.cstyle == 0x01
        assert entry["Compression"].startswith("lossless") and cod.xform == 1
        assert entry["Progression order"].startswith("RPCL") and cod.prog_order == glymur.core.RPCL
        assert entry["PLT markers"].startswith("yes") and entry["TLM markers"].startswith("yes")
        assert "TLM" in {s.marker_id for s in codestream.segment}
    assert _entry(text, small.jp2_path.name)["Georeferencing"] == "GeoJP2 box and GMLJP2 box"
    assert _entry(text, big.jp2_path.name)["Georeferencing"] == "GeoJP2 box"


def test_products_and_jp2info_pass_the_validator(tmp_path):
    out = tmp_path / "out"
    write_ortho(_input(tmp_path, (300, 260), "a.tif"), out, gmljp2=True)
    report = validate_paths([out], strict=True)
    assert report.count("error") == 0, [f.message for f in report.findings]
    assert not {rule for rule in report.rule_ids() if rule.startswith(("GEO", "PTR"))}


def test_rewriting_a_product_replaces_its_entry_and_keeps_the_others(tmp_path):
    out = tmp_path / "out"
    write_ortho(_input(tmp_path, (80, 90), "one.tif"), out)
    write_ortho(_input(tmp_path, (70, 60), "two.tif"), out)
    write_ortho(_input(tmp_path, (75, 50), "one.tif"), out, overwrite=True)
    text = (out / "JP2INFO.TXT").read_bytes().decode("ascii")
    assert text.count("ONE.JP2\r\n") == 1 and text.count("TWO.JP2\r\n") == 1
    assert _entry(text, "ONE.JP2")["Image"].startswith("50 samples x 75 lines")


def test_write_ortho_threads_limit_gives_the_same_product(tmp_path):
    source = _input(tmp_path, (700, 600), "t.tif")
    one = write_ortho(source, tmp_path / "one", threads=1)
    every = write_ortho(source, tmp_path / "every")
    assert one.jp2_path.read_bytes() == every.jp2_path.read_bytes()
    assert (tmp_path / "one" / "JP2INFO.TXT").read_bytes() == (tmp_path / "every" / "JP2INFO.TXT").read_bytes()
