"""PDS4: the second label dialect over the same geometry, statistics and data writers.

Writing (`--label pds4|both`): `products` (DTM and orthoimage labels and the data taps),
`label` (cart: values, template rendering), `context` (investigation, instruments,
target), `content` (MD5, size and statistics taken while writing), for the Information
Model in `model.CURRENT_IM` (1O00 = 1.24.0.0), from `templates/pds4/`.

Validating (`pdsgen validate`, whose PDS4 rule family validate/families/pds4_rules.py
declares the rules and runs these checks): `detect` (is a file a PDS4 label: cheap, asked
of every file), `validate` (`Pds4LabelContext`, the family's context, and the schema checks), `catalog`
(schema URLs -> schema files: beside the label, `--schemas DIR`, the download cache,
shipped `schemas/pds4/` files and archives), `download` (into the cache), `xsd` (lxml),
`schematron` (Saxon, optional), `data_checks` and `cart_checks` (the label against its
data), `table_checks`, `document_checks`, `context_registry`, `label_tree` (what the
checks share: the hits they add by rule id, label values in their units).
"""
