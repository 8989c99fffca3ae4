"""Validate one PDS4 label offline: XML Schema, Schematron, and the label against its data.

Order: parse -> find the schemas it names in the catalog (shipped + `--schemas`)
-> XML Schema (lxml) -> Schematron (Saxon, when installed) -> content checks
(file size, MD5, array statistics, special constants, cartography against the
georeferencing). Every problem is a Finding with a PDS4-nnn rule id; nothing a
label holds can raise out of here.

The content checks compute independently of the writer: they read the data file
with numpy and project with the validator's own closed-form sphere formulas.
"""

from __future__ import annotations

import hashlib
import math
import os
import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from lxml import etree

from ..validate.geojp2 import Jp2Error, read_jp2
from ..validate.model import Finding
from ..validate.projection import Sphere, boundary
from . import schematron
from .catalog import SchemaCatalog, schema_references
from .model import CART_NS, NUMPY_TYPES, PDS_NS
from .rules import RULES
from .xsd import SchemaImportError, build_schema, xsd_errors

P = f"{{{PDS_NS}}}"
C = f"{{{CART_NS}}}"
_READ_BYTES = 8 * 1024 * 1024  # one read of a data file (memory stays flat)
# ISIS special pixels (NULL, LRS, LIS, HIS, HRS) are the float32 values at or below NULL.
_ISIS_SPECIAL_LIMIT = -3.4028226550889045e38
_IM_RE_HINT = "supply that version's schemas with --schemas DIR"


SEVERITY = {rule.id: rule.severity for rule in RULES}


def is_pds4_label(path: Path) -> bool:
    """An .xml file whose root element is a PDS4 Product_* (read from its first few KB)."""
    if path.suffix.lower() != ".xml":
        return False
    try:
        with open(path, "rb") as handle:
            head = handle.read(8192)
    except OSError:
        return False
    return b"http://pds.nasa.gov/pds4/pds/v1" in head and b"<Product_" in head


def check_schema_dirs(directories: Iterable[str | os.PathLike[str]]) -> tuple[str, ...]:
    """The `--schemas` directories as strings, refusing one that is not a directory (usage error)."""
    checked = tuple(os.fspath(d) for d in directories)
    SchemaCatalog.build(checked)
    return checked


def validate_label(path: str | Path, schema_dirs: tuple[str, ...] = (), labels_only: bool = False) -> list[Finding]:
    """The validator's entry point for one PDS4 label (catalog cached per set of directories)."""
    if schema_dirs not in _CATALOGS:
        _CATALOGS[schema_dirs] = SchemaCatalog.build(schema_dirs)
    return validate_pds4(path, _CATALOGS[schema_dirs], labels_only)


_CATALOGS: dict[tuple[str, ...], SchemaCatalog] = {}


def add_run_notes(reports: list) -> None:  # noqa: ANN001 - the validator's FileReport list
    """One PDS4-007 warning for a run that checked PDS4 labels without Saxon (schema-only)."""
    if schematron.available():
        return
    first = next((r for r in reports if is_pds4_label(Path(r.path))), None)
    if first is not None:
        first.findings.append(Finding("PDS4-007", SEVERITY["PDS4-007"], first.path,
                                      "Schematron not run: saxonche is not installed (pip install pdsgen[pds4]); "
                                      "PDS4 labels were checked against their XML Schemas only"))


class _Report:
    def __init__(self, path: Path) -> None:
        self.path = path
        self.findings: list[Finding] = []

    def add(self, rule: str, message: str, line: int | None = None, keyword: str | None = None,
            severity: str | None = None) -> None:
        self.findings.append(Finding(rule, severity or SEVERITY[rule], str(self.path), message, line, keyword))


def validate_pds4(path: str | Path, catalog: SchemaCatalog | None = None, labels_only: bool = False,
                  use_schematron: bool = True) -> list[Finding]:
    """Every finding for one PDS4 label."""
    path = Path(path)
    report = _Report(path)
    catalog = catalog or SchemaCatalog.build()
    tree = _parse(report)
    if tree is None:
        return report.findings
    root = tree.getroot()
    if not (root.tag.startswith(P) and root.tag[len(P):].startswith("Product_")):
        report.add("PDS4-001", f"root element {root.tag} is not a PDS4 Product_*", root.sourceline)
        return report.findings
    for check in _schema_checks(tree, catalog, use_schematron):
        check(report)
    for content_check in _CONTENT_CHECKS:
        if labels_only and content_check not in _LABEL_ONLY_CHECKS:
            continue
        try:
            content_check(report, tree)
        except Exception as exc:  # a check must never turn odd input into a traceback
            report.add("PDS4-001", f"check {content_check.__name__} could not run ({type(exc).__name__}: {exc})",
                       severity="error")
    return sorted(report.findings, key=lambda f: (f.line or 0, f.rule))


