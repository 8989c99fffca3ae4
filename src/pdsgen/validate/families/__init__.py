"""The validator's rule families, one module each; importing a module registers its rules
(see ..registry). FILE, SYNTAX, DICT, PTR and REC (pointers and records), IMG, MAP, GEO
(GeoJP2), HRSC and IMARS (mission profiles), SET (across files), PDS4 (listed only), DLV (deliveries)."""

from __future__ import annotations

from . import (
    delivery_rules,
    dict_rules,
    file_rules,
    geo_rules,
    hrsc_rules,
    image_rules,
    imars_rules,
    map_rules,
    pds4_rules,
    pointer_rules,
    set_rules,
    syntax_rules,
)

__all__ = ["delivery_rules", "dict_rules", "file_rules", "geo_rules", "hrsc_rules", "image_rules", "imars_rules",
           "map_rules", "pds4_rules", "pointer_rules", "set_rules", "syntax_rules"]
