"""DICT family: keyword types, ranges, lengths, standard values and units from the dictionary.

Severity follows who chose the dictionary. Against the built-in one, what genuine archives
contain (local keywords, units the list lacks, ranges and lengths broken, unquoted numbers
for text) is a warning or a note. When the user names dictionaries (`--dictionary FILE`),
those are the authority they validate against, as NASA's PDS3 validator does with its
dictionary: an element they do not define, a value outside their standard values, range or
length, a type mismatch and an unknown unit are then errors (`_authority_level`).

Placeholders ("N/A", "UNK", "NULL") skip the value checks: the PDS3 standard allows
them for any keyword. "NULL" is reported as information (a value still to be filled).
"""

from __future__ import annotations

import re
from collections.abc import Iterator

from ...label.grammar import DATA_TYPES
from ...label.parser import date_problem
from ...label.tree import Statement, Value
from ..context import FileContext
from ..dictionary import NUMERIC_PLACEHOLDERS, PLACEHOLDERS
from ..model import Hit
from ..registry import Rule, register

_LETTERS = re.compile(r"[A-Za-z ]+")
_ALNUM = re.compile(r"[A-Za-z0-9 ]+")
_NUMERIC = ("INTEGER", "ASCII_INTEGER", "REAL", "DOUBLE", "NONDECIMAL", "NON_DECIMAL")
_TEXT = ("CHARACTER", "ALPHANUMERIC", "IDENTIFIER", "ALPHABET")


def _statements(ctx: FileContext) -> list[tuple[Statement, dict | None]]:
    """(statement, definition or None) for every non-pointer statement; computed once."""
    cached = ctx.cache.get("_dict_statements")
    if cached is None:
        dictionary = ctx.dictionary
        cached = [(stmt, dictionary.lookup(stmt.keyword))
                  for block in ctx.root.walk() for stmt in block.statements() if not stmt.pointer]
        ctx.cache["_dict_statements"] = cached
    return cached


def _defined(ctx: FileContext) -> list[tuple[Statement, dict, Value]]:
    """(statement, definition, scalar) for every non-placeholder scalar of a known keyword."""
    cached = ctx.cache.get("_dict_defined")
    if cached is not None:
        return cached
    cached = []
    for stmt, entry in _statements(ctx):
        if entry is None:
            continue
        for value in stmt.value.scalars():
            if value.kind == "bad":
                continue  # already a SYNTAX finding
            if value.kind in ("string", "ident", "symbol") and (
                _norm(value) in PLACEHOLDERS or not str(value.py).strip()
            ):
                continue
            cached.append((stmt, entry, value))
    ctx.cache["_dict_defined"] = cached
    return cached


def _shown(value: Value) -> str:
    """The value as written, on one line, shortened for a message."""
    text = " ".join(value.raw.split())
    return text if len(text) <= 60 else text[:57] + "..."


def _norm(value: Value) -> str:
    return " ".join(str(value.py).split()).upper() if isinstance(value.py, str) else value.raw


def _authority_level(ctx: FileContext) -> str | None:
    """"error" when the user named the dictionaries (they are the authority: see the module
    docstring); else None, the rule's own severity."""
    return "error" if ctx.dictionary_is_authority else None


def check_unknown(ctx: FileContext) -> Iterator[Hit]:
    level = _authority_level(ctx)
    where = "the data dictionaries given" if level else "the PDS3 data dictionary"
    for stmt, entry in _statements(ctx):
        if entry is None:
            yield Hit(f"{stmt.keyword} is not in {where} or a known mission namespace", stmt.line, stmt.keyword,
                      severity=level)


# The integers a reader holds: 64 bits, signed or not. A longer one overflows every reader.
_INT_RANGE = (-(2**63), 2**64 - 1)


def _type_problem(kind: str, value: Value) -> str | None:
    if kind in ("INTEGER", "ASCII_INTEGER"):
        if value.kind == "int" and not _INT_RANGE[0] <= int(value.py) <= _INT_RANGE[1]:  # type: ignore[call-overload]
            return f"{_shown(value)} has {len(value.raw.lstrip('+-'))} digits: no reader holds an integer past 64 bits"
        if value.kind in ("int", "based"):
            return None
        if value.kind == "real":
            return f"{value.raw} is a real number, the keyword takes integers"
        return f"{value.raw!r} is not an integer"
    if kind in ("REAL", "DOUBLE"):
        return _real_problem(value)
    if kind in ("NONDECIMAL", "NON_DECIMAL"):
        return None if value.kind in ("based", "int") else f"{value.raw!r} is not a based integer"
    if kind == "ALPHABET" and not value.is_number and not _LETTERS.fullmatch(str(value.py).strip()):
        return f"{value.raw!r} is not letters only"
    if kind == "ALPHABET" and value.is_number:
        return f"{value.raw} is a number, the keyword takes letters"
    if kind == "ALPHANUMERIC" and not value.is_number and not _ALNUM.fullmatch(str(value.py).strip()):
        return f"{value.raw!r} is not letters and digits only"
    if kind in _TEXT:
        return None  # numbers for text keywords: see check_number_for_text
    if kind in ("DATE", "TIME"):
        if value.kind == "date" or (value.kind == "int" and len(value.raw) == 4):  # a year
            return None
        if value.kind in ("string", "symbol") and not date_problem(str(value.py).strip()):
            return None
        return f"{value.raw!r} is not a date/time"
    return None