_DECLARATION = re.compile(rb"<\?xml\s[^>]*\?>")


def _parse(report: _Report) -> etree._ElementTree | None:
    """The label's tree, or None after a PDS4-001 finding. A label whose XML declaration
    follows a comment (not well-formed, but readers such as GDAL accept it) is reported
    and then checked without the misplaced declaration, keeping its line numbers."""
    parser = etree.XMLParser(no_network=True, resolve_entities=False)
    try:
        data = report.path.read_bytes()
        return etree.ElementTree(etree.fromstring(data, parser))
    except OSError as exc:
        report.add("PDS4-001", f"cannot read the label: {exc.strerror or exc}")
        return None
    except etree.XMLSyntaxError as exc:
        declaration = _DECLARATION.search(data)
        if declaration is None or declaration.start() == 0:
            report.add("PDS4-001", f"not well-formed XML: {exc}", exc.lineno)
            return None
        line = data.count(b"\n", 0, declaration.start()) + 1
        report.add("PDS4-001", "the XML declaration is not at the start of the file (not well-formed XML)", line)
        blanked = data[:declaration.start()] + b" " * len(declaration.group()) + data[declaration.end():]
        try:
            return etree.ElementTree(etree.fromstring(blanked, parser))
        except etree.XMLSyntaxError as again:
            report.add("PDS4-001", f"not well-formed XML: {again}", again.lineno)
            return None


def _schema_checks(tree: etree._ElementTree, catalog: SchemaCatalog, use_schematron: bool
                   ) -> list[Callable[[_Report], None]]:
    refs = schema_references(tree)
    version = tree.findtext(f"{P}Identification_Area/{P}information_model_version") or "unknown"
    missing = [url for _, url in refs.xsd if catalog.resolve(url) is None]
    missing += [url for url in refs.sch if catalog.resolve(url) is None]

    def not_shipped(report: _Report) -> None:
        names = ", ".join(Path(u).name for u in dict.fromkeys(missing))
        report.add("PDS4-002", f"IM version {version} not shipped: no local copy of {names}; schema and "
                               f"Schematron checks skipped ({_IM_RE_HINT})",
                   tree.getroot().sourceline, "information_model_version")

    if missing:
        return [not_shipped]
    if not refs.xsd:
        return [lambda r: r.add("PDS4-004", "the label names no XML Schema (xsi:schemaLocation)",
                                tree.getroot().sourceline)]

    def xml_schema(report: _Report) -> None:
        try:
            schema = build_schema(catalog, refs.xsd)
        except SchemaImportError as exc:
            report.add("PDS4-003", exc.problem)
            return
        for line, message in xsd_errors(schema, tree):
            report.add("PDS4-004", message, line)

    def rules(report: _Report) -> None:
        if not refs.sch:
            return
        if not schematron.available():
            return  # reported once per run (add_run_notes), not once per label
        files = [p for p in (catalog.resolve(u) for u in refs.sch) if p is not None]
        text = etree.tostring(tree, encoding="unicode")
        for failure in schematron.compiled(files).check(text):
            rule = "PDS4-006" if failure.role in ("warning", "warn", "info") else "PDS4-005"
            report.add(rule, failure.message, schematron.location_line(tree, failure.location),
                       failure.rule_context)

    return [xml_schema, rules] if use_schematron else [xml_schema]


# --- content checks -------------------------------------------------------------------------


def _file_areas(tree: etree._ElementTree) -> Iterator[etree._Element]:
    for area in tree.getroot():
        if isinstance(area.tag, str) and area.tag.startswith(f"{P}File_Area"):
            yield area


# Units a label may state, to metres, metres per pixel, degrees (the PDS4 unit classes we read).
_UNITS = {"m": 1.0, "km": 1000.0, "cm": 0.01, "mm": 0.001, "m/pixel": 1.0, "km/pixel": 1000.0,
          "mm/pixel": 0.001, "deg": 1.0, "rad": 180.0 / math.pi, "mrad": 0.18 / math.pi}


