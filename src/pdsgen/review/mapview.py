"""The page's maps: footprints drawn in SVG over a longitude/latitude graticule.

Two plane projections, both simple enough for anyone to invert from the numbers the
SVG carries (its data-* attributes), which is how the tests read outlines back:

- "equirectangular": x = (lon - lon0) * k, y = (lat0 - lat) * k (lon unwrapped
  continuously around the view's central meridian);
- "north-polar" / "south-polar", azimuthal equidistant about the pole: r = 90 - |lat|,
  X = r sin(lon), Y = -r cos(lon) in the north (0 E at the bottom, 90 E to the right)
  and Y = r cos(lon) in the south (0 E at the top); x = (X - x0) * k, y = (y0 - Y) * k.

Each view is zoomed to its footprints (padded), so a few small products are seen,
not a dot on the globe; the graticule step follows the extent.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from ..geo.conventions import wrap_360
from .footprint import Outline

VIEW_SIZE = 1000.0  # the longer side of a view, SVG units
_PAD = 0.06
_STEPS = (0.0001, 0.0002, 0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0,
          10.0, 15.0, 30.0)
_SIMPLIFY = 0.15  # SVG units: a point closer than this to the line through its neighbours is dropped


@dataclass
class Shape:
    product_id: str
    link: str  # to its product's entry: #p-... on the first page, REVIEW-2.html#p-... on another
    points: str  # SVG polygon points


@dataclass
class GridLine:
    path: str
    label: str
    x: float
    y: float


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
    # the whole body (equirectangular views): x = lon - west, y = 90 - lat, and the zoomed box
    overview: list[str] = field(default_factory=list)
    overview_west: float = 0.0
    overview_box: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)

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


def build_views(outlines: Iterable[tuple[str, str, str, Outline]]) -> list[View]:
    """(product id, link to its entry, target, outline) -> one view per target body and projection kind."""
    groups: dict[tuple[str, str], list[tuple[str, str, Outline]]] = {}
    for product_id, link, target, outline in outlines:
        groups.setdefault((target, view_kind(outline)), []).append((product_id, link, outline))
    return [_view(target, kind, members) for (target, kind), members in sorted(groups.items())]


def _circular_mean(degrees: list[float]) -> float:
    angles = np.radians(np.asarray(degrees))
    return float(np.degrees(math.atan2(np.mean(np.sin(angles)), np.mean(np.cos(angles)))))


def _view(target: str, kind: str, members: list[tuple[str, str, Outline]]) -> View:
    centre = _circular_mean([float(np.mean(o.lons)) for _, _, o in members]) if kind == "equirectangular" else 0.0
    planes = [(pid, link, *_plane(o, kind, centre)) for pid, link, o in members]
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
    for pid, link, xs, ys in planes:
        sx, sy = (xs - x0) * k, (y0 - ys) * k
        view.shapes.append(Shape(pid, link, _points(sx, sy)))
    view.grid = _graticule(kind, x0, y0, k, width, height, centre)
    if kind == "equirectangular":
        _add_overview(view, planes, centre, x0, y0, width / k, height / k)
    return view


_OVERVIEW_MIN_BOX = 3.0  # degrees: a view of small products still shows where it is


def _add_overview(view: View, planes: list, centre: float, x0: float, y0: float, dx: float, dy: float) -> None:
    """The zoomed view's place on the whole body (360 x 180 degrees, centred on the view)."""
    west = centre - 180.0
    view.overview_west = west
    for _, _, xs, ys in planes:
        view.overview.append(" ".join(f"{x - west:.2f},{90.0 - y:.2f}"
                                      for x, y in zip(xs[::4], ys[::4], strict=True)))
    w, h = max(dx, _OVERVIEW_MIN_BOX), max(dy, _OVERVIEW_MIN_BOX)
    cx, cy = x0 + dx / 2 - west, 90.0 - (y0 - dy / 2)
    view.overview_box = (round(cx - w / 2, 3), round(cy - h / 2, 3), round(w, 3), round(h, 3))


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
               centre: float) -> list[GridLine]:
    x1, y1 = x0 + width / k, y0 - height / k
    grid: list[GridLine] = []
    if kind == "equirectangular":
        step = _step(max(x1 - x0, y0 - y1))
        for i in range(math.ceil(x0 / step), math.floor(x1 / step) + 1):
            lon = i * step
            x = (lon - x0) * k
            grid.append(GridLine(f"M{x:.2f},0V{height:.2f}", f"{_fmt(wrap_360(lon), step)}°E", x + 3, height - 4))
        for i in range(math.ceil(y1 / step), math.floor(y0 / step) + 1):
            lat = i * step
            y = (y0 - lat) * k
            grid.append(GridLine(f"M0,{y:.2f}H{width:.2f}", f"{_fmt(lat, step)}°", 3, y - 3))
        return grid
    sign = -1.0 if kind == "north-polar" else 1.0
    corners = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
    radii = [math.hypot(x, y) for x, y in corners]
    contains_pole = x0 <= 0 <= x1 and y1 <= 0 <= y0
    r_low = 0.0 if contains_pole else max(0.0, min(radii) if not (x0 <= 0 <= x1 or y1 <= 0 <= y0)
                                          else min(abs(v) for v in (x0, x1, y0, y1)))
    r_high = min(90.0, max(radii))
    step = _step(max(x1 - x0, y0 - y1))
    px, py = -x0 * k, y0 * k  # the pole in SVG units
    for i in range(math.ceil(r_low / step), math.floor(r_high / step) + 1):
        r = i * step
        if r <= 0:
            continue
        lat = (90.0 - r) * (1 if kind == "north-polar" else -1)
        rk = r * k
        grid.append(GridLine(f"M{px - rk:.2f},{py:.2f}a{rk:.2f},{rk:.2f} 0 1,0 {2 * rk:.2f},0"
                             f"a{rk:.2f},{rk:.2f} 0 1,0 {-2 * rk:.2f},0",
                             f"{_fmt(lat, step)}°", *_on_view(px, py - rk if sign < 0 else py + rk, width, height)))
    mid_r = max(r_low, step, (r_low + r_high) / 2)
    lon_step = min(30.0, max(_STEPS[0], _nice(math.degrees(step / mid_r))))
    for i in range(int(round(360.0 / lon_step))):
        lon = i * lon_step
        theta = math.radians(lon)
        ex, ey = px + r_high * k * math.sin(theta), py - sign * r_high * k * math.cos(theta)
        sx, sy = px + r_low * k * math.sin(theta), py - sign * r_low * k * math.cos(theta)
        if not _crosses(sx, sy, ex, ey, width, height):
            continue
        lx, ly = px + mid_r * k * math.sin(theta), py - sign * mid_r * k * math.cos(theta)
        grid.append(GridLine(f"M{sx:.2f},{sy:.2f}L{ex:.2f},{ey:.2f}", f"{_fmt(lon, lon_step)}°E",
                             *_on_view(lx, ly, width, height)))
    return grid


def _nice(value: float) -> float:
    return next((s for s in _STEPS if s >= value), _STEPS[-1])


def _on_view(x: float, y: float, width: float, height: float) -> tuple[float, float]:
    return min(max(x, 2.0), width - 60.0), min(max(y, 12.0), height - 4.0)


def _crosses(x0: float, y0: float, x1: float, y1: float, width: float, height: float) -> bool:
    """Whether a segment passes through the view rectangle (sampled: enough for a graticule)."""
    for t in np.linspace(0.0, 1.0, 64):
        x, y = x0 + (x1 - x0) * t, y0 + (y1 - y0) * t
        if 0 <= x <= width and 0 <= y <= height:
            return True
    return False
