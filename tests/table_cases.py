"""PDS4 tables with seeded faults of every kind validate/pds4/table_checks.py reports, and
clean twins: the differential cases of tests/test_table_checks_differential.py.

Each case is a label (one file area, one table) and its data file, written from a seeded
random generator, so the same call always writes the same bytes. The findings the checks
made on them before the column-at-a-time rewrite are kept in
tests/data/table_checks/findings.json; the rewrite must make the same ones.
"""

from __future__ import annotations

import random
import struct
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

NS = "http://pds.nasa.gov/pds4/pds/v1"
RECORDS = 120  # enough for "and N more like these" on every fault kind


@dataclass
class Column:
    """A field of a generated table: how it is declared and how its values are written."""

    name: str
    data_type: str
    length: int
    good: Callable[[random.Random], str | bytes]
    bad: Callable[[random.Random], str | bytes] | None = None
    extra: str = ""  # Field_Statistics, Special_Constants, formats (XML inside the field)
    rate: float = 0.04  # chance that a value is bad


@dataclass
class Case:
    name: str
    label: str
    data: bytes
    data_name: str = field(default="")

    def write(self, directory: Path) -> Path:
        directory.mkdir(parents=True, exist_ok=True)
        (directory / self.data_name).write_bytes(self.data)
        label = directory / f"{self.name}.xml"
        label.write_text(self.label, encoding="utf-8")
        return label


def _label(name: str, data_name: str, table: str) -> str:
    return (
        f'<?xml version="1.0" encoding="UTF-8"?>\n<Product_Observational xmlns="{NS}">\n'
        f"  <Identification_Area><logical_identifier>urn:nasa:pds:test:data:{name}</logical_identifier>"
        "<version_id>1.0</version_id></Identification_Area>\n"
        f"  <File_Area_Observational>\n    <File><file_name>{data_name}</file_name></File>\n{table}"
        "  </File_Area_Observational>\n</Product_Observational>\n"
    )


def _stats(low: float, high: float) -> str:
    return f"<Field_Statistics><minimum>{low}</minimum><maximum>{high}</maximum></Field_Statistics>"


def _special(*constants: str, valid: tuple[float, float] | None = None) -> str:
    body = "".join(
        f"<{tag}>{value}</{tag}>"
        for tag, value in zip(("missing_constant", "invalid_constant", "saturated_constant"), constants, strict=False)
    )
    if valid is not None:
        body += f"<valid_minimum>{valid[0]}</valid_minimum><valid_maximum>{valid[1]}</valid_maximum>"
    return f"<Special_Constants>{body}</Special_Constants>"


def _real(decimals: int, low: float, high: float) -> Callable[[random.Random], str]:
    return lambda r: f"{r.uniform(low, high):.{decimals}f}"


def _choice(*values: str | bytes) -> Callable[[random.Random], str | bytes]:
    return lambda r: r.choice(values)


