"""PDS4: the second label dialect over the same geometry, statistics and data writers.

Writing: `products` (DTM and orthoimage labels, `--label pds4|both`), rendered from
`templates/pds4/` for the Information Model in `model.CURRENT_IM` (1O00 = 1.24.0.0).
Validating: `validate` (XML Schema through `xsd`, Schematron through `schematron`
when saxonche is installed, content checks), offline, with schemas found by `catalog`
among those shipped in `schemas/pds4/` and any `--schemas DIR`.
"""

