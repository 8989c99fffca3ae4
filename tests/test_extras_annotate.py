"""Annotated browse: margins around untouched data, a true scale bar, a turning north arrow."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from pdsgen.extras.annotate import Annotation, Legend, annotate, nice_scale_bar
from pdsgen.extras.colour_ramp import CONTROL_POINTS


def browse(width: int = 600, height: int = 400) -> Image.Image:
    rng = np.random.default_rng(0)
    return Image.fromarray(rng.integers(1, 255, (height, width), dtype=np.uint8), "L")


@pytest.mark.parametrize("mpp, width, metres, label", [
    (1.0, 1000, 200.0, "200 m"),
    (2.0, 1024, 500.0, "500 m"),
    (20800.0, 1024, 5e6, "5000 km"),
    (0.25, 2048, 100.0, "100 m"),
    (14.818, 1440, 5000.0, "5 km"),
])
def test_scale_bar_has_a_nice_length_near_a_fifth_of_the_width(mpp, width, metres, label):
    bar = nice_scale_bar(mpp, width)
    assert (bar.metres, bar.label) == (metres, label)
    assert bar.pixels == round(metres / mpp)
    assert 0.08 * width <= bar.pixels <= 0.5 * width
    mantissa = bar.metres / 10 ** math.floor(math.log10(bar.metres))
    assert round(mantissa, 9) in (1.0, 2.0, 5.0)


@pytest.mark.parametrize("mpp", [0.73, 1.0, 3.3, 14818.0])
def test_drawn_scale_bar_length_is_label_over_metres_per_pixel(mpp):
    image, layout = annotate(browse(), Annotation("ID_1", "test", "Credit", mpp, 0.0))
    x0, y0, x1, _ = layout.scale_bar_box
    row = np.asarray(image.convert("L"))[y0]
    dark = np.flatnonzero(row < 80)
    run = dark[(dark >= x0 - 5) & (dark <= x1 + 5)]
    assert run.max() - run.min() + 1 == layout.scale_bar.pixels
    assert abs((run.max() - run.min() + 1) - layout.scale_bar.metres / mpp) <= 1.0


def test_data_is_pasted_unchanged_and_margins_surround_it():
    data = browse()
    image, layout = annotate(data, Annotation("ESP_1_RED", "sub", "NASA", 1.0, 0.0))
    x0, y0, x1, y1 = layout.image_box
    assert image.width > data.width and image.height > data.height
    inside = np.asarray(image)[y0:y1 + 1, x0:x1 + 1, 0]
    assert np.array_equal(inside, np.asarray(data))
    sb = layout.scale_bar_box
    assert sb[1] > y1 and layout.north_tip[1] > y1  # annotations below the data


def test_north_arrow_turns_with_north():
    tips = {}
    for north in (0.0, 90.0, 180.0):
        _, layout = annotate(browse(), Annotation("X", "s", "", 1.0, north))
        tips[north] = layout.north_tip
    assert tips[90.0][0] > tips[0.0][0]           # pointing right
    assert tips[180.0][1] > tips[0.0][1]          # pointing down


def test_colour_legend_runs_from_first_colour_at_the_bottom_to_last_at_the_top():
    image, layout = annotate(browse(), Annotation("X", "s", "c", 1.0, 0.0,
                                                  Legend(-4400.0, -4100.0)))
    assert layout.ramp_box is not None
    x0, y0, x1, y1 = layout.ramp_box
    rgb = np.asarray(image)
    xm = (x0 + x1) // 2
    assert np.abs(rgb[y1 - 2, xm].astype(int) - CONTROL_POINTS[0]).max() <= 12
    assert np.abs(rgb[y0 + 2, xm].astype(int) - CONTROL_POINTS[-1]).max() <= 12
    assert x0 > layout.image_box[2]  # beside the data, not over it


def test_long_credit_line_never_runs_into_the_north_arrow():
    from pdsgen.extras.annotate import _Sizes

    credit = "LUNAR RECONNAISSANCE ORBITER / GODDARD SPACE FLIGHT CENTER"
    short, _ = annotate(browse(200, 100), Annotation("X", "s", "", 1.0, 0.0))
    image, layout = annotate(browse(200, 100), Annotation("X", "s", credit, 1.0, 0.0))
    assert image.height > short.height            # the credit got a line of its own
    size = _Sizes(200)
    credit_top = image.height - size.pad - size.text
    arrow_tail = layout.north_tip[1] + size.arrow  # north up: the tail is below the tip
    assert arrow_tail < credit_top
