"""The PDS value formatter and label layout used by every label pdsgen writes."""

from __future__ import annotations

import pvl
import pytest

from pdsgen.label.layout import LabelLayoutError, layout_label
from pdsgen.label.render import RecordLayout, pad_label, settle_attached_label
from pdsgen.label.values import Based, Quantity, Symbol, float32_bits, format_real, format_value


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (-543510.49999999, "-543510.5"),  # the float noise of a real HiRISE label
        (0.1 + 0.2, "0.3"),
        (1.0113804322107, "1.0113804322107"),
        (180.0, "180.0"),
        (0.0, "0.0"),
        (2.0, "2.0"),
        (1.07543902665525e-04, "0.000107543902665525"),
        (-3.4028226550889045e38, "-3.4028226550889045E+38"),
        (1.234e-7, "1.234E-07"),
    ],
)
def test_reals_have_no_float_noise_and_round_trip(value, text):
    assert format_real(value) == text
    assert float(text) == pytest.approx(value, rel=1e-13, abs=0)


def test_reals_keep_enough_digits_for_geotransforms():
    offset = -6050328.123456789
    assert abs(float(format_real(offset)) - offset) < 1e-6


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (Symbol("PC_REAL"), "PC_REAL"),
        ("UNIVERSITY OF ARIZONA", '"UNIVERSITY OF ARIZONA"'),
        ("1.0", '"1.0"'),
        (Quantity(3396.19, "KM"), "3396.19 <KM>"),
        (Based(float32_bits(-3.4028226550889045e38), 16, 8), "16#FF7FFFFB#"),
        (Based(1023, 2, 16), "2#0000001111111111#"),
        ([Symbol("PSP_008669_1705"), Symbol("PSP_009025_1705")], "(PSP_008669_1705, PSP_009025_1705)"),
        (42, "42"),
    ],
)
def test_value_forms(value, text):
    assert format_value(value) == text


@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_non_finite_reals_are_refused(bad):
    with pytest.raises(ValueError):
        format_real(bad)


def test_strings_must_be_ascii_without_quotes():
    with pytest.raises(ValueError):
        format_value('say "hi"')
    with pytest.raises(ValueError):
        format_value("caf\u00e9")
    with pytest.raises(ValueError):
        Symbol("HAS SPACE")


def test_layout_aligns_indents_and_wraps_within_80_bytes():
    long_name = "MRO MARS HIGH RESOLUTION IMAGING SCIENCE EXPERIMENT DIGITAL TERRAIN MODEL EXTRA WORDS V1.0"
    sources = "(" + ", ".join(f"ESP_0{n}0000_1955_RED" for n in range(10, 30)) + ")"
    text = layout_label(
        "PDS_VERSION_ID = PDS3\n"
        f'DATA_SET_NAME = "{long_name}"\n'
        f"SOURCE_PRODUCT_ID = {sources}\n"
        "OBJECT = IMAGE\nLINES = 3\nSAMPLE_BIT_MASK = 2#1111#\nEND_OBJECT = IMAGE\nEND\n"
    )
    lines = text.split("\r\n")
    assert lines[-1] == "" and lines[-2] == "END"
    assert all(len(line) <= 78 for line in lines)
    assert "  LINES           = 3" in lines
    assert "PDS_VERSION_ID    = PDS3" in lines
    parsed = pvl.loads(text)
    assert " ".join(parsed["DATA_SET_NAME"].split()) == long_name
    assert len(parsed["SOURCE_PRODUCT_ID"]) == 20


def test_layout_refuses_unbalanced_objects_and_unwrappable_values():
    with pytest.raises(LabelLayoutError):
        layout_label("OBJECT = IMAGE\nLINES = 1\nEND\n")
    with pytest.raises(LabelLayoutError):
        layout_label("KEY = " + "9" * 90 + "\nEND\n")


def test_attached_label_records_settle_on_a_consistent_count():
    def render(layout: RecordLayout) -> str:
        body = f"RECORD_BYTES = {layout.record_bytes}\nLABEL_RECORDS = {layout.label_records}\n"
        return layout_label(body + "X = 1\n" * 30 + "END\n")

    layout, text = settle_attached_label(render, record_bytes=12, data_records=5)
    assert layout.label_records == -(-len(text) // 12)
    assert f"LABEL_RECORDS = {layout.label_records}" in text
    padded = pad_label(text, layout)
    assert len(padded) == layout.label_records * 12


@pytest.mark.parametrize("grows", [False, True])
def test_an_attached_label_that_outgrows_its_reservation_moves_the_data_after_it(tmp_path, monkeypatch, grows):
    """The label is sized before the data pass with the widest statistic; should the final
    label still need more records, the data written after the reservation moves down intact
    (copied in chunks far smaller than the move, so a front-to-back copy would corrupt it)."""
    from pdsgen.formats import img
    from pdsgen.formats.img import RESERVATION_STATISTIC, BandStatistics, write_attached_product

    monkeypatch.setattr(img, "_COPY_CHUNK", 7)

    record_bytes, data_records = 16, 40
    data = bytes(range(256)) * (record_bytes * data_records // 256) + bytes(record_bytes * data_records % 256)

    def render(layout: RecordLayout, stats: BandStatistics) -> str:
        final = stats.minimum != RESERVATION_STATISTIC
        body = (f"RECORD_BYTES = {layout.record_bytes}\nLABEL_RECORDS = {layout.label_records}\n"
                f"FILE_RECORDS = {layout.file_records}\n")
        return layout_label(body + ("X = 1\n" * 9 if final and grows else "") + "END\n")

    def write_data(handle) -> BandStatistics:
        handle.write(data)
        return BandStatistics(1, 0.0, 1.0)

    path = tmp_path / "product.img"
    path.write_bytes(b"")
    layout, text, _ = write_attached_product(path, render, record_bytes, data_records, write_data)
    written = path.read_bytes()
    assert len(written) == layout.file_records * record_bytes
    assert written[:len(text)] == text.encode("ascii") and written[layout.label_bytes:] == data
    assert f"LABEL_RECORDS = {layout.label_records}" in text
