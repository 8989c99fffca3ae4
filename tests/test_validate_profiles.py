"""Which archive a label belongs to, as the validator decides it from mission facts."""

from __future__ import annotations

import pytest

from pdsgen.missions import hirise
from pdsgen.validate.context import FileContext
from pdsgen.validate.profiles import is_hirise


@pytest.mark.parametrize("statements, expected", [
    ('PRODUCT_ID = "ESP_042252_1930_IRB_B_41_ORTHO"', True),
    ("PRODUCT_ID = DTEEC_008669_1705_009025_1705_U01", True),
    ("PRODUCT_ID = psp_008669_1705_red", True),
    ("INSTRUMENT_ID = HIRISE", True),
    ('DATA_SET_ID = "MRO-M-HIRISE-5-DTM-V1.0"', True),
    ("PRODUCT_ID = XSP_008669_1705", False),
    ("PRODUCT_ID = h1234_0000_dt4\r\nINSTRUMENT_ID = HRSC", False),
])
def test_hirise_labels_by_instrument_data_set_or_product_id(tmp_path, statements, expected):
    path = tmp_path / "X.LBL"
    path.write_bytes(f"PDS_VERSION_ID = PDS3\r\n{statements}\r\nEND\r\n".encode())
    assert is_hirise(FileContext(path)) is expected


def test_product_ids_the_hirise_profile_writes_are_hirise_ids():
    """The id pattern and the name builders live together and agree."""
    assert hirise.PRODUCT_ID_RE.match(hirise.ortho_id("ESP_042252_1930", 3, 0.5, 41))
    assert not hirise.PRODUCT_ID_RE.match("ZZZ_042252_1930")