def _character_columns() -> list[Column]:
    """One column per ASCII data type, each with its own faults."""
    return [
        Column(
            "real",
            "ASCII_Real",
            10,
            _real(3, -50, 50),
            _choice("1.2.3", "abc", "--1", "1e", "nan?", "1,5"),
            _stats(-50, 50),
        ),
        Column(
            "real_range",
            "ASCII_Real",
            9,
            _real(2, 0, 100),
            _real(2, 100.5, 300),
            _stats(0, 100) + _special("-9999.00", valid=(0, 150)),
            rate=0.06,
        ),
        Column(
            "special",
            "ASCII_Real",
            9,
            _choice("-9999.00", "12.50", "   ", "0x1F"),
            _choice("-8888.00"),
            _special("-9999.00", "0x1F", valid=(-100, 100)),
        ),
        Column(
            "int",
            "ASCII_Integer",
            6,
            lambda r: str(r.randint(-999, 999)),
            _choice("1.5", "x", "+-3", "1e3"),
            _stats(-999, 999),
        ),
        Column("nonneg", "ASCII_NonNegative_Integer", 5, lambda r: str(r.randint(0, 9999)), _choice("-1", "1.0")),
        Column(
            "base2",
            "ASCII_Numeric_Base2",
            6,
            lambda r: format(r.randint(0, 40), "b"),
            _choice("102", "2", "110010"),
            _stats(0, 40),
        ),
        Column("base8", "ASCII_Numeric_Base8", 4, lambda r: format(r.randint(0, 511), "o"), _choice("8", "79")),
        Column(
            "base16",
            "ASCII_Numeric_Base16",
            4,
            lambda r: format(r.randint(0, 3000), "X"),
            _choice("G1", "0x1", "FFF"),
            _special(valid=(0, 3000)),
        ),
        Column("bool", "ASCII_Boolean", 5, _choice("true", "false", "0", "1"), _choice("TRUE", "yes", "2")),
        Column("date", "ASCII_Date_YMD", 10, _choice("2024-01-31", "1999-12", "2000"), _choice("2024-13-01", "24-1-1")),
        Column("doy", "ASCII_Date_DOY", 8, _choice("2024-001", "2024-366"), _choice("2024-367", "2024-1")),
        Column(
            "time",
            "ASCII_Date_Time_YMD_UTC",
            24,
            _choice("2024-01-31T12:00:00.123Z", "2024-02-01T00:00Z"),
            _choice("2024-01-31T25:00:00Z", "2024-01-31T12:00:00"),
        ),
        Column(
            "anytime",
            "ASCII_Date_Time",
            20,
            _choice("2024-001T01:02:03", "2024-01-01T01:02"),
            _choice("2024/01/01", "T12:00"),
        ),
        Column("clock", "ASCII_Time", 12, _choice("23:59:60.5", "00:00"), _choice("24:00", "1:2:3")),
        Column(
            "md5",
            "ASCII_MD5_Checksum",
            32,
            lambda r: "".join(r.choice("0123456789abcdef") for _ in range(32)),
            _choice("z" * 32),
        ),
        Column(
            "lidvid",
            "ASCII_LIDVID",
            40,
            _choice("urn:nasa:pds:b:c:p::1.0", "urn:esa:psa:x:y::12.3"),
            _choice("urn:nasa:pds:b:c:p", "nasa:pds:b::1.0"),
        ),
        Column("file", "ASCII_File_Name", 14, _choice("a.txt", "file_1.dat"), _choice(".hidden", "noext", "a b.c")),
        Column(
            "text",
            "UTF8_String",
            6,
            _choice("abc", "héllo".encode()[:6].decode("utf-8", "ignore")),
            _choice(b"\xff\xfe\xfdab"),
        ),
        Column("vfmt", "ASCII_Real", 8, _real(2, 0, 9), _real(3, 0, 9), "<validation_format>%7.2f</validation_format>"),
        Column("ffmt", "ASCII_Real", 8, _real(1, 0, 9), _choice("1.23", "7"), "<field_format>%7.1f</field_format>"),
    ]


def _character_record(columns: list[Column], rng: random.Random, ending: bytes, clean: bool) -> bytes:
    parts = []
    for column in columns:
        value = (
            column.bad(rng) if not clean and column.bad is not None and rng.random() < column.rate else column.good(rng)
        )
        raw = value.encode("utf-8") if isinstance(value, str) else value
        parts.append(raw[: column.length].rjust(column.length) + b" ")
    return b"".join(parts) + ending


def _character_fields(columns: list[Column]) -> tuple[str, int]:
    xml, location = [], 1
    for column in columns:
        xml.append(
            f"        <Field_Character><name>{column.name}</name><field_location>{location}</field_location>"
            f"<data_type>{column.data_type}</data_type><field_length>{column.length}</field_length>"
            f"{column.extra}</Field_Character>\n"
        )
        location += column.length + 1
    return "".join(xml), location - 1


def _character_table(
    name: str,
    records: int,
    fields: str,
    record_length: int,
    delimiter: str = "Carriage-Return Line-Feed",
    offset: int = 0,
    extra_fields: str = "",
) -> str:
    return (
        f'    <Table_Character><name>{name}</name><offset unit="byte">{offset}</offset><records>{records}</records>'
        f"<record_delimiter>{delimiter}</record_delimiter>\n"
        f'      <Record_Character><fields>0</fields><groups>0</groups><record_length unit="byte">{record_length}'
        f"</record_length>\n{fields}{extra_fields}      </Record_Character>\n    </Table_Character>\n"
    )


