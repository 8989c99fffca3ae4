"""PDS4: the second label dialect over the same geometry, statistics and data writers.

Writing (`--label pds4|both`): `products` (DTM and orthoimage labels and the data taps),
`label` (cart: values, template rendering), `context` (investigation, instruments,
target), `content` (MD5, size and statistics taken while writing), for the Information
Model in `model.CURRENT_IM` (1O00 = 1.24.0.0), from `templates/pds4/`.

Validating: `detect` (is a file a PDS4 label: cheap, asked of every file, by the validator
and deliver alike). The checks themselves are the validator's PDS4 rule family and live
under validate/pds4/: pds4/ imports nothing of validate/.
"""