def _number(element: etree._Element | None, path: str) -> float | None:
    """A numeric element's value in metres / metres per pixel / degrees (per its unit attribute)."""
    found = element.find(path) if element is not None else None
    if found is None or found.text is None:
        return None
    try:
        value = float(found.text)
    except ValueError:
        return None
    return value * _UNITS.get(found.get("unit", ""), 1.0)


def _data_path(report: _Report, area: etree._Element, report_missing: bool = True) -> Path | None:
    file = area.find(f"{P}File")
    name = file.findtext(f"{P}file_name") if file is not None else None
    if not name:
        return None
    path = report.path.parent / name
    if not path.is_file():
        if report_missing:
            report.add("PDS4-010", f"data file {name} not found beside the label", file.sourceline, "file_name")
        return None
    return path


def _check_data(report: _Report, tree: etree._ElementTree) -> None:
    """Each data file read once: its size, its MD5, and the statistics of every array in it."""
    for area in _file_areas(tree):
        path = _data_path(report, area)
        if path is None:
            continue
        file = area.find(f"{P}File")
        size = path.stat().st_size
        size_element = file.find(f"{P}file_size")
        if size_element is not None and _number(file, f"{P}file_size") != size:
            report.add("PDS4-011", f"file_size = {size_element.text} but {path.name} has {size} bytes",
                       size_element.sourceline, "file_size")
        arrays = [a for a in _area_arrays(area) if _fits(report, a, path, size)]
        md5_element = file.find(f"{P}md5_checksum")
        md5 = hashlib.md5()
        with open(path, "rb") as handle:
            position = 0
            while block := handle.read(_READ_BYTES):
                md5.update(block)
                for array in arrays:
                    array.feed(position, block)
                position += len(block)
        if md5_element is not None and md5_element.text and md5.hexdigest() != md5_element.text.strip().lower():
            report.add("PDS4-012", f"md5_checksum = {md5_element.text.strip()} but {path.name} has MD5 "
                                   f"{md5.hexdigest()}", md5_element.sourceline, "md5_checksum")
        for array in arrays:
            array.report(report)


class _ArrayStatistics:
    """Extremes, mean and deviation of one array's samples not flagged special, fed the
    file's bytes in order (samples split across two reads are carried over)."""

    def __init__(self, element: etree._Element, offset: int, elements: int, dtype: np.dtype) -> None:
        self.element = element
        self.start, self.end = offset, offset + elements * dtype.itemsize
        self.dtype = dtype
        constants = [v for v in _special_constants(element).values() if _storable(v, dtype)]
        # as stored: a decimal constant of a float32 array flags the float32 nearest to it
        self.flagged = np.array(constants, dtype=np.float64).astype(dtype).astype(np.float64)
        self.pending = b""
        self.count, self.total, self.squares = 0, 0.0, 0.0
        self.low, self.high = math.inf, -math.inf
        self.shift: float | None = None  # sums of (value - first value) stay accurate
        self.undeclared = 0

    def feed(self, position: int, block: bytes) -> None:
        low, high = max(self.start, position), min(self.end, position + len(block))
        if low >= high:
            return
        data = self.pending + block[low - position:high - position]
        usable = len(data) - len(data) % self.dtype.itemsize
        self.pending = data[usable:]
        values = np.frombuffer(data[:usable], dtype=self.dtype).astype(np.float64)
        valid = ~np.isin(values, self.flagged) & np.isfinite(values)
        if self.dtype.kind == "f":
            special = values <= _ISIS_SPECIAL_LIMIT
            self.undeclared += int(np.count_nonzero(special & valid))
            valid &= ~special
        chosen = values[valid]
        if chosen.size == 0:
            return
        self.shift = float(chosen[0]) if self.shift is None else self.shift
        centred = chosen - self.shift
        self.count += chosen.size
        self.total += float(centred.sum())
        self.squares += float((centred * centred).sum())
        self.low, self.high = min(self.low, float(chosen.min())), max(self.high, float(chosen.max()))

    def report(self, report: _Report) -> None:
        if self.undeclared:
            report.add("PDS4-022", f"{self.undeclared} samples hold ISIS special-pixel values (e.g. NULL "
                                   "-3.4028226550889045E+38) but Special_Constants does not declare them",
                       self.element.sourceline, "missing_constant")
        stats = self.element.find(f"{P}Object_Statistics")
        if stats is None or self.count == 0 or self.shift is None:
            return
        mean = self.shift + self.total / self.count
        deviation = math.sqrt(max(0.0, self.squares / self.count - (self.total / self.count) ** 2))
        _compare(report, stats, "minimum", self.low, "PDS4-020", _float32_tolerance(self.low, self.dtype))
        _compare(report, stats, "maximum", self.high, "PDS4-020", _float32_tolerance(self.high, self.dtype))
        spread = max(abs(self.high - self.low), 1e-12)
        _compare(report, stats, "mean", mean, "PDS4-021", 1e-6 * spread)
        _compare(report, stats, "standard_deviation", deviation, "PDS4-021", 1e-6 * spread)


