"""The page's maps: footprints drawn in SVG over a longitude/latitude graticule.

Two plane projections, both simple enough for anyone to invert from the numbers the
SVG carries (its data-* attributes), which is how the tests read outlines back:

- "equirectangular": x = (lon - lon0) * k, y = (lat0 - lat) * k (lon unwrapped
  continuously around the view's central meridian);
- "north-polar" / "south-polar", azimuthal equidistant about the pole: r = 90 - |lat|,
  X = r sin(lon), Y = -r cos(lon) in the north (0 E at the bottom, 90 E to the right)
  and Y = r cos(lon) in the south (0 E at the top); x = (X - x0) * k, y = (y0 - Y) * k.

Each view is zoomed to its footprints (padded), so a few small products are seen,
not a dot on the globe; the graticule step follows the extent. The graticule's labels
stand in a margin around the plot (where each line leaves it), never over a footprint.
Footprints are drawn by kind (DTM, orthoimage, other), each kind in its own colour and
stroke, so outlines that coincide - a DTM and the orthoimage on its grid - both show;
the page's legend names each kind beside its colour. Beside an equirectangular view, an
inset shows the region around it (the view's box on a graticule some times larger), and
is left out when the view already shows most of the body.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from ..geo.conventions import wrap_360
from .footprint import Outline

VIEW_SIZE = 1000.0  # the longer side of a view, SVG units
# The margin around a view's plot that holds the graticule's labels (SVG units; labels are 24 units
# high, the longest, "-89.0005°" or "359.0005°E", about 130 wide).
MARGIN = 140.0
LABEL_GAP = 8.0
# Kinds of footprints, in drawing order (a DTM under the orthoimage made on its grid).
KINDS = ("DTM", "orthoimage", "product")
_PAD = 0.06
_STEPS = (0.0001, 0.0002, 0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0,
          10.0, 15.0, 30.0)
_SIMPLIFY = 0.15  # SVG units: a point closer than this to the line through its neighbours is dropped


@dataclass
class Shape:
    product_id: str
    link: str  # to its product's entry: #p-... on the first page, REVIEW-2.html#p-... on another
    points: str  # SVG polygon points
    kind: str = "product"  # DTM, orthoimage or product: its colour and stroke (the legend's)

    @property
    def css_class(self) -> str:
        return "kind-" + self.kind.lower()


@dataclass
class GridLine:
    path: str
    label: str
    x: float  # where the label stands: outside the plot, beside the edge the line leaves it by
    y: float
    anchor: str = "start"  # SVG text-anchor of the label
    labelled: bool = True  # False: the line does not reach the plot's edge where labels stand


@dataclass
class Inset:
    """The region around an equirectangular view: plane x = (lon - west) * scale, y = (north -
    lat) * scale, in pixels; the view's box on it and its footprints."""

    west: float
    north: float
    scale: float
    width: float
    height: float
    box: tuple[float, float, float, float]
    footprints: list[str] = field(default_factory=list)
    grid: list[GridLine] = field(default_factory=list)


@dataclass
class View:
    """One map: the target body, the projection, its numbers, footprints and graticule."""

    target: str
    projection: str
    params: dict[str, float]
    width: float = VIEW_SIZE
    height: float = VIEW_SIZE
    shapes: list[Shape] = field(default_factory=list)
    grid: list[GridLine] = field(default_factory=list)
    inset: Inset | None = None  # the region around the view (equirectangular views of part of a body)
    margin: float = MARGIN

    @property
    def kinds(self) -> list[str]:
        """The kinds of footprint drawn, for the legend, in drawing order."""
        present = {shape.kind for shape in self.shapes}
        return [kind for kind in KINDS if kind in present]

    @property
    def title(self) -> str:
        kind = {"equirectangular": "longitude/latitude (equirectangular)",
                "north-polar": "north polar view (azimuthal equidistant)",
                "south-polar": "south polar view (azimuthal equidistant)"}[self.projection]
        return f"{self.target.title()}: {kind}"


def _plane(outline: Outline, projection: str, centre_lon: float) -> tuple[np.ndarray, np.ndarray]:
    """Plane coordinates (degrees) of an outline in a view's projection, y up."""
    if projection == "equirectangular":
        lons = np.degrees(np.unwrap(np.radians(outline.lons)))
        shift = 360.0 * round((float(np.mean(lons)) - centre_lon) / 360.0)
        return lons - shift, outline.lats.copy()
    r = 90.0 - np.abs(outline.lats)
    theta = np.radians(outline.lons)
    sign = -1.0 if projection == "north-polar" else 1.0
    return r * np.sin(theta), sign * r * np.cos(theta)