def _real_problem(value: Value) -> str | None:
    """A REAL keyword takes decimal numbers, integers among them; a based integer (2#10001#)
    is for NONDECIMAL keywords - the standard has no based real, and NASA's tools reject it."""
    if value.kind == "based":
        return f"{value.raw} is a based integer, the keyword takes decimal (real) numbers"
    return None if value.is_number else f"{value.raw!r} is not a number"


def check_type(ctx: FileContext) -> Iterator[Hit]:
    for stmt, entry, value in _defined(ctx):
        if value.kind == "string" and not str(value.py).strip():
            continue  # empty "" is reported as a missing value (SYNTAX-009)
        problem = _type_problem(entry["type"], value)
        if problem:
            yield Hit(f"{stmt.keyword}: {problem} ({entry['type']})", value.line, stmt.keyword)


def _to_be_written(value: Value) -> bool:
    """A delivery's [TO BE WRITTEN: ...] placeholder: DLV-006 reports it, once."""
    from ...archive.layout import PLACEHOLDER_PATTERN  # loaded here: a product's label check never needs it

    return PLACEHOLDER_PATTERN.search(str(value.py)) is not None


def check_number_for_text(ctx: FileContext) -> Iterator[Hit]:
    """Unquoted numbers given to text keywords: readers take them, the dictionary wants text
    (a type mismatch, an error against the dictionaries the user named)."""
    level = _authority_level(ctx)
    for stmt, entry, value in _defined(ctx):
        if entry["type"] in _TEXT and entry["type"] != "ALPHABET" and value.is_number and not value.unit:
            yield Hit(f"{stmt.keyword} = {value.raw}: a number for a {entry['type']} keyword "
                      f'(write "{value.raw}")', value.line, stmt.keyword, severity=level)


def _placeholder(ctx: FileContext, value: Value) -> bool:
    """A mission's numeric "not applicable": -2147483648, -9.99e+31, -1e+32 (HRSC writes
    -1e+32 for RIGHT_ASCENSION of a surface image and a DA4's MEX:DTM radii)."""
    return value.is_number and value.py in NUMERIC_PLACEHOLDERS


# Units the range check converts between: unit -> (quantity, factor, offset) to the base unit
_CONVERSIONS = {
    "K": ("temperature", 1.0, 0.0), "KELVIN": ("temperature", 1.0, 0.0),
    "DEGC": ("temperature", 1.0, 273.15), "C": ("temperature", 1.0, 273.15),
    "KM": ("length", 1000.0, 0.0), "M": ("length", 1.0, 0.0), "METERS": ("length", 1.0, 0.0),
    "METRES": ("length", 1.0, 0.0), "CM": ("length", 0.01, 0.0), "MM": ("length", 0.001, 0.0),
    "DEG": ("angle", 1.0, 0.0), "DEGREES": ("angle", 1.0, 0.0), "RAD": ("angle", 180.0 / 3.141592653589793, 0.0),
    "S": ("time", 1.0, 0.0), "SEC": ("time", 1.0, 0.0), "MS": ("time", 0.001, 0.0),
    "MSEC": ("time", 0.001, 0.0), "MICROSECONDS": ("time", 1e-6, 0.0), "US": ("time", 1e-6, 0.0),
}


def in_dictionary_unit(entry: dict, value: Value) -> float | None:
    """The value in the dictionary's unit; None when its unit cannot be converted to it
    (then no range applies: -89.2 <DEGC> is compared with a range in K after conversion)."""
    number = float(value.py)  # type: ignore[arg-type]
    given = (value.unit or "").strip().upper()
    wanted = str(entry.get("unit", "")).strip().upper()
    if not given or given == wanted:
        return number
    source, target = _CONVERSIONS.get(given), _CONVERSIONS.get(wanted)
    if source is None or target is None or source[0] != target[0]:
        return None
    base = number * source[1] + source[2]
    return (base - target[2]) / target[1]


