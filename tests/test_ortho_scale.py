"""DN mapping of orthoimages: special DNs stay free, the inverse mapping is exact to half a step."""

import numpy as np
import pytest

from pdsgen.errors import PdsgenError
from pdsgen.formats.scale_dn import (
    SPECIAL_DNS,
    default_bits,
    dtype_fits,
    identity_mapping,
    invalid_mask,
    linear_mapping,
    to_dns,
)


@pytest.mark.parametrize("bits", [8, 10, 16])
def test_linear_mapping_round_trips_within_half_a_step(bits):
    special = SPECIAL_DNS[bits]
    rng = np.random.default_rng(bits)
    values = rng.uniform(0.013, 0.41, size=(64, 70)).astype(np.float32)
    values[0, 0], values[0, 1] = values.min(), values.max()
    mapping = linear_mapping(special, float(values.min()), float(values.max()))
    dns = to_dns(values, None, mapping, "x")
    assert dns.dtype == special.dtype
    assert dns.min() == special.valid_min and dns.max() == special.valid_max
    back = dns * mapping.scaling_factor + mapping.offset
    assert np.abs(back - values).max() <= mapping.scaling_factor / 2 * (1 + 1e-9)


def test_nodata_nan_and_out_of_range_become_special_dns():
    special = SPECIAL_DNS[10]
    mapping = linear_mapping(special, 0.0, 1.0)
    values = np.array([[np.nan, -0.5, 0.0, 1.0, 1.5, -9999.0, np.inf]], dtype=np.float32)
    dns = to_dns(values, -9999.0, mapping, "x")
    assert dns.tolist() == [[0, special.low_repr, 3, 1021, special.high_repr, 0, 0]]


def test_eight_bit_scheme_matches_the_hirise_convention():
    special = SPECIAL_DNS[8]
    assert (special.null, special.valid_min, special.valid_max, special.high_repr) == (0, 1, 254, 255)
    mapping = linear_mapping(special, 10.0, 20.0)
    dns = to_dns(np.array([[10.0, 20.0, 25.0, 5.0]]), None, mapping, "x")
    assert dns.tolist() == [[1, 254, 255, 1]]


def test_integer_values_are_kept_and_nodata_becomes_null():
    special = SPECIAL_DNS[8]
    values = np.array([[7, 200, 255, 0]], dtype=np.uint8)
    dns = to_dns(values, 255, identity_mapping(special), "x")
    assert dns.tolist() == [[7, 200, 0, 0]]


def test_integer_values_that_do_not_fit_are_refused():
    with pytest.raises(PdsgenError, match="do not fit 10-bit"):
        to_dns(np.array([[5, 2000]], dtype=np.uint16), None, identity_mapping(SPECIAL_DNS[10]), "in.tif")


def test_constant_image_maps_to_one_dn_and_back_exactly():
    mapping = linear_mapping(SPECIAL_DNS[16], 0.25, 0.25)
    dns = to_dns(np.full((3, 3), 0.25, np.float32), None, mapping, "x")
    assert (dns * mapping.scaling_factor + mapping.offset == 0.25).all()


def test_helpers():
    assert default_bits(np.uint8) == 8 and default_bits(np.int16) == 16 and default_bits(np.float32) == 16
    assert dtype_fits(np.uint8, 8) and dtype_fits(np.uint8, 10) and not dtype_fits(np.uint16, 10)
    assert not dtype_fits(np.int16, 16)
    assert invalid_mask(np.ones((2, 2), np.float32), None) is None
    mask = invalid_mask(np.array([np.float32(-3.4028226550889045e38), 1.0], np.float32), None)
    assert mask.tolist() == [True, False]