def view_kind(outline: Outline) -> str:
    if not outline.polar:
        return "equirectangular"
    return "north-polar" if outline.north else "south-polar"


def build_views(outlines: Iterable[tuple[str, str, str, Outline, str]]) -> list[View]:
    """(product id, link to its entry, target, outline, kind of product) -> one view per target body
    and projection kind, its footprints in drawing order (KINDS)."""
    groups: dict[tuple[str, str], list[tuple[str, str, Outline, str]]] = {}
    for product_id, link, target, outline, kind in outlines:
        groups.setdefault((target, view_kind(outline)), []).append(
            (product_id, link, outline, kind if kind in KINDS else "product"))
    for members in groups.values():
        members.sort(key=lambda member: KINDS.index(member[3]))
    return [_view(target, kind, members) for (target, kind), members in sorted(groups.items())]


def _circular_mean(degrees: list[float]) -> float:
    angles = np.radians(np.asarray(degrees))
    return float(np.degrees(math.atan2(np.mean(np.sin(angles)), np.mean(np.cos(angles)))))


def _view(target: str, kind: str, members: list[tuple[str, str, Outline, str]]) -> View:
    centre = _circular_mean([float(np.mean(o.lons)) for _, _, o, _ in members]) if kind == "equirectangular" else 0.0
    planes = [(pid, link, *_plane(o, kind, centre)) for pid, link, o, _ in members]
    xmin = min(float(x.min()) for _, _, x, _ in planes)
    xmax = max(float(x.max()) for _, _, x, _ in planes)
    ymin = min(float(y.min()) for _, _, _, y in planes)
    ymax = max(float(y.max()) for _, _, _, y in planes)
    span = max(xmax - xmin, ymax - ymin, 1e-6)
    pad = span * _PAD
    x0, y0 = xmin - pad, ymax + pad
    k = VIEW_SIZE / (span + 2 * pad)
    width = max((xmax - xmin + 2 * pad) * k, VIEW_SIZE / 4)
    height = max((ymax - ymin + 2 * pad) * k, VIEW_SIZE / 4)
    if kind == "equirectangular":
        params = {"lon0": x0, "lat0": y0, "k": k}
    else:
        params = {"x0": x0, "y0": y0, "k": k}
    view = View(target, kind, params, round(width, 2), round(height, 2))
    for (pid, link, xs, ys), (_, _, _, shape_kind) in zip(planes, members, strict=True):
        sx, sy = (xs - x0) * k, (y0 - ys) * k
        view.shapes.append(Shape(pid, link, _points(sx, sy), shape_kind))
    view.grid = _graticule(kind, x0, y0, k, width, height, centre)
    if kind == "equirectangular":
        view.inset = _inset(planes, x0, y0, width / k, height / k)
    return view


INSET_WIDTH = 300.0  # pixels: the inset's plot
_INSET_ZOOM = 8.0  # the region shown is this many times the view's extent ...
_INSET_MIN_SPAN = 10.0  # ... and at least this many degrees across
_INSET_MAX_SHARE = 0.35  # a view spanning more than this share of the body's longitudes gets no inset
_INSET_MIN_BOX = 8.0  # pixels: the view's box on the inset is drawn at least this large, to be seen


def _inset(planes: list, x0: float, y0: float, dx: float, dy: float) -> Inset | None:
    """The region around the view: its box on a graticule, clamped to the body (latitudes -90..90,
    at most 360 degrees of longitude); None when the view already shows most of the body."""
    if dx > 360.0 * _INSET_MAX_SHARE or dy > 180.0 * _INSET_MAX_SHARE:
        return None
    span_x = min(360.0, max(dx * _INSET_ZOOM, _INSET_MIN_SPAN))
    span_y = min(180.0, max(dy * _INSET_ZOOM, _INSET_MIN_SPAN / 2))
    west = x0 + dx / 2 - span_x / 2
    north = min(90.0, max(-90.0 + span_y, y0 - dy / 2 + span_y / 2))
    scale = INSET_WIDTH / span_x
    box_w, box_h = max(dx * scale, _INSET_MIN_BOX), max(dy * scale, _INSET_MIN_BOX)
    centre_x, centre_y = (x0 + dx / 2 - west) * scale, (north - y0 + dy / 2) * scale
    inset = Inset(west, north, scale, INSET_WIDTH, round(span_y * scale, 2),
                  (round(centre_x - box_w / 2, 3), round(centre_y - box_h / 2, 3), round(box_w, 3), round(box_h, 3)))
    for _, _, xs, ys in planes:
        inset.footprints.append(" ".join(f"{(x - west) * scale:.2f},{(north - y) * scale:.2f}"
                                         for x, y in zip(xs[::4], ys[::4], strict=True)))
    inset.grid = _graticule("equirectangular", west, north, scale, inset.width, inset.height, 0.0, lines=4,
                            font=9.0)
    return inset