def _out_of_range(entry: dict, number: float | None) -> bool:
    lo, hi = entry.get("min"), entry.get("max")
    return number is not None and ((lo is not None and number < lo) or (hi is not None and number > hi))


def check_range(ctx: FileContext) -> Iterator[Hit]:
    for stmt, entry, value in _defined(ctx):
        if not value.is_number or entry["type"] not in _NUMERIC or _placeholder(ctx, value):
            continue
        lo, hi = entry.get("min"), entry.get("max")
        number = in_dictionary_unit(entry, value)
        if _out_of_range(entry, number):
            unit = f" <{entry['unit']}>" if value.unit and entry.get("unit") else ""
            shown = f" ({number:g}{unit})" if unit else ""
            yield Hit(f"{stmt.keyword} = {value.raw}{shown} is outside {lo if lo is not None else '-inf'}.."
                      f"{hi if hi is not None else 'inf'}{unit}", value.line, stmt.keyword,
                      severity=_deviation_level(ctx))


def _deviation_level(ctx: FileContext) -> str | None:
    """Ranges and lengths: warnings in labels others wrote (genuine archives break them, e.g.
    long DATA_SET_NAMEs), errors in labels pdsgen writes and under --strict (the writers
    refuse them before publishing, see products/agreement.py), and against the dictionaries
    the user named."""
    return "error" if ctx.strict or ctx.written_by_pdsgen or ctx.dictionary_is_authority else None


def check_hrsc_not_applicable(ctx: FileContext) -> Iterator[Hit]:
    """Where a numeric "not applicable" value falls outside a keyword's range, say so as
    information instead of a range finding."""
    for stmt, entry, value in _defined(ctx):
        if entry["type"] in _NUMERIC and _placeholder(ctx, value) and _out_of_range(entry, float(value.number)):
            yield Hit(f"{stmt.keyword} = {value.raw}: a numeric 'not applicable' value "
                      "(outside the dictionary range by design)", value.line, stmt.keyword)


def _standard(entry: dict, value: Value) -> bool:
    values = entry.get("values")
    if not values or value.is_number:
        return True
    upper = entry.get("_upper")
    if upper is None:
        upper = entry["_upper"] = frozenset(v.upper() for v in values)
    return _norm(value) in upper


# Keywords naming a mission, host, instrument or target: their STATIC lists grow as missions
# register, so a value newer than the shipped dictionary is no defect of the label.
IDENTITY_KEYWORDS = frozenset({
    "MISSION_NAME", "MISSION_ID", "MISSION_PHASE_NAME", "INSTRUMENT_HOST_NAME", "INSTRUMENT_HOST_ID",
    "INSTRUMENT_NAME", "INSTRUMENT_ID", "SPACECRAFT_NAME", "SPACECRAFT_ID", "TARGET_NAME", "DATA_SET_ID",
    "DATA_SET_NAME", "PRODUCER_INSTITUTION_NAME", "PRODUCER_ID", "VOLUME_SET_ID", "TELEMETRY_FORMAT_ID",
})


def _is_data_type(entry: dict, value: Value) -> bool:
    """A PDS3 data type given to a keyword whose standard values are data types
    (CORE_ITEM_TYPE = SUN_INTEGER): the dictionary and the IMG rules accept the same set."""
    return "MSB_INTEGER" in entry.get("values", ()) and _norm(value) in DATA_TYPES


def check_identity_values(ctx: FileContext) -> Iterator[Hit]:
    version = ctx.dictionary.version
    for stmt, entry, value in _defined(ctx):
        if (entry.get("values_type") == "STATIC" and stmt.keyword.upper() in IDENTITY_KEYWORDS
                and not _standard(entry, value)):
            yield Hit(f"{stmt.keyword} = {_shown(value)} is not registered in the data dictionary "
                      f"{version} (values registered since are not known here)", value.line, stmt.keyword)


# Keywords whose value tells a reader how to read the data: a non-standard value there is
# misread (an error); elsewhere a non-standard value describes, and is a warning.
LAYOUT_KEYWORDS = frozenset({
    "RECORD_TYPE", "INTERCHANGE_FORMAT", "SAMPLE_TYPE", "CORE_ITEM_TYPE", "DATA_TYPE", "ITEM_TYPE",
    "BAND_STORAGE_TYPE", "AXIS_ORDER_TYPE", "ENCODING_TYPE", "BIT_DATA_TYPE", "SUFFIX_ITEM_TYPE",
    "MAP_PROJECTION_TYPE", "COORDINATE_SYSTEM_TYPE", "POSITIVE_LONGITUDE_DIRECTION", "DATA_FORMAT",
    "TABLE_STORAGE_TYPE", "CORE_NULL", "SAMPLE_DISPLAY_DIRECTION", "LINE_DISPLAY_DIRECTION",
})


