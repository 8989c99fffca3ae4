"""`pdsgen migrate` on PDS3 ARRAY, COLLECTION, ELEMENT and BIT_ELEMENT objects.

No genuine Galileo Probe calibration product (OBJECT = ARRAY of ELEMENTs) is held in a public
repository the project could find, so the products here are written by the PDS3 Standards
Reference (appendix A, the ARRAY, COLLECTION, ELEMENT and BIT_ELEMENT objects: AXES,
AXIS_ITEMS, AXIS_NAME; a COLLECTION's parts at their START_BYTE). Every migrated label is read
back by pds4_tools and compared with pdr's reading of the PDS3 product, and both with the
numbers packed here with struct (the reference that shares no reader's assumption); where pdr
cannot read the object (BIT_ELEMENTs) the bytes alone are the reference.
"""

from __future__ import annotations

import shutil
import struct
from pathlib import Path

import numpy as np
import pytest

from pdsgen.migrate import Refused, migrate_product
from pdsgen.validate import validate_paths
from pdsgen.validate.pds4 import schematron

from helpers import UNNAMED, assert_pds4_clean

pds4_tools = pytest.importorskip("pds4_tools")
pdr = pytest.importorskip("pdr")
BUNDLE = "urn:nasa:pds:pdsgen_arrays_test"
needs_saxon = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")


def _label(directory: Path, name: str, data: bytes, objects: str, pointer: str = "ARRAY") -> Path:
    (directory / f"{name}.DAT").write_bytes(data)
    label = directory / f"{name}.LBL"
    text = ("PDS_VERSION_ID = PDS3\nRECORD_TYPE = FIXED_LENGTH\nRECORD_BYTES = " f"{len(data)}\n"
            f"FILE_RECORDS = 1\n^{pointer} = \"{name}.DAT\"\nPRODUCT_ID = {name}\n"
            "INSTRUMENT_HOST_NAME = \"GALILEO PROBE\"\nINSTRUMENT_NAME = \"ATMOSPHERIC STRUCTURE INSTRUMENT\"\n"
            "TARGET_NAME = JUPITER\n" + objects + "END\n")
    label.write_text(text.replace("\n", "\r\n"), newline="")
    return label


def _clean(label: Path, unnamed: tuple[str, ...] = ()) -> None:
    """XSD + Schematron valid with no finding but DLV-008's for the areas `unnamed`, and no error."""
    assert_pds4_clean(label, unnamed)
    assert [f for f in validate_paths([label]).findings if f.severity == "error"] == []


def _pds4(label: Path, ident: str):
    return pds4_tools.read(str(label), quiet=True)[ident].data


# -- an ARRAY of ELEMENTs (the Galileo Probe calibration products' form): an Array_2D ---------------

CALIBRATION = (np.arange(-6, 6).reshape(3, 4) * 517).astype(">i2")


def _calibration(directory: Path) -> Path:
    return _label(directory, "CALIB", CALIBRATION.tobytes(),
                  "OBJECT = ARRAY\n NAME = CALIBRATION\n INTERCHANGE_FORMAT = BINARY\n AXES = 2\n"
                  " AXIS_ITEMS = (3, 4)\n AXIS_NAME = (TEMPERATURE_STEP, CHANNEL)\n"
                  " DESCRIPTION = \"Counts per temperature step and channel.\"\n"
                  " OBJECT = ELEMENT\n  NAME = COUNTS\n  DATA_TYPE = MSB_INTEGER\n  BYTES = 2\n"
                  "  START_BYTE = 1\n  UNIT = \"DN\"\n END_OBJECT = ELEMENT\nEND_OBJECT = ARRAY\n")


@needs_saxon
def test_an_array_of_elements_is_an_array_2d_read_as_pdr_and_the_bytes_read_it(tmp_path):
    label = _calibration(tmp_path)
    product = migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
    _clean(product.label_path)
    text = product.label_path.read_text(encoding="utf-8")
    assert "<Array_2D>" in text and "<axis_name>TEMPERATURE_STEP</axis_name>" in text
    assert "<data_type>SignedMSB2</data_type>" in text and "<unit>DN</unit>" in text
    pds3 = pdr.read(str(label))["ARRAY"]["COUNTS"]  # pdr: a structured array, the ELEMENT its field
    pds4 = np.asarray(_pds4(product.label_path, "array"))
    assert pds3.shape == pds4.shape == (3, 4)
    assert np.array_equal(pds4, CALIBRATION) and np.array_equal(pds3, CALIBRATION)


