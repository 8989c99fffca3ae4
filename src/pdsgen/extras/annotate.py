"""Annotated browse: the browse image framed by margins that carry the annotations.

Layout (nothing is ever drawn over the data):

    +--------------------------------------------------+
    | PRODUCT_ID                                       |  title margin
    | what the rendering shows                         |
    +--------------------------------------+-----------+
    |                                      |  colour   |
    |           browse image               |  ramp     |  (ramp margin only for
    |                                      |  legend   |   colour renderings)
    +--------------------------------------+-----------+
    | [scale bar]     (N arrow)          credit line   |  foot margin
    +--------------------------------------------------+

Text uses Pillow's embedded TrueType font (Aileron) at sizes that follow the image
width, ASCII only. The scale bar has a "nice" length (1, 2 or 5 x 10^n) near 20 %
of the image width at the true ground scale of the image centre; its drawn length
is that length divided by the preview's metres per pixel, rounded to whole pixels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from .colour_ramp import ramp_colours

BACKGROUND = (255, 255, 255)
INK = (25, 25, 25)
MUTED = (90, 90, 90)


@dataclass(frozen=True)
class ScaleBar:
    """A scale bar: its ground length, its label and its length in preview pixels."""

    metres: float
    pixels: int
    label: str


@dataclass(frozen=True)
class Legend:
    """The colour ramp legend: the elevation range it spans, in metres."""

    low: float
    high: float
    title: str = "Elevation (m)"


@dataclass(frozen=True)
class Annotation:
    """Everything the margins show besides the image itself."""

    title: str
    subtitle: str
    credit: str
    metres_per_pixel: float   # true ground metres per browse pixel along rows, at the centre
    north_deg: float          # clockwise from image up
    legend: Legend | None = None


@dataclass(frozen=True)
class Layout:
    """Where things went (pixel boxes in the annotated image), for checks and tests."""

    image_box: tuple[int, int, int, int]
    scale_bar: ScaleBar
    scale_bar_box: tuple[int, int, int, int]   # x0, y0, x1, y1 inclusive
    north_tip: tuple[float, float]
    ramp_box: tuple[int, int, int, int] | None


def nice_scale_bar(metres_per_pixel: float, image_width: int, fraction: float = 0.2) -> ScaleBar:
    """The 1/2/5 x 10^n length nearest (in ratio) to `fraction` of the image width."""
    target = fraction * image_width * metres_per_pixel
    exponent = math.floor(math.log10(target))
    candidates = [m * 10.0**e for e in (exponent - 1, exponent, exponent + 1) for m in (1, 2, 5)]
    metres = min(candidates, key=lambda c: abs(math.log(c / target)))
    return ScaleBar(metres, max(1, round(metres / metres_per_pixel)), _length_label(metres))


def _length_label(metres: float) -> str:
    if metres >= 1000.0:
        return f"{metres / 1000.0:g} km"
    if metres >= 0.01:
        return f"{metres:g} m"
    return f"{metres * 1000.0:g} mm"


def annotate(image: Image.Image, note: Annotation) -> tuple[Image.Image, Layout]:
    """Return the annotated image (RGB) and where its parts were placed."""
    width, height = image.size
    size = _Sizes(width)
    title_font = ImageFont.load_default(size=size.title)
    text_font = ImageFont.load_default(size=size.text)
    small_font = ImageFont.load_default(size=size.small)

    ramp_width = _ramp_margin_width(note.legend, size, small_font) if note.legend else 0
    top = size.pad + size.title + size.gap + size.text + size.pad
    foot = size.pad + max(size.bar + size.gap + size.small, size.arrow_box) + size.pad
    # A narrow image still gets margins wide enough for its title and credit line.
    text_width = max(title_font.getlength(_ascii(note.title)),
                     text_font.getlength(_ascii(note.subtitle)),
                     text_font.getlength(_ascii(note.credit)))
    right = max(size.side, ramp_width, int(text_width) + size.side - width)
    middle = max(height, 12 * size.small) if note.legend else height  # room for the ramp
    canvas = Image.new("RGB", (size.side + width + right, top + middle + foot), BACKGROUND)
    x_img, y_img = size.side, top
    canvas.paste(image.convert("RGB"), (x_img, y_img))
    draw = ImageDraw.Draw(canvas)
    draw.rectangle((x_img - 1, y_img - 1, x_img + width, y_img + height), outline=MUTED)

    draw.text((x_img, size.pad), _ascii(note.title), font=title_font, fill=INK)
    draw.text((x_img, size.pad + size.title + size.gap), _ascii(note.subtitle),
              font=text_font, fill=MUTED)

    foot_y = y_img + middle + 1 + size.pad
    bar = nice_scale_bar(note.metres_per_pixel, width)
    bar_box = _draw_scale_bar(draw, bar, x_img, foot_y, size, small_font)
    bar_right = bar_box[2] + size.gap + small_font.getlength(bar.label)
    tip = _draw_north_arrow(draw, note.north_deg, bar_right + 2 * size.text + size.arrow_box / 2,
                            foot_y + size.arrow_box / 2, size, small_font)
    credit = _ascii(note.credit)
    if credit:
        right = canvas.width - size.side
        credit_w = draw.textlength(credit, font=text_font)
        draw.text((right - credit_w, canvas.height - size.pad - size.text), credit,
                  font=text_font, fill=MUTED)

    ramp_box = None
    if note.legend is not None:
        ramp_box = _draw_legend(draw, note.legend, x_img + width + size.side, y_img, middle,
                                size, small_font)
    return canvas, Layout((x_img, y_img, x_img + width - 1, y_img + height - 1), bar, bar_box,
                          tip, ramp_box)


class _Sizes:
    """Font sizes and spacing that scale with the image width (legible at any size)."""

    def __init__(self, width: int) -> None:
        self.title = max(14, round(width / 42))
        self.text = max(11, round(width / 64))
        self.small = max(10, round(width / 76))
        self.pad = max(6, round(self.text * 0.8))
        self.gap = max(3, round(self.text * 0.35))
        self.bar = max(5, round(self.text * 0.55))
        self.side = max(8, round(self.text * 1.2))
        self.arrow = max(12, round(self.text * 2.0))
        self.arrow_box = round(self.arrow + 2.6 * self.small)


def _draw_scale_bar(draw: ImageDraw.ImageDraw, bar: ScaleBar, x0: int, y0: int,
                    size: _Sizes, font: ImageFont.FreeTypeFont | ImageFont.ImageFont) -> tuple[int, int, int, int]:
    """Four alternating black/white segments, outlined; '0' and the length below."""
    x1, y1 = x0 + bar.pixels - 1, y0 + size.bar - 1
    segments = 4 if bar.pixels >= 40 else 1
    for i in range(segments):
        sx0 = x0 + round(i * bar.pixels / segments)
        sx1 = x0 + round((i + 1) * bar.pixels / segments) - 1
        draw.rectangle((sx0, y0, sx1, y1), fill=INK if i % 2 == 0 else BACKGROUND)
    draw.rectangle((x0, y0, x1, y1), outline=INK)
    text_y = y1 + 1 + size.gap
    if bar.pixels >= font.getlength(bar.label) + font.getlength("0") + 2 * size.gap:
        draw.text((x0, text_y), "0", font=font, fill=INK, anchor="mt")
        draw.text((x1, text_y), bar.label, font=font, fill=INK, anchor="mt")
    else:  # a bar too short for labels under its ends: label beside it
        draw.text((x1 + size.gap, (y0 + y1) / 2), bar.label, font=font, fill=INK, anchor="lm")
    return (x0, y0, x1, y1)


def _draw_north_arrow(draw: ImageDraw.ImageDraw, north_deg: float, cx: float, cy: float,
                      size: _Sizes, font: ImageFont.FreeTypeFont | ImageFont.ImageFont) -> tuple[float, float]:
    """An arrow pointing north (clockwise angle from up), 'N' beyond its tip."""
    length = size.arrow
    angle = math.radians(north_deg)
    ux, uy = math.sin(angle), -math.cos(angle)
    tail = (cx - ux * length / 2, cy - uy * length / 2)
    tip = (cx + ux * length / 2, cy + uy * length / 2)
    head = length * 0.38
    px, py = -uy, ux
    left = (tip[0] - ux * head + px * head * 0.45, tip[1] - uy * head + py * head * 0.45)
    right = (tip[0] - ux * head - px * head * 0.45, tip[1] - uy * head - py * head * 0.45)
    draw.line((tail, (tip[0] - ux * head * 0.5, tip[1] - uy * head * 0.5)), fill=INK,
              width=max(2, size.text // 7))
    draw.polygon((tip, left, right), fill=INK)
    reach = length / 2 + size.small * 0.75
    label_at = (cx + ux * reach, cy + uy * reach)
    draw.text(label_at, "N", font=font, fill=INK, anchor="mm")
    return tip


def _ramp_margin_width(legend: Legend, size: _Sizes, font: ImageFont.FreeTypeFont | ImageFont.ImageFont) -> int:
    labels = [_tick_label(v, _tick_step(legend)) for v in _ticks(legend)]
    widest = max(font.getlength(t) for t in labels)
    content = max(round(size.text * 1.5) + size.gap * 2 + widest, font.getlength(legend.title))
    return int(size.side + content + size.side)


def _draw_legend(draw: ImageDraw.ImageDraw, legend: Legend, x0: int, y_img: int, height: int,
                 size: _Sizes, font: ImageFont.FreeTypeFont | ImageFont.ImageFont) -> tuple[int, int, int, int]:
    """A vertical colour ramp (high at the top) with ticks at round elevations."""
    bar_w = round(size.text * 1.5)
    y0 = y_img + size.small + size.gap * 2
    bar_h = max(20, min(height - (y0 - y_img), round(height * 0.7)))
    y1 = y0 + bar_h - 1
    values = np.linspace(legend.high, legend.low, bar_h, dtype=np.float64)
    colours = ramp_colours(values, legend.low, legend.high)
    for i, colour in enumerate(np.rint(colours).astype(np.uint8)):
        draw.line(((x0, y0 + i), (x0 + bar_w - 1, y0 + i)), fill=tuple(int(c) for c in colour))
    draw.rectangle((x0, y0, x0 + bar_w - 1, y1), outline=INK)
    draw.text((x0, y_img), legend.title, font=font, fill=INK)
    step = _tick_step(legend)
    for value in _ticks(legend):
        y = y0 + (legend.high - value) / (legend.high - legend.low) * (bar_h - 1)
        draw.line(((x0 + bar_w, y), (x0 + bar_w + size.gap, y)), fill=INK)
        draw.text((x0 + bar_w + size.gap * 2, y), _tick_label(value, step), font=font,
                  fill=INK, anchor="lm")
    return (x0, y0, x0 + bar_w - 1, y1)


def _tick_step(legend: Legend) -> float:
    """A 1/2/5 x 10^n step giving about five ticks over the legend's range."""
    span = legend.high - legend.low
    if span <= 0:
        return 1.0
    raw = span / 5.0
    exponent = math.floor(math.log10(raw))
    for m in (1, 2, 5, 10):
        if m * 10.0**exponent >= raw:
            return m * 10.0**exponent
    return 10.0 ** (exponent + 1)


def _ticks(legend: Legend) -> list[float]:
    step = _tick_step(legend)
    first = math.ceil(legend.low / step - 1e-9) * step
    ticks: list[float] = []
    value = first
    while value <= legend.high + 1e-9 * step and len(ticks) < 50:
        ticks.append(value)
        value += step
    return ticks or [legend.low, legend.high]


def _tick_label(value: float, step: float) -> str:
    decimals = max(0, -math.floor(math.log10(step))) if step < 1 else 0
    text = f"{value:.{decimals}f}"
    return "0" if text.strip("-0.") == "" else text.replace("-", "-")


def _ascii(text: str) -> str:
    return text.encode("ascii", "replace").decode("ascii")