def _points(xs: np.ndarray, ys: np.ndarray) -> str:
    keep = _simplified(xs, ys)
    return " ".join(f"{x:.3f},{y:.3f}" for x, y in zip(xs[keep], ys[keep], strict=True))


def _simplified(xs: np.ndarray, ys: np.ndarray) -> list[int]:
    """Indices of the ring's points worth drawing: the grid's four corners always (the ring runs
    along its four edges, footprint.EDGE_POINTS - 1 steps each), and of each edge's points those
    farther than _SIMPLIFY from the line the kept ones draw (Douglas-Peucker)."""
    n = len(xs)
    side = n // 4
    keep: list[int] = []
    for corner in range(4):
        first, last = corner * side, (corner + 1) * side
        keep += _douglas_peucker(xs, ys, first, last % n, list(range(first, last + 1)))[:-1]
    return keep


def _douglas_peucker(xs: np.ndarray, ys: np.ndarray, first: int, last: int, span: list[int]) -> list[int]:
    n = len(xs)
    if len(span) <= 2:
        return [first, last]
    ax, ay, bx, by = xs[first], ys[first], xs[last], ys[last]
    inner = [i % n for i in span[1:-1]]
    length = math.hypot(bx - ax, by - ay)
    if length == 0.0:
        distances = [math.hypot(xs[i] - ax, ys[i] - ay) for i in inner]
    else:
        distances = [abs((bx - ax) * (ys[i] - ay) - (by - ay) * (xs[i] - ax)) / length for i in inner]
    worst = int(np.argmax(distances))
    if distances[worst] <= _SIMPLIFY:
        return [first, last]
    split = worst + 1
    left = _douglas_peucker(xs, ys, first, span[split] % n, span[: split + 1])
    right = _douglas_peucker(xs, ys, span[split] % n, last, span[split:])
    return left[:-1] + right


def _step(span: float, lines: int = 5) -> float:
    for step in _STEPS:
        if span / step <= lines:
            return step
    return _STEPS[-1]


def _fmt(value: float, step: float) -> str:
    decimals = max(0, -int(math.floor(math.log10(step)))) if step < 1 else 0
    return f"{value:.{decimals}f}"


def _graticule(kind: str, x0: float, y0: float, k: float, width: float, height: float,
               centre: float, lines: int = 5, font: float = 24.0) -> list[GridLine]:
    """The graticule's lines over the plot (width x height from 0,0), each labelled in the margin
    beside the edge it leaves the plot by (_edge_label)."""
    x1, y1 = x0 + width / k, y0 - height / k
    step = _step(max(x1 - x0, y0 - y1), lines)
    grid: list[GridLine] = []
    placed: list[Box] = []
    if kind == "equirectangular":
        for i in range(math.ceil(x0 / step), math.floor(x1 / step) + 1):
            x = (i * step - x0) * k
            grid.append(_labelled(f"M{x:.2f},0V{height:.2f}", f"{_fmt(wrap_360(i * step), step)}°E",
                                  np.array([x, x]), np.array([0.0, height]), width, height, font, placed))
        for i in range(math.ceil(y1 / step), math.floor(y0 / step) + 1):
            y = (y0 - i * step) * k
            grid.append(_labelled(f"M0,{y:.2f}H{width:.2f}", f"{_fmt(i * step, step)}°",
                                  np.array([0.0, width]), np.array([y, y]), width, height, font, placed))
        return grid
    sign = -1.0 if kind == "north-polar" else 1.0
    corners = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
    radii = [math.hypot(x, y) for x, y in corners]
    contains_pole = x0 <= 0 <= x1 and y1 <= 0 <= y0
    r_low = 0.0 if contains_pole else max(0.0, min(radii) if not (x0 <= 0 <= x1 or y1 <= 0 <= y0)
                                          else min(abs(v) for v in (x0, x1, y0, y1)))
    r_high = min(90.0, max(radii))
    px, py = -x0 * k, y0 * k  # the pole in SVG units
    around = np.linspace(0.0, 2.0 * math.pi, 721)
    for i in range(math.ceil(r_low / step), math.floor(r_high / step) + 1):
        r = i * step
        if r <= 0:
            continue
        lat = (90.0 - r) * (1 if kind == "north-polar" else -1)
        rk = r * k
        grid.append(_labelled(f"M{px - rk:.2f},{py:.2f}a{rk:.2f},{rk:.2f} 0 1,0 {2 * rk:.2f},0"
                              f"a{rk:.2f},{rk:.2f} 0 1,0 {-2 * rk:.2f},0", f"{_fmt(lat, step)}°",
                              px + rk * np.sin(around), py + rk * np.cos(around), width, height, font, placed))
    mid_r = max(r_low, step, (r_low + r_high) / 2)
    lon_step = min(30.0, max(_STEPS[0], _nice(math.degrees(step / mid_r))))
    for i in range(int(round(360.0 / lon_step))):
        lon = i * lon_step
        theta = math.radians(lon)
        ex, ey = px + r_high * k * math.sin(theta), py - sign * r_high * k * math.cos(theta)
        sx, sy = px + r_low * k * math.sin(theta), py - sign * r_low * k * math.cos(theta)
        if not _crosses(sx, sy, ex, ey, width, height):
            continue
        grid.append(_labelled(f"M{sx:.2f},{sy:.2f}L{ex:.2f},{ey:.2f}", f"{_fmt(lon, lon_step)}°E",
                              np.linspace(sx, ex, 257), np.linspace(sy, ey, 257), width, height, font, placed))
    return grid