def character_cases(seed: int) -> list[Case]:
    rng = random.Random(seed)
    columns = _character_columns()
    fields, width = _character_fields(columns)
    cases = []
    for clean in (False, True):
        records = b"".join(_character_record(columns, rng, b"\r\n", clean) for _ in range(RECORDS))
        name = f"char_{'clean' if clean else 'faults'}_{seed}"
        cases.append(
            Case(
                name,
                _label(name, f"{name}.tab", _character_table("t", RECORDS, fields, width + 2)),
                records,
                f"{name}.tab",
            )
        )
    # a header before the table, Line-Feed records, a group of repeated fields
    header = b"HEADER" * 7
    group = (
        f"        <Group_Field_Character><repetitions>3</repetitions><fields>1</fields><groups>0</groups>"
        f"<group_location>{width + 1}</group_location><group_length>12</group_length>"
        "<Field_Character><name>rep</name><field_location>1</field_location><data_type>ASCII_Integer</data_type>"
        f"<field_length>4</field_length>{_stats(0, 500)}</Field_Character></Group_Field_Character>\n"
    )
    body = []
    for _ in range(RECORDS):
        reps = b"".join(str(rng.choice([1, 20, 499, 501, 7777, -3])).encode().rjust(4) for _ in range(3))
        body.append(_character_record(columns, rng, b"", False) + reps + b"\n")
    name = f"char_group_lf_{seed}"
    cases.append(
        Case(
            name,
            _label(
                name,
                f"{name}.tab",
                _character_table("grouped", RECORDS, fields, width + 12 + 1, "Line-Feed", len(header), group),
            ),
            header + b"".join(body),
            f"{name}.tab",
        )
    )
    cases += _character_structure_cases(seed, columns, fields, width, rng)
    return cases


def _character_structure_cases(
    seed: int, columns: list[Column], fields: str, width: int, rng: random.Random
) -> list[Case]:
    """Records that are not where the label says: short files, wrong delimiters, bad layouts."""
    cases = []
    good = [_character_record(columns, rng, b"\r\n", True) for _ in range(30)]
    variants = {
        "short": (good[:-1] + [good[-1][:10]], 30, "Carriage-Return Line-Feed", width + 2),
        "lf_label_crlf_data": (good, 30, "Line-Feed", width + 1),  # every record misread, stops at the first
        "broken_ends": (
            [r if i % 4 else r[:-2] + b"XY" for i, r in enumerate(good)],
            30,
            "Carriage-Return Line-Feed",
            width + 2,
        ),
        "more_stated": (good, 40, "Carriage-Return Line-Feed", width + 2),
        "misplaced": (good, 30, "Line-Feed", width + 3),  # a delimiter inside the first record: stop there
    }
    for variant, (records, count, delimiter, length) in variants.items():
        name = f"char_{variant}_{seed}"
        cases.append(
            Case(
                name,
                _label(name, f"{name}.tab", _character_table(variant, count, fields, length, delimiter)),
                b"".join(records),
                f"{name}.tab",
            )
        )
    layout = (
        "        <Field_Character><name>a</name><field_location>1</field_location><data_type>ASCII_Integer"
        "</data_type><field_length>6</field_length></Field_Character>\n"
        "        <Field_Character><name>b</name><field_location>4</field_location><data_type>ASCII_Integer"
        "</data_type><field_length>4</field_length></Field_Character>\n"
        "        <Field_Character><name>c</name><field_location>9</field_location><data_type>ASCII_Integer"
        "</data_type><field_length>6</field_length></Field_Character>\n"
    )
    name = f"char_layout_{seed}"
    data = b"".join(f"{i:6d}{i:6d}\r\n".encode() for i in range(20))
    cases.append(
        Case(name, _label(name, f"{name}.tab", _character_table("layout", 20, layout, 14)), data, f"{name}.tab")
    )
    return cases


