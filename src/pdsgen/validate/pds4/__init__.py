"""The checks of the validator's PDS4 rule family (validate/families/pds4_rules.py declares the
rules and their severities and runs these checks).

Here, under validate/, and not in pds4/: they are the validator's, reading its Hit, registry,
projection and GeoJP2 readers, while pds4/ keeps the PDS4 facts and writers the checks read.
So validate imports pds4 and pds4 never imports validate.

`label_checks` (`Pds4LabelContext`, the family's context, and the schema checks), `catalog`
(schema URLs -> schema files, from trusted sources only: `--schemas DIR`, the download cache,
shipped `schemas/pds4/` files and archives), `download` (into the cache), `xsd` (lxml),
`schematron` (Saxon, optional), `data_checks` and `cart_checks` (the label against its
data), `table_checks`, `document_checks`, `context_registry`, `label_tree` (what the
checks share: the hits they add by rule id, label values in their units).
"""