def _nice(value: float) -> float:
    return next((s for s in _STEPS if s >= value), _STEPS[-1])


Box = tuple[float, float, float, float]  # left, top, right, bottom


def _labelled(path: str, label: str, xs: np.ndarray, ys: np.ndarray, width: float, height: float,
              font: float, placed: list[Box]) -> GridLine:
    """The line with its label at the first of its edge places (_edge_places) that no label placed
    before covers (`placed`, which it joins); unlabelled when every place is taken."""
    for x, y, anchor in _edge_places(xs, ys, width, height, font):
        extent = _text_box(label, x, y, anchor, font)
        if not any(_boxes_meet(extent, other) for other in placed):
            placed.append(extent)
            return GridLine(path, label, x, y, anchor)
    return GridLine(path, label, 0.0, 0.0, labelled=False)


def _edge_places(xs: np.ndarray, ys: np.ndarray, width: float, height: float,
                 font: float) -> list[tuple[float, float, str]]:
    """Where a line's label may stand: in the margin outside each edge the line (points xs, ys)
    meets - the left edge first (latitudes), then the bottom (longitudes), the right, the top."""
    gap = font / 3
    places = []
    for edge in ("left", "bottom", "right", "top"):
        at = _meets(xs, ys, edge, width, height)
        if at is None:
            continue
        places.append({"left": (-gap, at + font * 0.35, "end"), "bottom": (at, height + gap + font, "middle"),
                       "right": (width + gap, at + font * 0.35, "start"), "top": (at, -gap, "middle")}[edge])
    return places


def _text_box(label: str, x: float, y: float, anchor: str, font: float) -> Box:
    """About where a label's text lies (digits are some 0.6 em wide), for keeping labels apart."""
    width = 0.62 * font * len(label)
    left = {"start": x, "middle": x - width / 2, "end": x - width}[anchor]
    return left, y - font, left + width, y + font * 0.25


def _boxes_meet(a: Box, b: Box) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _meets(xs: np.ndarray, ys: np.ndarray, edge: str, width: float, height: float) -> float | None:
    """The coordinate along `edge` where the polyline first reaches it within the plot, or None."""
    vertical = edge in ("left", "right")
    along, across = (ys, xs) if vertical else (xs, ys)
    limit = height if vertical else width
    level = {"left": 0.0, "right": width, "top": 0.0, "bottom": height}[edge]
    offset = across - level
    for i in range(len(offset) - 1):
        a, b = float(offset[i]), float(offset[i + 1])
        if a == b == 0.0:
            value = float(along[i])
        elif min(a, b) <= 0.0 <= max(a, b):
            value = float(along[i] + (along[i + 1] - along[i]) * a / (a - b))
        else:
            continue
        if 0.0 <= value <= limit:
            return value
    return None


def _crosses(x0: float, y0: float, x1: float, y1: float, width: float, height: float) -> bool:
    """Whether a segment passes through the view rectangle (sampled: enough for a graticule)."""
    for t in np.linspace(0.0, 1.0, 64):
        x, y = x0 + (x1 - x0) * t, y0 + (y1 - y0) * t
        if 0 <= x <= width and 0 <= y <= height:
            return True
    return False