@needs_saxon
def test_nested_arrays_add_their_axes(tmp_path):
    cube = (np.arange(24).reshape(2, 3, 4) * 1001).astype("<u2")
    label = _label(tmp_path, "NESTED", cube.tobytes(),
                   "OBJECT = ARRAY\n NAME = SWEEPS\n INTERCHANGE_FORMAT = BINARY\n AXES = 1\n AXIS_ITEMS = 2\n"
                   " OBJECT = ARRAY\n  NAME = FRAME\n AXES = 2\n  AXIS_ITEMS = (3, 4)\n"
                   "  DATA_TYPE = LSB_UNSIGNED_INTEGER\n  BYTES = 2\n END_OBJECT = ARRAY\nEND_OBJECT = ARRAY\n")
    product = migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
    _clean(product.label_path)
    assert "<Array_3D>" in product.label_path.read_text(encoding="utf-8")
    assert np.array_equal(np.asarray(_pds4(product.label_path, "array")), cube)


# -- an ARRAY of COLLECTIONs holding an ELEMENT array: a Table_Binary, a record per element -------

RECORDS = [(1.5 * n, 40 + n, (n, -n, 2 * n)) for n in range(5)]
COLLECTION = (
    "OBJECT = ARRAY\n NAME = SAMPLES\n INTERCHANGE_FORMAT = BINARY\n AXES = 1\n AXIS_ITEMS = 5\n"
    " OBJECT = COLLECTION\n  NAME = SAMPLE\n  BYTES = 12\n  START_BYTE = 1\n"
    "  OBJECT = ELEMENT\n   NAME = TIME\n   DATA_TYPE = IEEE_REAL\n   BYTES = 4\n   START_BYTE = 1\n"
    "   UNIT = \"S\"\n  END_OBJECT = ELEMENT\n"
    "  OBJECT = ELEMENT\n   NAME = TEMPERATURE\n   DATA_TYPE = MSB_UNSIGNED_INTEGER\n   BYTES = 2\n"
    "   START_BYTE = 5\n  END_OBJECT = ELEMENT\n"
    "  OBJECT = ARRAY\n   NAME = CHANNELS\n   AXES = 1\n   AXIS_ITEMS = 3\n   START_BYTE = 7\n"
    "   OBJECT = ELEMENT\n    NAME = COUNT\n    DATA_TYPE = LSB_INTEGER\n    BYTES = 2\n    START_BYTE = 1\n"
    "   END_OBJECT = ELEMENT\n"
    "  END_OBJECT = ARRAY\n END_OBJECT = COLLECTION\nEND_OBJECT = ARRAY\n")


@needs_saxon
def test_an_array_of_collections_is_a_table_of_records_read_as_the_bytes_and_pdr_read_it(tmp_path):
    data = b"".join(struct.pack(">fH", t, k) + struct.pack("<3h", *c) for t, k, c in RECORDS)
    label = _label(tmp_path, "SAMPLES", data, COLLECTION)
    product = migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
    _clean(product.label_path)
    table = _pds4(product.label_path, "array")
    assert list(table["TIME"]) == [t for t, _, _ in RECORDS]
    assert list(table["TEMPERATURE"]) == [k for _, k, _ in RECORDS]
    counts = table["CHANNELS, COUNT"]  # pds4_tools names a grouped field by its group too
    assert [list(v) for v in counts] == [list(c) for _, _, c in RECORDS]
    # pdr reads an ARRAY of COLLECTIONs of ELEMENTs (not one holding an ARRAY: KeyError 'SB_OFFSET'):
    # the same collection without its nested array, read by both readers
    flat = COLLECTION.split("  OBJECT = ARRAY")[0].replace("BYTES = 12", "BYTES = 6")
    label = _label(tmp_path, "FLAT", b"".join(struct.pack(">fH", t, k) for t, k, _ in RECORDS),
                   flat + " END_OBJECT = COLLECTION\nEND_OBJECT = ARRAY\n")
    product = migrate_product(label, tmp_path / "flat", bundle_lid=BUNDLE)
    _clean(product.label_path)
    table, reference = _pds4(product.label_path, "array"), pdr.read(str(label))["ARRAY"]
    assert list(reference["TIME"]) == list(table["TIME"]) == [t for t, _, _ in RECORDS]
    assert list(reference["TEMPERATURE"]) == list(table["TEMPERATURE"])


