"""IMG data checks: statistics recomputed by streaming the samples (any byte order and
sample type, blocks smaller than the image), compared with the label."""

from __future__ import annotations

import numpy as np
import pytest

from pdsgen.validate import datastats, validate_paths
from pdsgen.validate.datastats import SampleLayout, image_stats
from test_validate_support import make_dtm, replace_in_label


@pytest.mark.parametrize("dtype", [">f4", "<f4", ">i2", "<u2", "|u1", "<f8"])
def test_streamed_statistics_match_numpy(tmp_path, monkeypatch, dtype):
    monkeypatch.setattr(datastats, "_BLOCK_BYTES", 1000)  # many blocks
    rng = np.random.default_rng(5)
    data = (rng.random((37, 23)) * 200).astype(dtype)
    missing = np.array(0 if np.dtype(dtype).kind == "u" else -100, dtype=dtype)
    data[3, 4:9] = missing
    if np.dtype(dtype).kind == "f":
        data[7, 7] = np.nan
    prefix, suffix = 3, 2
    rows = [b"P" * prefix + row.tobytes() + b"S" * suffix for row in data]
    path = tmp_path / "img.raw"
    path.write_bytes(b"HEADER" + b"".join(rows))
    layout = SampleLayout(6, np.dtype(dtype), 37, 23, prefix, suffix)
    stats = image_stats(path, layout, [float(missing)], want_moments=True)
    valid = data.astype(float)
    valid = valid[(valid != float(missing)) & ~np.isnan(valid)]
    assert stats.count == valid.size
    assert stats.minimum == valid.min() and stats.maximum == valid.max()
    assert stats.mean == pytest.approx(valid.mean(), rel=1e-12)
    assert stats.std == pytest.approx(valid.std(), rel=1e-9)


def test_valid_range_checked_against_data_in_both_byte_orders(tmp_path):
    for order in ("lsb", "msb"):
        path = make_dtm(tmp_path, name=order, byte_order=order)
        assert validate_paths([path], strict=True).exit_code == 0
        head = path.read_bytes()[:4000]
        start = head.index(b"VALID_MINIMUM    = ") + len(b"VALID_MINIMUM    = ")
        old = head[start: head.index(b"\r\n", start)]
        new = (b"-9" + old[2:]) if old.startswith(b"-") and not old.startswith(b"-9") else b"1" + old[1:]
        replace_in_label(path, b"VALID_MINIMUM    = " + old, b"VALID_MINIMUM    = " + new)
        finding = next(f for f in validate_paths([path]).findings if f.rule == "IMG-007")
        assert "VALID_MINIMUM" in finding.message and "the data give" in finding.message


def test_missing_constant_that_the_type_cannot_hold(tmp_path):
    label = tmp_path / "X.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nOBJECT = IMAGE\r\n  LINES = 1\r\n  LINE_SAMPLES = 1\r\n"
                      b"  SAMPLE_TYPE = UNSIGNED_INTEGER\r\n  SAMPLE_BITS = 8\r\n"
                      b"  SAMPLE_BIT_MASK = 2#111111111#\r\n  MISSING_CONSTANT = -32768\r\n"
                      b"END_OBJECT = IMAGE\r\nEND\r\n")
    rules = {f.rule for f in validate_paths([label]).findings}
    assert {"IMG-003", "IMG-004"} <= rules


def test_special_value_outside_the_bit_mask(tmp_path):
    label = tmp_path / "Y.LBL"
    label.write_bytes(b"PDS_VERSION_ID = PDS3\r\nOBJECT = IMAGE\r\n  LINES = 1\r\n  LINE_SAMPLES = 1\r\n"
                      b"  SAMPLE_TYPE = MSB_UNSIGNED_INTEGER\r\n  SAMPLE_BITS = 16\r\n"
                      b"  SAMPLE_BIT_MASK = 2#0000001111111111#\r\n  CORE_HIGH_REPR_SATURATION = 4095\r\n"
                      b"  CORE_NULL = 0\r\nEND_OBJECT = IMAGE\r\nEND\r\n")
    findings = [f for f in validate_paths([label]).findings if f.rule == "IMG-004"]
    assert [f.keyword for f in findings] == ["CORE_HIGH_REPR_SATURATION"]


