"""The viridis ramp: ends, ordering, and the blend that keeps flat ground true."""

from __future__ import annotations

import math

import numpy as np

from pdsgen.extras.colour_ramp import (
    CONTROL_POINTS,
    blend_with_shade,
    first_colour,
    ramp_colours,
)


def luminance(rgb: np.ndarray) -> np.ndarray:
    return 0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2]


def test_lowest_valid_height_gets_the_first_colour_and_highest_the_last():
    heights = np.array([-4410.0, -4300.0, -4120.0], dtype=np.float32)
    colours = ramp_colours(heights, float(heights.min()), float(heights.max()))
    assert tuple(np.rint(colours[0]).astype(int)) == first_colour() == (0x44, 0x01, 0x54)
    assert tuple(np.rint(colours[-1]).astype(int)) == (0xFD, 0xE7, 0x25)


def test_values_outside_the_range_clip_to_the_ends():
    colours = ramp_colours(np.array([-1e6, 1e6]), 0.0, 1.0)
    assert np.allclose(colours[0], CONTROL_POINTS[0]) and np.allclose(colours[1], CONTROL_POINTS[-1])


def test_ramp_is_perceptually_ordered_lightness_rises_monotonically():
    colours = ramp_colours(np.linspace(0.0, 1.0, 256), 0.0, 1.0)
    assert np.all(np.diff(luminance(colours)) >= -0.5)
    assert luminance(colours[-1]) - luminance(colours[0]) > 150


def test_blend_keeps_flat_ground_at_the_ramp_colour_and_shows_relief():
    rgb = ramp_colours(np.array([0.3, 0.3, 0.3]), 0.0, 1.0)
    flat = math.sin(math.radians(45.0))
    out = blend_with_shade(rgb, np.array([flat, 1.0, 0.1], dtype=np.float32), 45.0)
    assert np.abs(out[0].astype(int) - np.rint(rgb[0]).astype(int)).max() <= 1
    assert luminance(out[1].astype(float)) > luminance(out[0].astype(float)) > luminance(
        out[2].astype(float))