@needs_saxon
def test_bit_elements_make_the_array_a_table_with_packed_fields(tmp_path):
    words = [0xA123, 0x0FFF, 0x8001]
    label = _label(tmp_path, "BITS", struct.pack(">3H", *words),
                   "OBJECT = ARRAY\n NAME = STATUS\n INTERCHANGE_FORMAT = BINARY\n AXES = 1\n AXIS_ITEMS = 3\n"
                   " OBJECT = ELEMENT\n  NAME = WORD\n  DATA_TYPE = MSB_UNSIGNED_INTEGER\n  BYTES = 2\n"
                   "  OBJECT = BIT_ELEMENT\n   NAME = MODE\n   BIT_DATA_TYPE = MSB_UNSIGNED_INTEGER\n"
                   "   START_BIT = 1\n   BITS = 4\n  END_OBJECT = BIT_ELEMENT\n"
                   "  OBJECT = BIT_ELEMENT\n   NAME = LEVEL\n   BIT_DATA_TYPE = MSB_UNSIGNED_INTEGER\n"
                   "   START_BIT = 5\n   BITS = 12\n  END_OBJECT = BIT_ELEMENT\n"
                   " END_OBJECT = ELEMENT\nEND_OBJECT = ARRAY\n")
    product = migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
    _clean(product.label_path)
    text = product.label_path.read_text(encoding="utf-8")
    assert "<Table_Binary>" in text and "<bit_fields>2</bit_fields>" in text
    packed = _pds4(product.label_path, "array")["WORD"]  # pds4_tools gives the packed field's bytes
    assert [int.from_bytes(bytes(v), "big") for v in packed] == words


def test_an_ascii_array_of_no_line_layout_and_an_element_that_does_not_fill_its_element_are_refused(tmp_path):
    label = _calibration(tmp_path)  # binary numbers called ASCII: no lines of values to describe
    label.write_bytes(label.read_bytes().replace(b"INTERCHANGE_FORMAT = BINARY", b"INTERCHANGE_FORMAT = ASCII"))
    with pytest.raises(Refused, match=r"OBJECT = ARRAY \(line 10\): ASCII array: its first line"):
        migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
    label = _calibration(tmp_path)
    label.write_bytes(label.read_bytes().replace(b"START_BYTE = 1", b"START_BYTE = 2"))
    with pytest.raises(Refused, match=r"OBJECT = ELEMENT \(line 17\): an ELEMENT that does not fill"):
        migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)


# -- genuine Galileo Probe products (tests/data/volume_gp0001, PROVENANCE.md) -------------------

GP = Path(__file__).parent / "data" / "volume_gp0001"


@needs_saxon
def test_genuine_nfr_ascii_array_is_a_character_table_read_as_pdr_reads_the_array(tmp_path):
    """The NFR field-of-view calibration ARRAY (ASCII, 81 x 101): a record per line, the values a
    repeated field; pds4_tools reads the very array pdr reads from the PDS3 label."""
    product = migrate_product(GP / "data/nfr/calib/nfrfova.lbl", tmp_path / "out", bundle_lid=BUNDLE)
    _clean(product.label_path)
    table = _pds4(product.label_path, "array")
    values = np.asarray(table[table.dtype.names[0]])
    reference = np.asarray(pdr.read(str(GP / "data/nfr/calib/nfrfova.lbl"))["ARRAY"])
    assert values.shape == reference.shape == (81, 101)
    assert np.array_equal(values, reference) and 0.98 < values.max() <= 1.0  # normalised to 1.0 at its maximum
    line = (GP / "data/nfr/calib/nfrfova.dat").read_bytes().split(b"\r\n")[40]  # the bytes, the 41st elevation
    assert [float(v) for v in line.split(b",")] == list(values[40])


