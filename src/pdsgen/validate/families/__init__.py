"""The validator's rule families, one module each; importing a module registers its rules
(see ..registry). FILE, SYNTAX, DICT, PTR and REC (pointers and records), IMG, MAP, GEO
(GeoJP2), HRSC and IMARS (mission profiles), SET (across files), PDS4 (listed only), DLV (deliveries), IDN
(what a product says of itself: identifier, times).

`load()` imports every built-in family (registry.rules() calls it before the table is
first read); importing one family module, as a product writer's label check does for
DICT, loads only that family and what it needs.
"""

from __future__ import annotations

import importlib

BUILTIN = ("delivery_rules", "dict_rules", "file_rules", "geo_rules", "hrsc_rules", "identity_rules", "image_rules",
           "imars_rules", "map_rules", "pds4_rules", "pointer_rules", "set_rules", "syntax_rules")

__all__ = [*BUILTIN, "BUILTIN", "load"]


def load() -> None:
    """Import (and so register) every built-in family."""
    for name in BUILTIN:
        importlib.import_module(f"{__name__}.{name}")