def _area_arrays(area: etree._Element) -> Iterator[_ArrayStatistics]:
    for element in area:
        if not (isinstance(element.tag, str) and element.tag.startswith(f"{P}Array")):
            continue
        data_type = element.findtext(f"{P}Element_Array/{P}data_type") or ""
        offset = _number(element, f"{P}offset")
        axes = [int(_number(axis, f"{P}elements") or 0) for axis in element.findall(f"{P}Axis_Array")]
        if data_type in NUMPY_TYPES and offset is not None and axes:
            yield _ArrayStatistics(element, int(offset), math.prod(axes), np.dtype(NUMPY_TYPES[data_type]))


def _fits(report: _Report, array: _ArrayStatistics, path: Path, size: int) -> bool:
    if array.end <= size:
        return True
    report.add("PDS4-013", f"the array needs bytes up to {array.end} but {path.name} has {size}",
               array.element.sourceline, array.element.tag[len(P):])
    return False


def _special_constants(element: etree._Element) -> dict[str, float]:
    found = {}
    special = element.find(f"{P}Special_Constants")
    for child in special if special is not None else ():
        if isinstance(child.tag, str) and not child.tag.endswith(("valid_maximum", "valid_minimum")):
            try:
                found[child.tag.split("}")[1]] = float(child.text or "")
            except ValueError:
                continue
    return found


def _check_special_constants(report: _Report, tree: etree._ElementTree) -> None:
    """A special constant the array's data type cannot hold can never flag a sample."""
    for element in tree.iter():
        if not (isinstance(element.tag, str) and element.tag.startswith(f"{P}Array")):
            continue
        data_type = element.findtext(f"{P}Element_Array/{P}data_type") or ""
        if data_type not in NUMPY_TYPES:
            continue
        dtype = np.dtype(NUMPY_TYPES[data_type])
        for name, value in _special_constants(element).items():
            if not _storable(value, dtype):
                constant = element.find(f"{P}Special_Constants/{P}{name}")
                report.add("PDS4-023", f"{name} = {value!r} cannot be stored as {data_type}",
                           constant.sourceline if constant is not None else element.sourceline, name)


def _storable(value: float, dtype: np.dtype) -> bool:
    """Integers: a whole number in range; reals: finite within range (decimals round to the type)."""
    if dtype.kind == "f":
        return math.isfinite(value) and abs(value) <= float(np.finfo(dtype).max)
    info = np.iinfo(dtype)
    return float(value).is_integer() and info.min <= value <= info.max


def _float32_tolerance(value: float, dtype: np.dtype) -> float:
    if dtype.kind != "f":
        return 0.0
    return float(np.spacing(np.float32(abs(value)))) if math.isfinite(value) else 0.0


def _compare(report: _Report, stats: etree._Element, name: str, actual: float, rule: str, tolerance: float) -> None:
    element = stats.find(f"{P}{name}")
    stated = _number(stats, f"{P}{name}")
    if element is None or stated is None:
        return
    if not abs(stated - actual) <= tolerance:
        report.add(rule, f"{name} = {element.text} but the valid samples give {actual:.10g}",
                   element.sourceline, name)


# --- cartography ----------------------------------------------------------------------------

_SPHERE_NAMES = {"Equirectangular": "EQUIRECTANGULAR", "Polar Stereographic": "POLAR_STEREOGRAPHIC",
                 "Sinusoidal": "SINUSOIDAL"}


@dataclass
class _Cart:
    element: etree._Element
    projection: str
    parameters: etree._Element | None
    resolution_x: float
    resolution_y: float
    scale: float | None
    ulx: float
    uly: float
    a: float
    c: float
    bounds: dict[str, float]
    bound_lines: dict[str, int | None]
    encoding: str
    lines: int
    samples: int