@needs_saxon
def test_genuine_integer_column_of_reals_is_described_as_the_bytes_are_with_a_warning(tmp_path):
    """DESCENT.TAB's ALTITUDE: DATA_TYPE ASCII_INTEGER, FORMAT F9.4, real values; as labelled, pds4_tools
    cannot read the table. Described as ASCII_Real, the keyword named; every column as pdr reads it."""
    product = migrate_product(GP / "data/asi/descent.lbl", tmp_path / "out", bundle_lid=BUNDLE)
    assert product.warnings == (
        f"{GP / 'data/asi/descent.lbl'}: OBJECT = TABLE (line 23): column ALTITUDE DATA_TYPE overridden by the "
        "bytes: '17.2910' in record 1 is no ASCII_Integer, and every value of the column is a number: described as "
        "ASCII_Real",)
    _clean(product.label_path)
    table = _pds4(product.label_path, "table")
    reference = pdr.read(str(GP / "data/asi/descent.lbl"))["TABLE"]
    assert len(table) == len(reference) == 300
    for name in table.dtype.names:
        assert np.array_equal(np.asarray(table[name], dtype=float), reference[name].to_numpy(dtype=float)), name


@pytest.mark.parametrize(("name", "rows", "length", "record", "end"),
                         [("asi/e03z1", 389, 32, 287, 33), ("nep/fittemp", 463, 56, 444, 59)])
def test_genuine_tables_whose_records_stop_ending_where_the_label_says_are_refused_by_record(
        tmp_path, name, rows, length, record, end):
    label = GP / "data" / f"{name}.lbl"
    with pytest.raises(Refused) as refused:
        migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
    assert f"ROWS {rows} records of {length} bytes ending with CR LF, but record {record} of {label.stem}.tab does " \
           f"not end so (its line end is at byte {end} of it)" in str(refused.value)
    lines = label.with_suffix(".tab").read_bytes().split(b"\r\n")  # the bytes agree: that record alone is longer
    assert [n + 1 for n, line in enumerate(lines[:-1]) if len(line) + 2 != length] == [record]
    assert not (tmp_path / "out").exists()


# -- binary headers and spare columns PDS4 has no type for ----------------------------------------------

@needs_saxon
def test_a_binary_bad_data_values_header_is_stated_as_a_table_of_its_bytes(tmp_path):
    """A Galileo SSI REDR's BAD_DATA_VALUES_HEADER (its OBJECT block as the genuine label
    tests/data/genuine_pds3/pdsparser/C052079-2800R.LBL gives it: HEADER_TYPE BDV, BINARY, BYTES,
    RECORDS, ^DESCRIPTION), in a product written here: PDS4's Header parses no binary standard,
    so the records are a Table_Binary of bytes; pds4_tools reads back the very bytes."""
    bdv, image = bytes(range(200)), bytes(range(100, 200))
    label_records = 5  # the attached label's records; then 2 of the header, 1 of the image
    label_text = (b"PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 100\r\nFILE_RECORDS = 8\r\n"
                  b"^BAD_DATA_VALUES_HEADER = 6\r\n^IMAGE = 8\r\nPRODUCT_ID = BDV\r\n"
                  b"OBJECT = BAD_DATA_VALUES_HEADER\r\nHEADER_TYPE = BDV\r\nINTERCHANGE_FORMAT = BINARY\r\n"
                  b"BYTES = 200\r\nRECORDS = 2\r\n^DESCRIPTION = \"BADDATA.TXT\"\r\nEND_OBJECT\r\n"
                  b"OBJECT = IMAGE\r\nLINES = 10\r\nLINE_SAMPLES = 10\r\nSAMPLE_BITS = 8\r\n"
                  b"SAMPLE_TYPE = UNSIGNED_INTEGER\r\nEND_OBJECT\r\nEND\r\n")
    assert len(label_text) <= label_records * 100
    product_path = tmp_path / "BDV.IMG"
    product_path.write_bytes(label_text.ljust(label_records * 100, b" ") + bdv + image)
    (tmp_path / "BADDATA.TXT").write_text("Bad data value records.\r\n", newline="")
    product = migrate_product(product_path, tmp_path / "out", bundle_lid=BUNDLE)
    assert any("a binary BDV header PDS4 has no parsing standard for" in w for w in product.warnings)
    _clean(product.label_path, UNNAMED)
    table = _pds4(product.label_path, "bad_data_values_header")
    assert b"".join(bytes(np.asarray(row[0], dtype=np.uint8)) for row in table) == bdv
    assert np.array_equal(np.asarray(_pds4(product.label_path, "image")).ravel(), np.frombuffer(image, np.uint8))