def _in_lower_case(entry: dict, value: Value) -> bool:
    """A standard value, all capitals in the dictionary, written with small letters (`yes` for
    YES): a warning, as NASA's tools give - readers that compare as written miss it."""
    if value.is_number or not isinstance(value.py, str) or value.py == value.py.upper():
        return False
    written = " ".join(value.py.split())
    return written not in entry.get("values", ()) and _standard(entry, value) and _norm(value) in entry["values"]


def check_static_values(ctx: FileContext) -> Iterator[Hit]:
    """An error where the keyword says how to read the data; a warning for descriptive
    keywords, for a standard value written with spaces for underscores (NOT POSSIBLE), and
    for one written in small letters (yes). Against the dictionaries the user named, any value
    outside the set is an error, spaces for underscores included; small letters stay a
    warning (NASA's tools rate them so too)."""
    authority = _authority_level(ctx)
    for stmt, entry, value in _defined(ctx):
        if stmt.keyword.upper() in IDENTITY_KEYWORDS or _is_data_type(entry, value):
            continue
        if entry.get("values_type") == "STATIC" and _in_lower_case(entry, value):
            yield Hit(f"{stmt.keyword} = {_shown(value)} is the standard value {_norm(value)} written in lower "
                      "case", value.line, stmt.keyword, severity="warning")
        if entry.get("values_type") == "STATIC" and not _standard(entry, value):
            shown = ", ".join(entry["values"][:8]) + (" ..." if len(entry["values"]) > 8 else "")
            spelled = "_".join(_norm(value).split())
            if spelled in entry["_upper"]:
                yield Hit(f"{stmt.keyword} = {_shown(value)} is the standard value {spelled} written with "
                          "spaces", value.line, stmt.keyword, severity=authority or "warning")
                continue
            level = None if stmt.keyword.upper() in LAYOUT_KEYWORDS else authority or "warning"
            yield Hit(f"{stmt.keyword} = {_shown(value)} is not one of its standard values ({shown})",
                      value.line, stmt.keyword, severity=level)


def check_suggested_values(ctx: FileContext) -> Iterator[Hit]:
    for stmt, entry, value in _defined(ctx):
        if entry.get("values_type") == "SUGGESTED" and not _standard(entry, value):
            yield Hit(f"{stmt.keyword} = {_shown(value)} is not among the dictionary's suggested values",
                      value.line, stmt.keyword)


def check_dynamic_values(ctx: FileContext) -> Iterator[Hit]:
    """DYNAMIC lists grow as data sets are registered: a value newer than the 2010 dictionary
    dump is no defect, but worth knowing; a warning against the dictionaries the user named
    (the lists they chose as current)."""
    level = "warning" if ctx.dictionary_is_authority else None
    for stmt, entry, value in _defined(ctx):
        if entry.get("values_type") == "DYNAMIC" and not _standard(entry, value) and not _to_be_written(value):
            yield Hit(f"{stmt.keyword} = {_shown(value)} is not among the dictionary's known values",
                      value.line, stmt.keyword, severity=level)


def check_length(ctx: FileContext) -> Iterator[Hit]:
    for stmt, entry, value in _defined(ctx):
        if value.is_number:
            length = len(value.raw.lstrip("+-"))
        else:
            length = len(" ".join(str(value.py).split()))
        lo, hi = entry.get("min_length"), entry.get("max_length")
        if lo is not None and length < lo:
            yield Hit(f"{stmt.keyword} has {length} characters, at least {lo}", value.line, stmt.keyword,
                      severity=_deviation_level(ctx))
        elif hi is not None and length > hi:
            yield Hit(f"{stmt.keyword} has {length} characters, at most {hi}", value.line, stmt.keyword,
                      severity=_deviation_level(ctx))


def check_units(ctx: FileContext) -> Iterator[Hit]:
    dictionary = ctx.dictionary
    level = _authority_level(ctx)
    for block in ctx.root.walk():
        for stmt in block.statements():
            units = {v.unit for v in stmt.value.scalars() if v.unit} | (
                {stmt.value.unit} if stmt.value.unit else set()
            )
            for unit in sorted(units):
                if not dictionary.knows_unit(unit):
                    yield Hit(f"{stmt.key}: unit <{unit}> is not a PDS unit", stmt.line, stmt.key, severity=level)


