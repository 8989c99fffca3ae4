"""A PDS4 bundle of many copies of one Table_Character product, for validation at scale
(tests/test_validate_parallel.py with a few dozen products, bench/validate_scale.py with up
to 100,000) and a single table of millions of records.

The product is made here, not copied: an IM 1.24 (1O00) Product_Observational whose table
has 304 records of 16 fields, the shape of the IM 1.24 test product the scale issue was
measured on (a Table_Character of 304 records x 16 fields, 22 KB of data). Its fields are
of the kinds such tables hold - a UTC time, reals with Field_Statistics and a
field_format, integers with a missing constant, a boolean, a hexadecimal - so every
column check runs. Records are made by numpy, so a table of 10 million is written in
seconds. The bundle: bundle_scale.xml (or `bundle_name`), one data collection with its
inventory, products data/pNNNNNN.xml + .tab.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

NS = "http://pds.nasa.gov/pds4/pds/v1"
BUNDLE = "urn:nasa:pds:scale_test"
RECORDS = 304
_HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n'
         '<?xml-model href="http://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.sch" '
         'schematypens="http://purl.oclc.org/dsdl/schematron"?>\n')
_SCHEMA = (f'xmlns="{NS}" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" '
           f'xsi:schemaLocation="{NS} https://pds.nasa.gov/pds4/pds/v1/PDS4_PDS_1O00.xsd"')

# name, data_type, width, extra XML inside the field (16 fields; one blank between them)
FIELDS: list[tuple[str, str, int, str]] = [
    ("utc", "ASCII_Date_Time_YMD_UTC", 20, ""),
    *[(f"real{i}", "ASCII_Real", 6, "<field_format>%6.2f</field_format>"
       "<Field_Statistics><maximum>99.99</maximum><minimum>-99.99</minimum></Field_Statistics>") for i in range(1, 7)],
    *[(f"count{i}", "ASCII_Integer", 5, "<Special_Constants><missing_constant>-9999</missing_constant>"
       "</Special_Constants>") for i in range(1, 5)],
    ("quality", "ASCII_NonNegative_Integer", 3, ""),
    ("flag", "ASCII_Boolean", 1, ""),
    ("mask", "ASCII_Numeric_Base16", 4, ""),
    ("channel", "ASCII_Integer", 3, ""),
    ("gain", "ASCII_Real", 8, ""),
]
RECORD_LENGTH = sum(width + 1 for _, _, width, _ in FIELDS) - 1 + 2  # blanks between fields, CR LF


def table_rows(count: int, seed: int = 0, start: int = 0) -> bytes:
    """`count` records (from record `start`, for writing a long table in parts) of the product's table."""
    rng = np.random.default_rng(seed + start)
    index = np.arange(start, start + count)
    seconds = index % 86400
    columns = [np.char.add(np.char.add("2019-08-06T", np.char.zfill((seconds // 3600).astype(str), 2)),
                           np.char.add(np.char.add(":", np.char.zfill((seconds // 60 % 60).astype(str), 2)),
                                       np.char.add(np.char.add(":", np.char.zfill((seconds % 60).astype(str), 2)),
                                                   "Z")))]
    columns += [np.char.mod("%6.2f", rng.uniform(-99.99, 99.99, count)) for _ in range(6)]
    columns += [np.char.mod("%5d", np.where(rng.random(count) < 0.01, -9999, rng.integers(-999, 9999, count)))
                for _ in range(4)]
    columns += [np.char.mod("%3d", rng.integers(0, 999, count)), np.where(rng.random(count) < 0.5, "1", "0"),
                np.char.mod("%04X", rng.integers(0, 65535, count)), np.char.mod("%3d", index % 256),
                np.char.mod("%8.3f", rng.uniform(0, 9999, count))]
    row = columns[0]
    for column in columns[1:]:
        row = np.char.add(np.char.add(row, " "), column)
    return "".join(np.char.add(row, "\r\n").tolist()).encode("ascii")


def product_label(lid: str, data_name: str, records: int, title: str = "Scale test table") -> str:
    fields, location = [], 1
    for name, data_type, width, extra in FIELDS:
        fields.append(f"        <Field_Character>\n          <name>{name}</name>\n"
                      f"          <field_location unit=\"byte\">{location}</field_location>\n"
                      f"          <data_type>{data_type}</data_type>\n"
                      f"          <field_length unit=\"byte\">{width}</field_length>\n"
                      f"          {extra}\n        </Field_Character>\n")
        location += width + 1
    return (f"{_HEAD}<Product_Observational {_SCHEMA}>\n"
            f"  <Identification_Area>\n    <logical_identifier>{lid}</logical_identifier>\n"
            f"    <version_id>1.0</version_id>\n    <title>{title}</title>\n"
            "    <information_model_version>1.24.0.0</information_model_version>\n"
            "    <product_class>Product_Observational</product_class>\n  </Identification_Area>\n"
            "  <Observation_Area>\n    <Time_Coordinates>\n"
            "      <start_date_time>2019-08-06T00:00:00Z</start_date_time>\n"
            "      <stop_date_time>2019-08-06T23:59:59Z</stop_date_time>\n    </Time_Coordinates>\n"
            "    <Investigation_Area>\n      <name>Scale Test</name>\n      <type>Other Investigation</type>\n"
            "      <Internal_Reference>\n        <lid_reference>urn:nasa:pds:context:investigation:"
            "individual.none</lid_reference>\n        <reference_type>data_to_investigation</reference_type>\n"
            "      </Internal_Reference>\n    </Investigation_Area>\n"
            "    <Observing_System>\n      <Observing_System_Component>\n        <name>Test Instrument</name>\n"
            "        <type>Instrument</type>\n      </Observing_System_Component>\n    </Observing_System>\n"
            "    <Target_Identification>\n      <name>Mars</name>\n      <type>Planet</type>\n"
            "    </Target_Identification>\n  </Observation_Area>\n"
            f"  <File_Area_Observational>\n    <File>\n      <file_name>{data_name}</file_name>\n    </File>\n"
            "    <Table_Character>\n      <name>scale_table</name>\n      <offset unit=\"byte\">0</offset>\n"
            f"      <records>{records}</records>\n"
            "      <record_delimiter>Carriage-Return Line-Feed</record_delimiter>\n"
            f"      <Record_Character>\n        <fields>{len(FIELDS)}</fields>\n        <groups>0</groups>\n"
            f"        <record_length unit=\"byte\">{RECORD_LENGTH}</record_length>\n{''.join(fields)}"
            "      </Record_Character>\n    </Table_Character>\n  </File_Area_Observational>\n"
            "</Product_Observational>\n")


def write_table(directory: Path, name: str, records: int, block: int = 1_000_000) -> Path:
    """A label and a table of `records` records (written `block` records at a time)."""
    directory.mkdir(parents=True, exist_ok=True)
    with open(directory / f"{name}.tab", "wb") as handle:
        for start in range(0, records, block):
            handle.write(table_rows(min(block, records - start), start=start))
    label = directory / f"{name}.xml"
    label.write_text(product_label(f"{BUNDLE}:data:{name}", f"{name}.tab", records), encoding="utf-8")
    return label


_CITATION = ("    <Citation_Information>\n      <publication_year>2026</publication_year>\n"
             "      <description>Copies of one table product, for validation at scale.</description>\n"
             "    </Citation_Information>\n")


def _collection_label(products: int) -> str:
    return (f"{_HEAD}<Product_Collection {_SCHEMA}>\n"
            f"  <Identification_Area>\n    <logical_identifier>{BUNDLE}:data</logical_identifier>\n"
            "    <version_id>1.0</version_id>\n    <title>Scale test data collection</title>\n"
            "    <information_model_version>1.24.0.0</information_model_version>\n"
            "    <product_class>Product_Collection</product_class>\n" + _CITATION + "  </Identification_Area>\n"
            "  <Collection>\n    <collection_type>Data</collection_type>\n  </Collection>\n"
            "  <File_Area_Inventory>\n    <File>\n      <file_name>collection_data_inventory.csv</file_name>\n"
            "    </File>\n    <Inventory>\n      <offset unit=\"byte\">0</offset>\n"
            "      <parsing_standard_id>PDS DSV 1</parsing_standard_id>\n"
            f"      <records>{products}</records>\n"
            "      <record_delimiter>Carriage-Return Line-Feed</record_delimiter>\n"
            "      <field_delimiter>Comma</field_delimiter>\n      <Record_Delimited>\n        <fields>2</fields>\n"
            "        <groups>0</groups>\n        <Field_Delimited>\n          <name>Member Status</name>\n"
            "          <field_number>1</field_number>\n          <data_type>ASCII_String</data_type>\n"
            "          <maximum_field_length unit=\"byte\">1</maximum_field_length>\n        </Field_Delimited>\n"
            "        <Field_Delimited>\n          <name>LIDVID_LID</name>\n          <field_number>2</field_number>\n"
            "          <data_type>ASCII_LIDVID_LID</data_type>\n"
            "          <maximum_field_length unit=\"byte\">255</maximum_field_length>\n        </Field_Delimited>\n"
            "      </Record_Delimited>\n      <reference_type>inventory_has_member_product</reference_type>\n"
            "    </Inventory>\n  </File_Area_Inventory>\n</Product_Collection>\n")


def _bundle_label() -> str:
    return (f"{_HEAD}<Product_Bundle {_SCHEMA}>\n"
            f"  <Identification_Area>\n    <logical_identifier>{BUNDLE}</logical_identifier>\n"
            "    <version_id>1.0</version_id>\n    <title>Scale test bundle</title>\n"
            "    <information_model_version>1.24.0.0</information_model_version>\n"
            "    <product_class>Product_Bundle</product_class>\n" + _CITATION + "  </Identification_Area>\n"
            "  <Bundle>\n    <bundle_type>Archive</bundle_type>\n  </Bundle>\n"
            "  <Bundle_Member_Entry>\n    <lidvid_reference>"
            f"{BUNDLE}:data::1.0</lidvid_reference>\n    <member_status>Primary</member_status>\n"
            "    <reference_type>bundle_has_data_collection</reference_type>\n  </Bundle_Member_Entry>\n"
            "</Product_Bundle>\n")


def make_bundle(root: Path, products: int, bundle_name: str = "bundle_scale.xml", fault_last: bool = False,
                per_directory: int = 1000) -> Path:
    """A bundle of `products` copies of the table product (`per_directory` to a directory).
    fault_last: the last product's table has a value out of its Field_Statistics range and the
    last product is left out of the inventory (two faults only the full run finds)."""
    rows = table_rows(RECORDS)
    data = root / "data"
    inventory = []
    for number in range(products):
        name = f"p{number:06d}"
        directory = data / f"d{number // per_directory:03d}"
        directory.mkdir(parents=True, exist_ok=True)
        lid = f"{BUNDLE}:data:{name}"
        table = rows
        if fault_last and number == products - 1:
            table = rows[:RECORD_LENGTH * 100 + 21] + b"123.45" + rows[RECORD_LENGTH * 100 + 27:]
        (directory / f"{name}.tab").write_bytes(table)
        (directory / f"{name}.xml").write_text(product_label(lid, f"{name}.tab", RECORDS), encoding="utf-8")
        if not (fault_last and number == products - 1):
            inventory.append(f"P,{lid}::1.0\r\n")
    (data / "collection_data_inventory.csv").write_text("".join(inventory), encoding="ascii", newline="")
    (data / "collection_data.xml").write_text(_collection_label(len(inventory)), encoding="utf-8")
    (root / bundle_name).write_text(_bundle_label(), encoding="utf-8")
    return root