@needs_saxon
def test_a_spare_column_of_ibm_real_is_stated_as_bytes_and_a_valued_one_refused(tmp_path):
    """A Pioneer Venus style binary table with a SPARE column of IBM_REAL (PDS4 has no IBM float):
    the spare holds no value, so its 4 bytes are stated as an UnsignedByte group (every byte of
    the record accounted for, no number format claimed); a column of values in IBM_REAL is refused."""
    rows = [(n * 1000, struct.pack(">I", 0x41100000 + n)) for n in range(4)]  # IBM 1.0625 ...: not IEEE
    (tmp_path / "PV.DAT").write_bytes(b"".join(struct.pack(">i", t) + spare for t, spare in rows))
    label = tmp_path / "PV.LBL"

    def write(spare_name: str) -> None:
        label.write_text(
            "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = FIXED_LENGTH\r\nRECORD_BYTES = 8\r\nFILE_RECORDS = 4\r\n"
            "^TABLE = \"PV.DAT\"\r\nPRODUCT_ID = PV\r\nOBJECT = TABLE\r\n INTERCHANGE_FORMAT = BINARY\r\n ROWS = 4\r\n"
            " COLUMNS = 2\r\n ROW_BYTES = 8\r\n"
            " OBJECT = COLUMN\r\n  NAME = TIME\r\n  DATA_TYPE = MSB_INTEGER\r\n  START_BYTE = 1\r\n  BYTES = 4\r\n"
            " END_OBJECT = COLUMN\r\n"
            f" OBJECT = COLUMN\r\n  NAME = {spare_name}\r\n  DATA_TYPE = IBM_REAL\r\n  START_BYTE = 5\r\n"
            "  BYTES = 4\r\n END_OBJECT = COLUMN\r\nEND_OBJECT = TABLE\r\nEND\r\n", newline="")

    write("SPARE")
    product = migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
    assert product.warnings == (f"{label}: OBJECT = COLUMN (line 18): column SPARE DATA_TYPE IBM_REAL has no PDS4 "
                                "data type; a spare column, stated as its 4 bytes (UnsignedByte)",)
    _clean(product.label_path, UNNAMED)
    table = _pds4(product.label_path, "table")
    assert list(table["TIME"]) == [t for t, _ in rows] == list(pdr.read(str(label))["TABLE"]["TIME"])
    spare_field = next(name for name in table.dtype.names if name.endswith("SPARE"))  # pds4_tools: "GROUP_0, SPARE"
    assert [bytes(np.asarray(v, dtype=np.uint8)) for v in table[spare_field]] == [spare for _, spare in rows]
    write("DENSITY")
    with pytest.raises(Refused, match="column DENSITY DATA_TYPE IBM_REAL of 4 bytes has no data type in PDS4"):
        migrate_product(label, tmp_path / "out2", bundle_lid=BUNDLE)


@needs_saxon
def test_a_numeric_column_holding_a_blank_is_described_as_the_text_it_is(tmp_path):
    """DESCENT.TAB with its first PRESSURE blanked (edited here): pds4_tools cannot convert a blank
    ASCII_Real, so the label would not open; the column is described as ASCII_String, the keyword
    named, and every other column keeps its type and values."""
    shutil.copy(GP / "data/asi/descent.lbl", tmp_path)
    data = (GP / "data/asi/descent.tab").read_bytes()
    (tmp_path / "descent.tab").write_bytes(data[:22] + b" " * 8 + data[30:])  # PRESSURE: bytes 23 to 30
    product = migrate_product(tmp_path / "descent.lbl", tmp_path / "out", bundle_lid=BUNDLE)
    assert f"{tmp_path / 'descent.lbl'}: OBJECT = TABLE (line 23): column PRESSURE DATA_TYPE overridden by the " \
           "bytes: '' in record 1 is no number, which a PDS4 reader of ASCII_Real cannot convert: described as " \
           "ASCII_String" in product.warnings
    _clean(product.label_path)
    table = _pds4(product.label_path, "table")
    assert [str(v).strip() for v in table["PRESSURE"][:2]] == ["", "0.47937"]
    assert list(table["TEMPERATURE"][:1]) == [130]


