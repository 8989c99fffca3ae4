"""What a PDS3 keyword becomes in a PDS4 label that describes the PDS3 file unchanged.

The tables here are the ones the migration code reads (objects.py, identity.py), and the
README's "Migrating PDS3 products" table is generated from `KEYWORD_TABLE` (a test holds
the two together). Sample and column data types are not repeated here: they come from
`pds4.model.pds4_data_type`, the join of PDS3's SAMPLE_TYPES and PDS4's DATA_TYPES.
"""

from __future__ import annotations

# PDS3 special-constant keywords -> PDS4 Special_Constants elements.
SPECIAL_CONSTANTS = {
    "MISSING_CONSTANT": "missing_constant",
    "NULL": "missing_constant",
    "CORE_NULL": "missing_constant",
    "INVALID_CONSTANT": "invalid_constant",
    "SATURATED_CONSTANT": "saturated_constant",
    "VALID_MAXIMUM": "valid_maximum",
    "CORE_HIGH_INSTR_SATURATION": "high_instrument_saturation",
    "CORE_HIGH_REPR_SATURATION": "high_representation_saturation",
    "VALID_MINIMUM": "valid_minimum",
    "CORE_LOW_INSTR_SATURATION": "low_instrument_saturation",
    "CORE_LOW_REPR_SATURATION": "low_representation_saturation",
}
# The schema's order of Special_Constants' elements.
SPECIAL_ORDER = ("saturated_constant", "missing_constant", "error_constant", "invalid_constant",
                 "unknown_constant", "not_applicable_constant", "valid_maximum", "high_instrument_saturation",
                 "high_representation_saturation", "valid_minimum", "low_instrument_saturation",
                 "low_representation_saturation")

# BAND_STORAGE_TYPE -> the axes, slowest first (PDS4 arrays are Last Index Fastest).
BAND_STORAGE_AXES = {
    "BAND_SEQUENTIAL": ("Band", "Line", "Sample"),
    "LINE_INTERLEAVED": ("Line", "Band", "Sample"),
    "SAMPLE_INTERLEAVED": ("Line", "Sample", "Band"),
}

# A header object's TYPE (IMAGE_HEADER, TABLE_HEADER ...) -> parsing_standard_id.
HEADER_STANDARDS = {
    "VICAR": "VICAR2",
    "VICAR2": "VICAR2",
    "VICAR1": "VICAR1",
    "FITS": "FITS 3.0",
    "ISIS": "ISIS2",
    "ISIS2": "ISIS2",
    "PDS3": "PDS3",
    "ASCII": "7-Bit ASCII Text",
    "TEXT": "7-Bit ASCII Text",
}

# Column DATA_TYPEs stored as text -> Field data_type (Table_Character and Table_Binary).
# DATE and TIME become strings: PDS3 allows forms (day of year, no zone) PDS4's date types do not.
TEXT_FIELD_TYPES = {
    "ASCII_REAL": "ASCII_Real",
    "ASCII_INTEGER": "ASCII_Integer",
    "CHARACTER": "ASCII_String",
    "DATE": "ASCII_String",
    "TIME": "ASCII_String",
}

# In an ASCII table PDS3's generic numeric names mean numbers written as text (Standards
# Reference, appendix C); byte-order names (MSB_INTEGER ...) have no meaning there.
ASCII_TABLE_TYPES = {
    **TEXT_FIELD_TYPES,
    "INTEGER": "ASCII_Integer",
    "UNSIGNED_INTEGER": "ASCII_NonNegative_Integer",
    "REAL": "ASCII_Real",
    "FLOAT": "ASCII_Real",
}

# Bit-string columns read whole (their BIT_COLUMNs not split): PDS4's bit strings are MSB first;
# an LSB_BIT_STRING's bytes run the other way and have no PDS4 type.
BIT_STRING_TYPES = {"MSB_BIT_STRING": "UnsignedBitString", "BIT_STRING": "UnsignedBitString"}

