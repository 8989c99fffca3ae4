"""Regenerate schemas/pds3_dictionary.json from the PDS3 data dictionary.

Usage (from the repository root):

    python tools/build_dictionary.py [PATH/TO/pdsdd.full] [OUTPUT.json]

Defaults: ../shared/corpus/reference/pdsdd.full and schemas/pds3_dictionary.json.

The shipped schemas/pds3_dictionary.json is built from the newest PSDD dump that could be
verified in a public repository: pdscat1r102, generated 2017-09-25, the dump NASA's own
PDS3 validator ships (ORIGINS below names the repository, commit and path). The earlier
dump in ../shared (pdscat1r77, 2010) builds the same way.

Input: the Planetary Science Data Dictionary dump (`pdsdd.full`, PSDD): one
`OBJECT = ELEMENT_DEFINITION` per keyword (GENERAL_DATA_TYPE, UNIT_ID,
STANDARD_VALUE_TYPE, MINIMUM/MAXIMUM, MINIMUM/MAXIMUM_LENGTH, STANDARD_VALUE_SET), the
UNIT_LIST, and the object definitions. Mission namespaces (MRO:, MEX:) are not in the
PSDD; they come from the hand-maintained schemas/pds3_namespaces.json and are merged
in under "namespaces". schemas/pds3_dictionary_overrides.json corrects PSDD limits that
PDS-accepted archives exceed (each with its evidence); the PSDD value stays beside the
corrected one as psdd_<field>. Unit spellings that PDS archives use but the 2010 unit list
writes differently (METERS/PIXEL, PIXEL/DEGREE, BYTES ...) are listed in UNIT_ALIASES
below. The output is what `pdsgen.validate` reads for its DICT rules.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from pdsgen.validate.psdd import read_psdd  # noqa: E402

DEFAULT_INPUT = REPO.parent / "shared" / "corpus" / "reference" / "pdsdd.full"
DEFAULT_OUTPUT = REPO / "schemas" / "pds3_dictionary.json"
NAMESPACES = REPO / "schemas" / "pds3_namespaces.json"
OVERRIDES = REPO / "schemas" / "pds3_dictionary_overrides.json"

# Spellings of units found in released PDS3 labels (HiRISE, HRSC, LOLA, CRISM ...)
# that are not ids or names in the PSDD unit list; compared case-insensitively.
UNIT_ALIASES = [
    "BYTES", "BYTE", "PIXEL", "PIXELS", "PIX", "DEGREES", "DEGREE", "METERS", "METER",
    "METRES", "KILOMETERS", "KILOMETRES", "METERS/PIXEL", "METRES/PIXEL", "M/PIX", "M/PIXEL",
    "KM/PIXEL", "KM/PIX", "PIXEL/DEGREE", "PIXELS/DEGREE", "PIX/DEG", "PIXEL/DEG",
    "MICROSECONDS", "MILLISECONDS", "NANOMETERS", "MICROMETERS", "DEGC",
    "W*M**-2*SR**-1", "W*M**-2*SR**-1*UM**-1", "W/(M**2*SR*UM)", "DN", "C", "K",
    "DEG/PIXEL", "RAD/PIXEL", "MRAD/PIXEL", "KM/S",
]

# Where each PSDD dump this script has been run on comes from (repository, commit, path).
ORIGINS = {
    "pdscat1r102": "NASA-PDS/pds3-product-tools commit e59da4cae05e791065ec51487344f8b121459fed "
                   "(2017-09-27, 'Updated for the 3.6.0 release'), src/main/java/pdsdd.full",
    "pdscat1r77": "PDS Engineering Node dump pdscat1r77 (also in NASA-PDS/pds3-product-tools "
                  "src/test-data/pdsdd.full)",
}


def build(source: Path) -> dict:
    data = read_psdd(source)
    data["origin"] = ORIGINS.get(data.get("version") or "", str(source))
    elements = data["elements"]
    for name, change in json.loads(OVERRIDES.read_text())["elements"].items():
        entry = elements[name]
        for field, value in change.items():
            if field != "reason":
                entry[f"psdd_{field}"] = entry.get(field)
                entry[field] = value
        entry["override_reason"] = change["reason"]
    data["unit_aliases"] = UNIT_ALIASES
    data["namespaces"] = json.loads(NAMESPACES.read_text())["namespaces"]
    return data


def main(argv: list[str]) -> int:
    source = Path(argv[1]) if len(argv) > 1 else DEFAULT_INPUT
    output = Path(argv[2]) if len(argv) > 2 else DEFAULT_OUTPUT
    data = build(source)
    output.write_text(json.dumps(data, indent=0, sort_keys=False) + "\n")
    print(f"{output}: {len(data['elements'])} keywords, {len(data['units'])} units, "
          f"{sum(len(v) for v in data['namespaces'].values())} namespace keywords")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