def _image_block(storage: str, prefix: int = 0, suffix: int = 0):
    from pdsgen.label.parser import parse_label

    text = (f"PDS_VERSION_ID = PDS3\nOBJECT = IMAGE\nLINES = 5\nLINE_SAMPLES = 7\nBANDS = 3\n"
            f"SAMPLE_TYPE = MSB_INTEGER\nSAMPLE_BITS = 16\nBAND_STORAGE_TYPE = {storage}\n"
            f"LINE_PREFIX_BYTES = {prefix}\nLINE_SUFFIX_BYTES = {suffix}\nEND_OBJECT = IMAGE\nEND\n")
    return next(parse_label(text).root.blocks("IMAGE"))


@pytest.mark.parametrize(("storage", "stored_lines", "line_bytes"), [
    ("BAND_SEQUENTIAL", 15, 14), ("LINE_INTERLEAVED", 15, 14), ("SAMPLE_INTERLEAVED", 5, 42)])
def test_bytes_per_image_for_each_band_storage(storage, stored_lines, line_bytes):
    from pdsgen.validate.families.image_rules import layout, object_bytes

    block = _image_block(storage)
    assert object_bytes(block) == 5 * 7 * 3 * 2
    lay = layout(block, 0)
    assert (lay.lines, lay.line_bytes) == (stored_lines, line_bytes)
    with_prefix = _image_block(storage, prefix=4, suffix=2)
    assert object_bytes(with_prefix) == stored_lines * (line_bytes + 6)


def _valid_range_stated_as(path, minimum: str):
    """The label's VALID_MINIMUM rewritten as `minimum` (padding keeps the data in place)."""
    from test_validate_support import resize_label_text

    head = path.read_bytes()[:4000]
    start = head.index(b"VALID_MINIMUM    = ")
    old = head[start: head.index(b"\r\n", start)]
    resize_label_text(path, old, b"VALID_MINIMUM    = " + minimum.encode())
    return [f for f in validate_paths([path]).findings if f.rule == "IMG-007"]


def test_valid_range_stated_to_fewer_decimals(tmp_path):
    """A value is stated to the decimals it is written with: a bound rounded outwards
    passes, one rounded to the nearest that cuts the lowest samples off is a warning
    (hidtmgen's REAL,2 does this), more than that is an error."""
    from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal

    path = make_dtm(tmp_path)
    low = min(v for v in np.fromfile(path, dtype="<f4")[-40 * 50:] if v > -1e30)
    exact = Decimal(repr(float(np.float32(low))))
    outwards = exact.quantize(Decimal("0.01"), rounding=ROUND_FLOOR)
    assert _valid_range_stated_as(path, str(outwards)) == []
    # the first number of decimals at which rounding to the nearest goes up, inside the data
    step = next(Decimal(10) ** -k for k in range(1, 8)
                if exact.quantize(Decimal(10) ** -k, rounding=ROUND_CEILING) - exact <= Decimal(10) ** -k / 2)
    (warning,) = _valid_range_stated_as(path, str(exact.quantize(step, rounding=ROUND_CEILING)))
    assert warning.severity == "warning" and f"rounded to the nearest {float(step):g}" in warning.message
    (error,) = _valid_range_stated_as(path, str(outwards - Decimal("0.02")))
    assert error.severity == "error" and "the data give" in error.message
    (whole,) = _valid_range_stated_as(path, str(int(outwards.to_integral_value(ROUND_FLOOR))))
    assert whole.severity == "error"  # no decimals written: stated exactly


@pytest.mark.parametrize("key, label, data, expected", [
    ("VALID_MINIMUM", 1.25, 1.25, "exact"),      # on the grid: stated exactly
    ("VALID_MINIMUM", 1.24, 1.25, None),         # a whole step out is not the data rounded outwards
    ("VALID_MINIMUM", 1.25, 1.2599, "exact"),    # rounded outwards
    ("VALID_MINIMUM", 1.26, 1.2599, "inside"),   # rounded to the nearest, above the minimum
    ("VALID_MAXIMUM", 1.26, 1.2501, "exact"),
    ("VALID_MAXIMUM", 1.25, 1.2501, "inside"),
    ("VALID_MAXIMUM", 1.27, 1.2501, None),
    ("VALID_MINIMUM", 0.0, -1e-9, "exact"),      # floating-point noise is not "inside"
    ("MINIMUM", 1.26, 1.2599, "exact"),          # statistics, not bounds: the nearest is right
    ("MINIMUM", 1.25, 1.2599, None),
])
def test_a_value_stated_to_two_decimals(key, label, data, expected):
    from pdsgen.validate.families.image_rules import _stated_to_precision

    assert _stated_to_precision(key, label, data, 0.01) == expected