# BIT_COLUMN BIT_DATA_TYPE -> Field_Bit data_type (PDS4 states a bit field's sign, nothing else).
BIT_DATA_TYPES = {
    "MSB_INTEGER": "SignedBitString", "INTEGER": "SignedBitString", "SIGNED_INTEGER": "SignedBitString",
    "MSB_UNSIGNED_INTEGER": "UnsignedBitString", "UNSIGNED_INTEGER": "UnsignedBitString",
    "BOOLEAN": "UnsignedBitString", "BIT_STRING": "UnsignedBitString", "MSB_BIT_STRING": "UnsignedBitString",
}

# SPREADSHEET FIELD_DELIMITER -> Table_Delimited field_delimiter.
FIELD_DELIMITERS = {"COMMA": "Comma", "TAB": "Horizontal Tab", "SEMICOLON": "Semicolon",
                    "VERTICAL_BAR": "Vertical Bar"}

# PDS3 object classes by name (fnmatch patterns, tried in order) -> the describer that takes
# them (objects.py's DESCRIBERS) and what it writes. docs/migrate-objects.md lists these rows
# and OTHER_OBJECTS' (a test holds page and code together).
OBJECT_CLASSES: tuple[tuple[str, str, str], ...] = (
    ("*HEADER", "header", "Header: parsing_standard_id from TYPE/HEADER_TYPE (FITS, VICAR, ISIS, PDS3 ...); "
     "SPREADSHEET, SFDU, TEXT or no type: 7-Bit ASCII Text or UTF-8 Text as the bytes are, else refused; "
     "length BYTES, or RECORDS x RECORD_BYTES; INTERCHANGE_FORMAT BINARY of no standard PDS4 parses (a Galileo SSI "
     "BAD_DATA_VALUES_HEADER, HEADER_TYPE BDV): Table_Binary of RECORDS records, each its bytes (UnsignedByte)"),
    ("HISTORY", "header", "Header: ISIS2 History Label in an ISIS2 cube, else 7-Bit ASCII Text or UTF-8 Text "
     "as the bytes are; bytes that are not text: refused"),
    ("*_HISTORY", "header", "Header, as HISTORY"),
    ("IMAGE", "image", "Array_2D_Image (BANDS = 1), Array_3D_Image (axes from BAND_STORAGE_TYPE); with "
     "LINE_PREFIX_BYTES/LINE_SUFFIX_BYTES: Table_Binary, a record per line (band sequential only)"),
    ("*_IMAGE", "image", "as IMAGE"),
    ("*HISTOGRAM", "histogram", "Array_1D (ITEMS of DATA_TYPE, ITEM_BYTES); with ROWS and COLUMNs: as a TABLE"),
    ("*TABLE", "table", "Table_Binary (INTERCHANGE_FORMAT BINARY), Table_Character (ASCII, records ending "
     "CR LF or LF as the bytes show); COLUMN ITEMS: Group_Field_*; CONTAINER: Group_Field_* (nested, "
     "REPETITIONS)"),
    ("*SERIES", "table", "as TABLE"),
    ("*SPECTRUM", "table", "as TABLE"),
    ("*SPREADSHEET", "spreadsheet", "Table_Delimited (parsing standard PDS DSV 1, FIELD_DELIMITER: "
     "COMMA, SEMICOLON, TAB, VERTICAL_BAR; FIELD objects, a ^STRUCTURE file's in its place, as Field_Delimited, "
     "a FIELD of ITEMS as ITEMS fields NAME_1 ...; every record must hold that many values, quotes respected)"),
    ("*ARRAY", "array", "ARRAY of one number per element (its own DATA_TYPE and BYTES, or an ELEMENT; nested "
     "ARRAYs add their axes): Array_1D, Array_2D, Array_3D or Array (more axes), the axes in PDS3's order (both "
     "store the last fastest), AXIS_NAME as axis_name; ARRAY of COLLECTIONs, or of an ELEMENT with BIT_ELEMENTs: "
     "Table_Binary, a record per element (axes flattened, last fastest); INTERCHANGE_FORMAT ASCII: "
     "Table_Character of a record per line when every line holds the last axis' values at the same columns, "
     "evenly spaced (read from the bytes: PDS3 states no layout), the values a repeated field; else refused"),
    ("*COLLECTION", "array", "Table_Binary of one record: its ELEMENTs Field_Binary, its COLLECTIONs "
     "Group_Field_Binary, its ARRAYs Group_Field_Binary of their elements' number of repetitions"),
    ("*QUBE", "qube", "(keywords of its ^STRUCTURE files included) Array_3D of the core (axes AXIS_NAME "
     "reversed, CORE_ITEM_TYPE/BYTES, CORE_BASE/"
     "CORE_MULTIPLIER as value_offset/scaling_factor, CORE_NULL and the CORE_* special values); suffix "
     "items along the fastest axis only (side planes of a SAMPLE-fastest cube): Table_Binary, a record per run "
     "of that axis (the core's items a group, each suffix item a field); suffix planes along the slowest axis "
     "only (back planes of a band-sequential cube): the core Array_3D, each plane an Array_2D after it; suffix "
     "planes along the middle axis (bottom planes, with or without side planes): slice by slice of the slowest "
     "axis, its core (Array_2D, or a table of a record per run with its side items) and its bottom runs (a "
     "Table_Binary, corner bytes a byte group); side and back planes together: the core's runs with their "
     "side items as records, each back plane a table after it; back planes with bottom planes: refused, named; "
     "an IMAGE_MAP_PROJECTION group (ISIS2 keeps it in the QUBE): cart: on the core array (its Line and Sample axes)"),
)
# Label constructs that are not data objects of their own, and what migrate does with them.
OTHER_OBJECTS: tuple[tuple[str, str], ...] = (
    ("OBJECT = FILE (combined detached label)", "each pointer in it described in its file, records counted "
     "in the FILE block's RECORD_BYTES; one File_Area_Observational per file"),
    ("an object of another name with LINES, LINE_SAMPLES, SAMPLE_TYPE and SAMPLE_BITS", "as IMAGE"),
    ("COMPRESSED_FILE (ENCODING_TYPE JP2)", "Encoded_Image in File_Area_Observational_Supplemental"),
    ("COLUMN DATA_TYPE MSB_BIT_STRING (also spelled MSB BIT STRING)", "Field_Binary UnsignedBitString"),
    ("BIT_COLUMN (in an MSB or 1-byte COLUMN)", "Packed_Data_Fields/Field_Bit, the column UnsignedBitString; "
     "BIT_DATA_TYPE: " + ", ".join(f"{k} -> {v}" for k, v in BIT_DATA_TYPES.items()) + "; ITEMS: one Field_Bit "
     "each; in an LSB column: refused"),
    ("BIT_ELEMENT (in an ELEMENT)", "as BIT_COLUMN: Packed_Data_Fields/Field_Bit of the element's field, the "
     "array then a Table_Binary (PDS4 arrays have no bit fields)"),
    ("a spare column (named SPARE, FILLER, PAD, UNUSED, RESERVED ...) of a DATA_TYPE PDS4 has no type for "
     "(IBM_REAL, VAX_REAL ...)", "its bytes as a Group_Field_Binary of UnsignedByte under its name (a warning says "
     "so): it holds no value, so stating its bytes keeps every byte of the record accounted for and claims no "
     "number format; a column of values of such a type: refused"),
    ("CONTAINER (REPETITIONS, nested CONTAINERs)", "Group_Field_Binary / Group_Field_Character: repetitions, "
     "group_location START_BYTE, group_length REPETITIONS x BYTES, its COLUMNs and CONTAINERs inside"),
    ("any other object (PALETTE, DOCUMENT, ...)", "refused, named with its line"),
)