# -- a spreadsheet with FIELD ITEMS in a ^STRUCTURE file, values checked against the bytes ---------------

def _channel_sheet(directory: Path) -> tuple[Path, list[list[str]]]:
    """A spreadsheet in the Cassini MIMI form (a time, then a FIELD of ITEMS channel counts), its
    FIELDs in a ^STRUCTURE file, written here by the PDS3 Standards (SPREADSHEET, FIELD ITEMS)."""
    rows = [["2004-183T02:48:00", "1.5", "2", "30", "400"], ["2004-183T02:49:00", "2.25", "5", "60", "800"]]
    (directory / "SHEET.CSV").write_bytes(b"".join((",".join(r) + "\r\n").encode() for r in rows))
    (directory / "SHEET.FMT").write_text(
        "OBJECT = FIELD\r\n NAME = UTC\r\n FIELD_NUMBER = 1\r\n DATA_TYPE = TIME\r\n BYTES = 17\r\n"
        "END_OBJECT = FIELD\r\n"
        "OBJECT = FIELD\r\n NAME = FLUX\r\n FIELD_NUMBER = 2\r\n DATA_TYPE = ASCII_REAL\r\n BYTES = 6\r\n"
        "END_OBJECT = FIELD\r\nOBJECT = FIELD\r\n NAME = COUNTS\r\n FIELD_NUMBER = 3\r\n DATA_TYPE = ASCII_INTEGER\r\n"
        " ITEMS = 3\r\n BYTES = 5\r\nEND_OBJECT = FIELD\r\n", newline="")
    label = directory / "SHEET.LBL"
    label.write_text(
        "PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = STREAM\r\n^SPREADSHEET = \"SHEET.CSV\"\r\nPRODUCT_ID = SHEET\r\n"
        "OBJECT = SPREADSHEET\r\n ROWS = 2\r\n ROW_BYTES = 40\r\n FIELDS = 5\r\n FIELD_DELIMITER = COMMA\r\n"
        " ^STRUCTURE = \"SHEET.FMT\"\r\nEND_OBJECT = SPREADSHEET\r\nEND\r\n", newline="")
    return label, rows


@needs_saxon
def test_spreadsheet_field_items_and_structure_file_read_value_by_value_as_the_bytes_hold(tmp_path):
    import csv

    label, rows = _channel_sheet(tmp_path)
    product = migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
    _clean(product.label_path, UNNAMED)
    table = _pds4(product.label_path, "spreadsheet")
    assert list(table.dtype.names) == ["UTC", "FLUX", "COUNTS_1", "COUNTS_2", "COUNTS_3"]
    with open(tmp_path / "SHEET.CSV", newline="") as stream:  # the reference: the bytes, split by a CSV reader
        written = list(csv.reader(stream))
    assert written == rows
    for n, name in enumerate(table.dtype.names):
        assert [str(v).strip() for v in table[name]] == [str(type(table[name][0].item())(r[n])) for r in written]
    reference = pdr.read(str(label))["SPREADSHEET"]  # pdr splits ITEMS too (COUNTS_0 ...): the same values
    for n, name in enumerate(table.dtype.names):
        assert [str(v).strip() for v in table[name]] == [str(v).strip() for v in reference.iloc[:, n]], name


def test_spreadsheet_records_holding_other_numbers_of_values_are_refused_by_record(tmp_path):
    label, rows = _channel_sheet(tmp_path)
    (tmp_path / "SHEET.CSV").write_bytes(b"".join((",".join(r[:4]) + "\r\n").encode() for r in rows))
    with pytest.raises(Refused, match=r"record 1 of SHEET.CSV holds 4 values, the label 5 fields \(ITEMS counted\)"):
        migrate_product(label, tmp_path / "out", bundle_lid=BUNDLE)