def _read_cart(tree: etree._ElementTree) -> _Cart | None:
    cart = tree.find(f".//{C}Cartography")
    if cart is None:
        return None
    horizontal = f"{C}Spatial_Reference_Information/{C}Horizontal_Coordinate_System_Definition"
    planar = cart.find(f"{horizontal}/{C}Planar")
    model = cart.find(f"{horizontal}/{C}Geodetic_Model")
    if planar is None or model is None:
        return None
    projection = planar.findtext(f"{C}Map_Projection/{C}map_projection_name") or ""
    parameters = planar.find(f"{C}Map_Projection/{C}{projection.replace(' ', '_')}")
    rep = f"{C}Planar_Coordinate_Information/{C}Coordinate_Representation"
    values = {
        "rx": _number(planar, f"{rep}/{C}pixel_resolution_x"),
        "ry": _number(planar, f"{rep}/{C}pixel_resolution_y"),
        "ulx": _number(planar, f"{C}Geo_Transformation/{C}upperleft_corner_x"),
        "uly": _number(planar, f"{C}Geo_Transformation/{C}upperleft_corner_y"),
        "a": _number(model, f"{C}a_axis_radius"),
        "c": _number(model, f"{C}c_axis_radius"),
    }
    if any(v is None for v in values.values()):
        return None
    box = cart.find(f"{C}Spatial_Domain/{C}Bounding_Coordinates")
    bounds, bound_lines = {}, {}
    for side in ("west", "east", "north", "south"):
        number = _number(box, f"{C}{side}_bounding_coordinate")
        if number is not None:
            bounds[side] = number
            bound_lines[side] = box.find(f"{C}{side}_bounding_coordinate").sourceline
    encoding = planar.findtext(f"{C}Planar_Coordinate_Information/{C}planar_coordinate_encoding_method") or ""
    ref = cart.findtext(f"{P}Local_Internal_Reference/{P}local_identifier_reference")
    array = next((a for a in tree.iter() if isinstance(a.tag, str) and a.tag.startswith(f"{P}Array")
                  and a.findtext(f"{P}local_identifier") == ref), None)
    if array is None:
        return None
    axes = {a.findtext(f"{P}axis_name"): int(_number(a, f"{P}elements") or 0)
            for a in array.findall(f"{P}Axis_Array")}
    return _Cart(cart, projection, parameters, values["rx"], values["ry"],  # type: ignore[arg-type]
                 _number(planar, f"{rep}/{C}pixel_scale_x"), values["ulx"], values["uly"],  # type: ignore[arg-type]
                 values["a"], values["c"], bounds, bound_lines, encoding,  # type: ignore[arg-type]
                 axes.get("Line", 0), axes.get("Sample", 0))


def _angle(parameters: etree._Element | None, name: str, default: float = 0.0) -> float:
    value = _number(parameters, f"{C}{name}") if parameters is not None else None
    return default if value is None else value


def _check_cartography(report: _Report, tree: etree._ElementTree) -> None:
    cart = _read_cart(tree)
    if cart is None:
        return
    if cart.parameters is None:
        report.add("PDS4-032", f"map_projection_name {cart.projection!r} but no cart:"
                               f"{cart.projection.replace(' ', '_')} block holds its parameters",
                   cart.element.sourceline, "map_projection_name")
        return
    sphere_name = _SPHERE_NAMES.get(cart.projection)
    if sphere_name is None:  # a projection pdsgen does not write: its arithmetic is not checked
        return
    radius = cart.c if sphere_name == "POLAR_STEREOGRAPHIC" else cart.a
    if cart.scale is not None and radius > 0 and cart.resolution_x > 0:
        expected = math.pi * radius / 180.0 / cart.resolution_x
        if not math.isclose(cart.scale, expected, rel_tol=1e-6):
            report.add("PDS4-030", f"pixel_scale_x = {cart.scale:.10g} pixel/deg but pixel_resolution_x = "
                                   f"{cart.resolution_x:.10g} m on a {radius:.10g} m radius gives {expected:.10g}",
                       cart.element.sourceline, "pixel_scale_x")
    _check_bounds(report, cart, sphere_name, radius)