# What each common unit measures; a value's unit must measure what the dictionary's does.
_DIMENSIONS = {
    "length": {"KM", "M", "MM", "METER", "METERS", "METRE", "METRES", "KILOMETER", "KILOMETERS",
               "KILOMETRE", "KILOMETRES", "MICRON", "NM", "CM"},
    "angle": {"DEG", "DEGREE", "DEGREES", "RAD", "RADIAN", "RADIANS", "MRAD", "ARCSEC", "ARCSECOND"},
    "time": {"S", "SEC", "SECOND", "SECONDS", "MS", "MSEC", "MILLISECONDS", "US", "MICROSECONDS", "D",
             "DAY", "DAYS", "H", "HOUR", "HOURS", "MIN", "MINUTE", "MINUTES"},
    "temperature": {"K", "DEGC", "C", "KELVIN"},
    "pixel scale": {"KM/PIX", "KM/PIXEL", "M/PIX", "M/PIXEL", "METERS/PIXEL", "METRES/PIXEL"},
    "map resolution": {"PIX/DEG", "PIXEL/DEGREE", "PIXELS/DEGREE", "PIXEL/DEG"},
    "pixels": {"PIXEL", "PIXELS", "PIX"},
}
_DIMENSION_OF = {unit: dim for dim, units in _DIMENSIONS.items() for unit in units}


def check_unit_dimension(ctx: FileContext) -> Iterator[Hit]:
    """<DEG> where the dictionary measures in KM, and the like."""
    for stmt, entry, value in _defined(ctx):
        expected = _DIMENSION_OF.get(str(entry.get("unit", "")).upper())
        given = _DIMENSION_OF.get((value.unit or "").upper().replace(" ", ""))
        if expected == "pixel scale" and given == "length":
            continue  # a pixel scale in <KM> (NEAR MSI): per pixel is understood
        if expected and given and expected != given:
            yield Hit(f"{stmt.keyword} is a {expected} (dictionary unit {entry['unit']}) but is given in "
                      f"<{value.unit}>, a {given}", value.line, stmt.keyword)


def check_placeholder(ctx: FileContext) -> Iterator[Hit]:
    for block in ctx.root.walk():
        for stmt in block.statements():
            if any(v.kind in ("string", "ident") and _norm(v) == "NULL" for v in stmt.value.scalars()):
                yield Hit(f"{stmt.key} = NULL: a value still to be supplied", stmt.line, stmt.key)


_WRITERS_NOTE = "error in labels pdsgen writes and under --strict: its writers refuse them"
_AUTHORITY_NOTE = "error against the dictionaries given with --dictionary"

register(
    Rule("DICT-001", "warning", "keywords are defined in the data dictionary or a mission namespace",
         check_unknown, note=_AUTHORITY_NOTE),
    Rule("DICT-002", "error", "values have the dictionary type of their keyword", check_type),
    Rule("DICT-003", "warning", "numeric values lie within the dictionary range (in its unit)",
         check_range, note=_WRITERS_NOTE + "; " + _AUTHORITY_NOTE),
    Rule("DICT-004", "error", "values of closed (STATIC) value sets are standard values",
         check_static_values),
    Rule("DICT-013", "warning", "mission identity values (MISSION_NAME, INSTRUMENT_HOST_ID ...) are "
         "registered in the shipped dictionary version", check_identity_values),
    Rule("DICT-005", "warning", "values of SUGGESTED value sets are among the suggestions",
         check_suggested_values),
    Rule("DICT-010", "info", "values of DYNAMIC value sets not yet in the dictionary",
         check_dynamic_values, note="warning against the dictionaries given with --dictionary"),
    Rule("DICT-009", "info", "text keywords given unquoted numbers (readers accept them)",
         check_number_for_text, note=_AUTHORITY_NOTE),
    Rule("DICT-006", "warning", "value lengths lie within the dictionary minimum/maximum length",
         check_length, note=_WRITERS_NOTE + "; " + _AUTHORITY_NOTE),
    Rule("DICT-007", "warning", "units are known PDS units", check_units, note=_AUTHORITY_NOTE),
    Rule("DICT-011", "error", "units measure what the dictionary's unit measures (KM, DEG ...)",
         check_unit_dimension),
    Rule("DICT-012", "info", "numeric 'not applicable' values (-2147483648, -9.99e+31, -1e+32) are "
         "exempt from DICT-003", check_hrsc_not_applicable),
    Rule("DICT-008", "info", "placeholder values (NULL) are reported", check_placeholder),
)