_BINARY_TYPES = [
    ("IEEE754MSBSingle", ">f"),
    ("IEEE754LSBSingle", "<f"),
    ("IEEE754MSBDouble", ">d"),
    ("IEEE754LSBDouble", "<d"),
    ("SignedByte", "b"),
    ("UnsignedByte", "B"),
    ("SignedMSB2", ">h"),
    ("SignedLSB2", "<h"),
    ("UnsignedMSB2", ">H"),
    ("UnsignedLSB2", "<H"),
    ("SignedMSB4", ">i"),
    ("SignedLSB4", "<i"),
    ("UnsignedMSB4", ">I"),
    ("UnsignedLSB4", "<I"),
    ("SignedMSB8", ">q"),
    ("SignedLSB8", "<q"),
    ("UnsignedMSB8", ">Q"),
    ("UnsignedLSB8", "<Q"),
]


def binary_cases(seed: int) -> list[Case]:
    rng = random.Random(seed)
    xml, location, packers = [], 1, []
    for data_type, code in _BINARY_TYPES:
        size = struct.calcsize(code)
        signed = code[-1] in "bhiqfd"
        high = 100 if code[-1] in "bB" else 1000
        low = -high if signed else 0
        extra = _stats(low // 2, high // 2) + _special(str(low), "0x" + format(high - 1, "X"), valid=(low // 4, high))
        xml.append(
            f"        <Field_Binary><name>{data_type}</name><field_location>{location}</field_location>"
            f"<data_type>{data_type}</data_type><field_length>{size}</field_length>{extra}</Field_Binary>\n"
        )
        packers.append((code, low, high))
        location += size
    xml.append(
        f"        <Field_Binary><name>ascii</name><field_location>{location}</field_location>"
        "<data_type>ASCII_Integer</data_type><field_length>4</field_length>"
        f"{_stats(0, 50)}</Field_Binary>\n"
    )
    xml.append(
        f"        <Field_Binary><name>text</name><field_location>{location + 4}</field_location>"
        "<data_type>UTF8_String</data_type><field_length>3</field_length></Field_Binary>\n"
    )
    width = location - 1 + 7
    cases = []
    for clean in (False, True):
        rows = []
        for _ in range(RECORDS):
            row = b""
            for code, low, high in packers:
                value: float = (
                    rng.randint(low // 4, high // 4)
                    if clean
                    else rng.choice(
                        [rng.randint(low // 4, high // 4)] * 20
                        + [low, high - 1, high, low // 2 - 1 if low else 0, high // 2 + 1]
                    )
                )
                if code[-1] in "fd" and not clean and rng.random() < 0.05:
                    value = float("nan")
                row += struct.pack(code, value)
            row += (b"  12" if clean else rng.choice([b"  12", b"  99", b" x1 ", b"    "])) + (
                b"abc" if clean else rng.choice([b"abc", b"\xff\xfe\x00"])
            )
            rows.append(row)
        name = f"bin_{'clean' if clean else 'faults'}_{seed}"
        cases.append(
            Case(
                name,
                _label(name, f"{name}.dat", _binary_table("b", RECORDS, "".join(xml), width)),
                b"".join(rows),
                f"{name}.dat",
            )
        )
    bits = (
        "        <Field_Binary><name>packed</name><field_location>1</field_location><data_type>UnsignedMSB2"
        "</data_type><field_length>3</field_length><Packed_Data_Fields><bit_fields>3</bit_fields>"
        "<Field_Bit><name>x</name><start_bit_location>1</start_bit_location><stop_bit_location>5"
        "</stop_bit_location></Field_Bit><Field_Bit><name>y</name><start_bit_location>4</start_bit_location>"
        "<stop_bit_location>30</stop_bit_location></Field_Bit></Packed_Data_Fields></Field_Binary>\n"
        "        <Field_Binary><name>past</name><field_location>3</field_location><data_type>SignedMSB4"
        "</data_type><field_length>4</field_length></Field_Binary>\n"
    )
    name = f"bin_layout_{seed}"
    cases.append(
        Case(name, _label(name, f"{name}.dat", _binary_table("layout", 10, bits, 5)), bytes(50), f"{name}.dat")
    )
    name = f"bin_short_{seed}"
    cases.append(
        Case(
            name,
            _label(name, f"{name}.dat", _binary_table("short", 11, "".join(xml), width)),
            cases[0].data[: width * 10],
            f"{name}.dat",
        )
    )
    return cases


def _binary_table(name: str, records: int, fields: str, record_length: int) -> str:
    return (
        f'    <Table_Binary><name>{name}</name><offset unit="byte">0</offset><records>{records}</records>\n'
        f'      <Record_Binary><fields>0</fields><groups>0</groups><record_length unit="byte">{record_length}'
        f"</record_length>\n{fields}      </Record_Binary>\n    </Table_Binary>\n"
    )


def delimited_cases(seed: int) -> list[Case]:
    rng = random.Random(seed)
    fields = (
        "<Field_Delimited><name>id</name><data_type>ASCII_Integer</data_type>"
        f"<maximum_field_length>5</maximum_field_length>{_stats(0, 900)}</Field_Delimited>"
        "<Field_Delimited><name>value</name><data_type>ASCII_Real</data_type>"
        "<validation_format>%6.2f</validation_format></Field_Delimited>"
        "<Field_Delimited><name>word</name><data_type>ASCII_String</data_type></Field_Delimited>"
    )
    cases = []
    for clean in (False, True):
        lines = []
        for i in range(RECORDS):
            row = [str(i), f"{rng.uniform(0, 9):.2f}", '"a, b"']
            if not clean:
                fault = rng.randrange(14)
                if fault == 0:
                    row[0] = "1234567"
                elif fault == 1:
                    row[1] = "x.5"
                elif fault == 2:
                    row[2] = '"say ""hi"""'
                elif fault == 3:
                    row.append("extra")
                elif fault == 4:
                    row[1] = "3.1"
                elif fault == 5:
                    row[0] = "950"
            ending = "\n" if not clean and rng.random() < 0.05 else "\r\n"
            lines.append(",".join(row) + ending)
        name = f"dsv_{'clean' if clean else 'faults'}_{seed}"
        table = (
            f'    <Table_Delimited><name>d</name><offset unit="byte">0</offset><records>{RECORDS + (0 if clean else 3)}'
            "</records><record_delimiter>Carriage-Return Line-Feed</record_delimiter><field_delimiter>Comma"
            f"</field_delimiter>\n      <Record_Delimited><fields>3</fields><groups>0</groups>{fields}"
            "</Record_Delimited>\n    </Table_Delimited>\n"
        )
        cases.append(Case(name, _label(name, f"{name}.csv", table), "".join(lines).encode(), f"{name}.csv"))
    return cases


def inventory_cases(seed: int) -> list[Case]:
    rng = random.Random(seed)
    cases = []
    for clean in (False, True):
        rows, members = [], []
        for i in range(RECORDS):
            member = f"urn:nasa:pds:bundle:data:p{i:04d}::1.0"
            status = "P"
            if not clean:
                fault = rng.randrange(12)
                if fault == 0 and members:
                    member = rng.choice(members)
                elif fault == 1:
                    status = "X"
                elif fault == 2:
                    member = "not a lid"
                elif fault == 3:
                    member = member.split("::")[0]
            members.append(member)
            rows.append(f"{status},{member}\r\n")
        extra = "" if clean else "P,urn:nasa:pds:bundle:data:late::1.0\r\n\r\nS,urn:nasa:pds:bundle:data:later\r\n"
        name = f"inv_{'clean' if clean else 'faults'}_{seed}"
        table = (
            f'    <Inventory><offset unit="byte">0</offset><parsing_standard_id>PDS DSV 1</parsing_standard_id>'
            f"<records>{RECORDS}</records><record_delimiter>Carriage-Return Line-Feed</record_delimiter>"
            "<field_delimiter>Comma</field_delimiter>\n      <Record_Delimited><fields>2</fields><groups>0</groups>"
            "<Field_Delimited><name>Member Status</name><data_type>ASCII_String</data_type></Field_Delimited>"
            "<Field_Delimited><name>LIDVID_LID</name><data_type>ASCII_LIDVID_LID</data_type></Field_Delimited>"
            "</Record_Delimited>\n      <reference_type>inventory_has_member_product</reference_type>\n"
            "    </Inventory>\n"
        )
        cases.append(
            Case(name, _label(name, f"{name}.csv", table), "".join(rows).encode() + extra.encode(), f"{name}.csv")
        )
    return cases


SEEDS = (1, 2, 3)


def all_cases() -> list[Case]:
    """Every case of every seed, in a fixed order."""
    return [
        case
        for seed in SEEDS
        for make in (character_cases, binary_cases, delimited_cases, inventory_cases)
        for case in make(seed)
    ]