def _check_bounds(report: _Report, cart: _Cart, sphere_name: str, radius: float) -> None:
    """Only "Coordinate Pair" encodings give Geo_Transformation in projection metres
    (as GDAL reads them); other encodings are not checked."""
    if len(cart.bounds) != 4 or not cart.lines or not cart.samples or cart.encoding != "Coordinate Pair":
        return
    centre_lat = _angle(cart.parameters, "standard_parallel_1",
                        _angle(cart.parameters, "latitude_of_projection_origin"))
    if sphere_name != "EQUIRECTANGULAR":
        centre_lat = _angle(cart.parameters, "latitude_of_projection_origin")
    sphere = Sphere(sphere_name, radius, centre_lat, _angle(cart.parameters, "longitude_of_central_meridian"))
    y_shift = 0.0
    if sphere_name == "EQUIRECTANGULAR":  # a latitude of origin shifts northings
        y_shift = radius * math.radians(_angle(cart.parameters, "latitude_of_projection_origin"))
    x0, x1 = cart.ulx, cart.ulx + cart.samples * cart.resolution_x
    y1, y0 = cart.uly + y_shift, cart.uly + y_shift - cart.lines * cart.resolution_y
    lats, lons = sphere.inverse(*boundary(x0, x1, y0, y1))
    extremes = {"north": int(np.nanargmax(lats)), "south": int(np.nanargmin(lats))}
    if not sphere.contains_pole(x0, x1, y0, y1):
        extremes.update(west=int(np.nanargmin(lons)), east=int(np.nanargmax(lons)))
    for side, index in extremes.items():
        lat, lon = float(lats[index]), float(lons[index])
        found = lon if side in ("west", "east") else lat
        stated = cart.bounds[side]
        difference = (stated - found + 180.0) % 360.0 - 180.0 if side in ("west", "east") else stated - found
        pixels = abs(difference) * _metres_per_degree(sphere, lat, lon, side in ("west", "east")) / cart.resolution_x
        if pixels > 0.5:
            report.add("PDS4-031", f"{side}_bounding_coordinate = {stated:.10g} but Geo_Transformation "
                                   f"({cart.ulx:.10g}, {cart.uly:.10g}) gives {_wrap_bound(found, side):.10g} "
                                   f"({pixels:.2f} px off)",
                       cart.bound_lines.get(side), f"{side}_bounding_coordinate")
    if sphere.contains_pole(x0, x1, y0, y1):
        pole = "north" if sphere.north else "south"
        if abs(cart.bounds[pole]) != 90.0:
            report.add("PDS4-031", f"{pole}_bounding_coordinate = {cart.bounds[pole]:.10g} but the raster "
                                   "contains the pole", cart.bound_lines.get(pole), f"{pole}_bounding_coordinate")


def _metres_per_degree(sphere: Sphere, lat: float, lon: float, along_longitude: bool) -> float:
    """Projected metres per degree at a point, in longitude or latitude (numerically)."""
    step = 1e-4
    lat = max(-90.0 + step, min(90.0 - step, lat))
    x0, y0 = sphere.forward(lat, lon)
    x1, y1 = sphere.forward(lat, lon + step) if along_longitude else sphere.forward(lat - step, lon)
    return float(math.hypot(x1 - x0, y1 - y0)) / step


def _wrap_bound(value: float, side: str) -> float:
    return value % 360.0 if side in ("west", "east") else value


def _check_encoded_jp2(report: _Report, tree: etree._ElementTree) -> None:
    cart = _read_cart(tree)
    for area in _file_areas(tree):
        encoded = area.find(f"{P}Encoded_Image")
        if encoded is None or encoded.findtext(f"{P}encoding_standard_id") not in ("JP2", "J2C"):
            continue
        path = _data_path(report, area, report_missing=False)
        if path is None or cart is None:
            continue
        try:
            info = read_jp2(path)
        except Jp2Error as exc:
            report.add("PDS4-040", f"{path.name} is not a readable JP2: {exc}", encoded.sourceline)
            continue
        georef = next((g for g in info.georefs if g.source == "GeoJP2"), None)
        if georef is None:
            report.add("PDS4-040", f"{path.name} has no GeoJP2 box", encoded.sourceline)
            continue
        for name, stated, found in (("upperleft_corner_x", cart.ulx, georef.ulx),
                                    ("upperleft_corner_y", cart.uly, georef.uly),
                                    ("pixel_resolution_x", cart.resolution_x, georef.xres)):
            if not math.isclose(stated, found, rel_tol=1e-9, abs_tol=1e-6 * cart.resolution_x):
                report.add("PDS4-040", f"cart:{name} = {stated:.10g} but the GeoJP2 box of {path.name} "
                                       f"gives {found:.10g}", encoded.sourceline, name)


_CONTENT_CHECKS = (_check_data, _check_special_constants, _check_cartography, _check_encoded_jp2)
_LABEL_ONLY_CHECKS = (_check_special_constants, _check_cartography)
