"""Writer/validator agreement: what pdsgen writes, `pdsgen validate` accepts - or it is refused.

A seeded random loop (no extra test dependency) writes DTM and orthoimage products
with random producer keywords; each either validates with zero errors (data checks
included) or is refused with one line before anything appears in the output directory.
"""

from __future__ import annotations

import random
import string

import numpy as np
import pytest
import rasterio
from click.testing import CliRunner
from rasterio.transform import Affine

from pdsgen import write_dtm, write_ortho
from pdsgen.cli import main
from pdsgen.errors import ParamsError
from pdsgen.validate import validate_paths

EQC = "+proj=eqc +lat_ts=-5 +lat_0=0 +lon_0=180 +x_0=0 +y_0=0 +R=3396190 +units=m +no_defs"
LONG_NAME = "ALFRED MCEWEN, PRINCIPAL INVESTIGATOR, SARAH S. MATTSON, TECHNICAL CONTACT"  # 74 chars
TEXT_KEYWORDS = ("PRODUCER_FULL_NAME", "PRODUCER_ID", "RATIONALE_DESC", "DATA_SET_NAME", "PRODUCER_INSTITUTION_NAME")


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("in")
    rng = np.random.default_rng(5)
    paths = {}
    for name, bands, dtype in (("dtm", 1, "float32"), ("ortho", 1, "uint16")):
        data = rng.random((bands, 16, 12)) * (1000 if dtype == "float32" else 900)
        data = (data - 4000).astype(dtype) if dtype == "float32" else (data + 5).astype(dtype)
        path = folder / f"{name}.tif"
        with rasterio.open(path, "w", driver="GTiff", width=12, height=16, count=bands, dtype=dtype,
                           crs=EQC, transform=Affine(1.0, 0, 6123456.0, 0, -1.0, 563211.0)) as out:
            out.write(data)
        paths[name] = path
    return paths


def _random_text(rng: random.Random) -> str:
    alphabet = string.ascii_uppercase + string.digits + "-,./()"
    words = []
    for _ in range(rng.randint(1, 8)):
        size = rng.choice([1, 3, 5, 8, 12, 12, 90]) if rng.random() < 0.1 else rng.randint(1, 10)
        words.append("".join(rng.choice(alphabet) for _ in range(size)))
    return " ".join(words)


def _random_params(rng: random.Random) -> dict[str, str]:
    chosen = rng.sample(TEXT_KEYWORDS, rng.randint(1, 3))
    return {key: _random_text(rng) for key in chosen}


@pytest.mark.parametrize("seed", range(8))
def test_random_params_give_clean_products_or_a_refusal(tmp_path, inputs, seed):
    rng = random.Random(seed)
    kind = rng.choice(["dtm", "ortho"])
    profile = rng.choice(["generic", "hirise"])
    outdir = tmp_path / "out"
    for trial in range(3):
        params = _random_params(rng)
        options = {"product_id": f"P{seed}_{trial}", "params": params}
        writer = write_dtm if kind == "dtm" else write_ortho
        before = sorted(outdir.iterdir()) if outdir.exists() else []
        try:
            product = writer(inputs[kind], outdir, profile=profile, **options)
        except ParamsError as refusal:
            assert "\n" not in str(refusal)
            assert (sorted(outdir.iterdir()) if outdir.exists() else []) == before, "refused, yet wrote"
            continue
        assert product.warnings == ()
        label = product.path if kind == "dtm" else product.label_path
        report = validate_paths([label])
        assert [f"{f.rule} {f.message}" for f in report.findings if f.severity == "error"] == [], params


def test_74_character_producer_name_is_refused_naming_the_keyword(tmp_path, inputs):
    with pytest.raises(ParamsError, match=r"^PRODUCER_FULL_NAME .*60.*`allow_dictionary_deviations=True`"):
        write_dtm(inputs["dtm"], tmp_path / "out", product_id="X", params={"PRODUCER_FULL_NAME": LONG_NAME})
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


def test_allowed_deviation_is_written_and_warned_once(tmp_path, inputs):
    params = tmp_path / "p.toml"
    params.write_text(f'producer_full_name = "{LONG_NAME}"\n')
    outdir = tmp_path / "out"
    refused = CliRunner().invoke(main, ["dtm", str(inputs["dtm"]), "-o", str(outdir), "--params", str(params)])
    assert refused.exit_code == 2 and "PRODUCER_FULL_NAME" in refused.output
    assert len(refused.output.strip().splitlines()) == 1
    kept = CliRunner().invoke(main, ["dtm", str(inputs["dtm"]), "-o", str(outdir), "--params", str(params),
                                     "--allow-dictionary-deviations"])
    assert kept.exit_code == 0, kept.output
    warned = [line for line in kept.output.splitlines() if line.startswith("warning:")]
    assert len(warned) == 1 and "PRODUCER_FULL_NAME" in warned[0]
    # the same setting from the params file; the validator still sees the deviation
    params.write_text(f'producer_full_name = "{LONG_NAME}"\nallow_dictionary_deviations = true\n')
    product = write_ortho(inputs["ortho"], outdir, product_id="O", params=params)
    assert len(product.warnings) == 1
    assert LONG_NAME in " ".join(product.label_text.split())
    report = validate_paths([product.label_path])
    assert {(f.rule, f.keyword) for f in report.findings if f.severity == "error"} == {
        ("DICT-006", "PRODUCER_FULL_NAME")
    }


def test_hrsc_labels_are_checked_too(tmp_path):
    from pdsgen.products.dtm import write_dtm

    from helpers import elevation_array, write_raster

    source = write_raster(tmp_path / "in.tif", elevation_array(12, 10), "+proj=sinu +lon_0=70 +R=3396000 +units=m",
                          Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0))
    params = {"PRODUCER_FULL_NAME": LONG_NAME}
    with pytest.raises(ParamsError, match="^PRODUCER_FULL_NAME"):
        write_dtm(source, tmp_path / "out", profile="hrsc", product_id="h0010_0023", params=params)
    assert not list((tmp_path / "out").iterdir())
    kept = write_dtm(source, tmp_path / "out", profile="hrsc", product_id="h0010_0023", params=params,
                     allow_dictionary_deviations=True)
    assert len(kept.warnings) == 1 and "PRODUCER_FULL_NAME" in kept.warnings[0]


def test_a_refused_ortho_label_stops_the_encoding_and_leaves_nothing(tmp_path):
    """The JP2 writer checks its label while the first tiles are encoded: a refusal still
    leaves no JP2, no label and no JP2INFO.TXT, and is the same one-line ParamsError."""
    source = tmp_path / "wide.tif"
    data = np.random.default_rng(9).integers(1, 250, (1, 1100, 1030)).astype("uint8")
    with rasterio.open(source, "w", driver="GTiff", width=1030, height=1100, count=1, dtype="uint8",
                       crs=EQC, transform=Affine(1.0, 0, 6123456.0, 0, -1.0, 563211.0)) as out:
        out.write(data)
    outdir = tmp_path / "out"
    with pytest.raises(ParamsError, match=r"^PRODUCER_FULL_NAME .*60.*`allow_dictionary_deviations=True`"):
        write_ortho(source, outdir, product_id="W", params={"PRODUCER_FULL_NAME": LONG_NAME})
    assert not outdir.exists() or not list(outdir.iterdir())
    product = write_ortho(source, outdir, product_id="W")  # the same input, accepted label
    assert {p.name for p in outdir.iterdir()} == {"W.JP2", "W.LBL", "JP2INFO.TXT"}
    with rasterio.open(product.jp2_path) as decoded:
        assert (decoded.read() == data).all()