# INTERCHANGE_FORMAT -> the PDS4 table class.
TABLE_CLASSES = {"BINARY": "Table_Binary", "ASCII": "Table_Character"}

# CODMAC level, the fourth part of a DATA_SET_ID (MGS-M-MOLA-5-MEGDR-L3-V1.0) -> processing_level.
PROCESSING_LEVELS = {"1": "Raw", "2": "Raw", "3": "Calibrated", "4": "Derived", "5": "Derived", "6": "Derived"}

# The README's table: PDS3 keyword or object -> PDS4 class/attribute (what the code writes).
KEYWORD_TABLE: tuple[tuple[str, str], ...] = (
    ("attached label (bytes before the first object)", "File_Area_Observational/Header (parsing_standard_id PDS3)"),
    ("detached label file", "File_Area_Observational_Supplemental/Header (parsing_standard_id PDS3)"),
    ("^IMAGE_HEADER, ^TABLE_HEADER ... with TYPE", "Header (parsing_standard_id from TYPE: "
     + ", ".join(sorted(set(HEADER_STANDARDS.values()))) + ")"),
    ("OBJECT = IMAGE, BANDS = 1", "Array_2D_Image (axes Line, Sample)"),
    ("OBJECT = IMAGE, BANDS > 1, BAND_STORAGE_TYPE",
     "Array_3D_Image, axes " + "; ".join(f"{k}: {', '.join(v)}" for k, v in BAND_STORAGE_AXES.items())),
    ("OBJECT = IMAGE with LINE_PREFIX_BYTES / LINE_SUFFIX_BYTES", "Table_Binary, a record per line: "
     "Group_Field_Binary LINE_PREFIX, SAMPLES, LINE_SUFFIX (an array has no stride)"),
    ("^IMAGE / ^TABLE (record or <BYTES>) x RECORD_BYTES", "offset (bytes)"),
    ("SAMPLE_TYPE + SAMPLE_BITS", "Element_Array/data_type (pds4.model.pds4_data_type)"),
    ("SCALING_FACTOR, OFFSET", "Element_Array/scaling_factor, value_offset"),
    ("UNIT", "Element_Array/unit, Field_*/unit"),
    *((keyword, f"Special_Constants/{element}") for keyword, element in SPECIAL_CONSTANTS.items()),
    ("OBJECT = *TABLE / *SERIES, INTERCHANGE_FORMAT", "Table_Binary (BINARY), Table_Character (ASCII)"),
    ("ROWS, ROW_BYTES (+ ROW_PREFIX_BYTES, ROW_SUFFIX_BYTES)", "records, Record_*/record_length"),
    ("COLUMN NAME, START_BYTE, BYTES, DATA_TYPE", "Field_Binary / Field_Character name, field_location, "
     "field_length, data_type"),
    *((f"COLUMN DATA_TYPE = {k}", f"data_type {v}") for k, v in TEXT_FIELD_TYPES.items()),
    *((f"COLUMN DATA_TYPE = {k} (ASCII table)", f"data_type {v}") for k, v in ASCII_TABLE_TYPES.items()
      if k not in TEXT_FIELD_TYPES),
    ("COLUMN ITEMS, ITEM_BYTES, ITEM_OFFSET", "Group_Field_Binary / Group_Field_Character (repetitions)"),
    ("^STRUCTURE (format file)", "its COLUMNs, in place"),
    ("IMAGE_MAP_PROJECTION", "Discipline_Area/cart:Cartography (offset convention as the validator decides)"),
    ("PRODUCT_ID", "Alias_List/Alias/alternate_id (and the LID's last part)"),
    ("DATA_SET_ID", "Alias_List/Alias/alternate_id; its CODMAC level -> processing_level"),
    ("START_TIME, STOP_TIME", "Time_Coordinates/start_date_time, stop_date_time (UTC)"),
    ("MISSION_NAME / INSTRUMENT_HOST_NAME / SPACECRAFT_NAME", "Investigation_Area, Observing_System (Host)"),
    ("INSTRUMENT_NAME / INSTRUMENT_ID", "Observing_System_Component (Instrument)"),
    ("TARGET_NAME", "Target_Identification"),
    ("SOURCE_PRODUCT_ID (N/A: none)", "Reference_List/Source_Product_External/external_source_product_identifier"),
)
