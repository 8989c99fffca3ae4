"""What an HRSC level-4 label says beyond the grid: keywords carried from the source
level-2/3 labels, the projection-offset convention, and the DN statistics DLR writes
in the IMAGE object (MINIMUM, MAXIMUM, MEAN, STANDARD_DEVIATION), computed while the
data are written.
"""

from __future__ import annotations

import datetime as dt
import math
import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..formats.img import BandStatistics
from ..geo.geometry import MapGeometry
from ..label.mapping import label_mapping
from ..label.parser import label_length
from ..label.read import LabelFile, structure_problem
from ..label.values import Quantity, Symbol
from ..missions import hrsc as hrsc_mission

Encode = Callable[[np.ndarray, "np.ndarray | None"], np.ndarray]


def offset_context(geometry: MapGeometry, convention: str) -> dict[str, object]:
    """LINE/SAMPLE_PROJECTION_OFFSET in the chosen convention, and the label comment saying which."""
    shift = hrsc_mission.OFFSET_CONVENTIONS[convention]
    return {
        "line_projection_offset": geometry.line_projection_offset + shift,
        "sample_projection_offset": geometry.sample_projection_offset + shift,
        "offset_note": "\n".join(hrsc_mission.OFFSET_NOTES[convention]),
    }


def carried_context(
    source_labels: Sequence[str | os.PathLike[str]], orbit: int, outdir: Path | None = None
) -> dict[str, object]:
    """The keywords the product carries from its source labels (none without them).

    A pointer to a description file (^MEX_POINTING_DESC = "MEX_POINTING_DESC.TXT") is
    carried only when that file is in the output directory: a pointer to a file the
    delivery lacks is an error of the product (the validator's PTR-002). Copy the file
    from the HRSC volume beside the products to have the pointer written.
    """
    carried: dict[str, object] = {}
    labels = [_read_source_label(Path(path)) for path in source_labels]
    for path, label in zip(source_labels, labels, strict=True):
        found = label.get("ORBIT_NUMBER")
        if found is not None and int(found) != orbit:
            raise InputError(path, f"is a label of orbit {found}, the product is of orbit {orbit}")
    if labels:
        first = labels[0]
        for group in hrsc_mission.CARRIED_KEYWORDS.values():
            carried |= {key: _label_value(key, first[key]) for key in group if key in first}
        earliest = min(labels, key=lambda label: _time_key(label.get("START_TIME")))
        latest = max(labels, key=lambda label: _time_key(label.get("STOP_TIME")))
        carried |= {key: _label_value(key, earliest[key]) for key in hrsc_mission.START_KEYWORDS if key in earliest}
        carried |= {key: _label_value(key, latest[key]) for key in hrsc_mission.STOP_KEYWORDS if key in latest}
        carried = {key: value for key, value in carried.items()
                   if not key.startswith("^") or (outdir is not None and (outdir / str(value)).is_file())}
    groups = hrsc_mission.CARRIED_KEYWORDS
    return {
        "carried": carried,
        "carried_keys": {
            "identification": groups["identification"],
            "time": groups["time"],
            "orbit": groups["orbit"],
        },
    }


def _read_source_label(path: Path) -> Mapping[str, Any]:
    """The source label's keywords, read by the label reader up to END (pvl's value shapes)."""
    if not path.is_file():
        raise InputError(path, "source label not found")
    try:
        label = LabelFile.read(path).label
    except OSError as exc:
        raise InputError(path, f"cannot be read ({exc.strerror})") from None
    broken = structure_problem(label)
    if broken is not None or not label.root.items:
        why = f"line {broken.line}: {broken.message}" if broken is not None else "no statements"
        raise InputError(path, f"is not a readable PDS3 label ({why})")
    return label_mapping(label)


def _time_key(value: object) -> str:
    if isinstance(value, dt.datetime):
        return value.replace(tzinfo=None).isoformat()
    return str(value) if value is not None else ""


def _label_value(key: str, value: Any) -> object:
    """A value read from a source label (label_mapping's shapes), as pdsgen's label writer writes
    it (identifiers stay bare)."""
    if hasattr(value, "value") and hasattr(value, "units"):
        return Quantity(value.value, str(value.units))
    if isinstance(value, (list, tuple)):
        return [_label_value(key, item) for item in value]
    if isinstance(value, str) and not key.startswith("^"):
        try:
            return Symbol(value)
        except ValueError:
            return value
    if isinstance(value, dt.datetime):
        return value.replace(tzinfo=None)
    return value


class DnMoments:
    """MINIMUM, MAXIMUM, MEAN and STANDARD_DEVIATION of the stored DNs, counted by the
    encoder as the data are written (one pass; no second read of the raster)."""

    # Printed as DLR does, to 6 significant digits; the placeholder is at least as wide.
    _DIGITS = 6
    _WIDEST_INT = -(10**23)
    _WIDEST_REAL = -1.234567e-123

    def __init__(self) -> None:
        self.count = 0
        self.total = 0.0
        self.squares = 0.0

    def counting(self, encode: Encode) -> Encode:
        def encode_and_count(values: np.ndarray, invalid: np.ndarray | None) -> np.ndarray:
            dns = encode(values, invalid)
            valid = dns if invalid is None else dns[~invalid]
            as_float = valid.astype(np.float64)
            self.count += int(as_float.size)
            self.total += float(as_float.sum())
            self.squares += float(np.square(as_float).sum())
            return dns

        return encode_and_count

    def summary(self, stats: BandStatistics) -> dict[str, object]:
        """The four keywords; placeholders of the widest form before the data are written."""
        if self.count == 0:
            return {"minimum": self._WIDEST_INT, "maximum": self._WIDEST_INT,
                    "mean": self._WIDEST_REAL, "standard_deviation": self._WIDEST_REAL}
        mean = self.total / self.count
        variance = max(self.squares / self.count - mean * mean, 0.0)
        return {
            "minimum": int(stats.minimum),
            "maximum": int(stats.maximum),
            # Written whatever its sign, as DLR does: heights below the datum are normal on
            # Mars and the dictionary gives MEAN no lower bound.
            "mean": _significant(mean, self._DIGITS),
            "standard_deviation": _significant(math.sqrt(variance), self._DIGITS),
        }


def _significant(value: float, digits: int) -> float:
    return float(f"{value:.{digits}g}")


# -- the VICAR2 header DLR writes between the PDS label and the image ----------------------
VICAR_DESCRIPTION_NAME = "VICAR2.TXT"
VICAR_DESCRIPTION = """VICAR2.TXT - the VICAR header of the HRSC level-4 image files in this directory

Each image file (h<orbit>_<sequence>_<kind>.img) holds, one after the other: the PDS3
label (LABEL_RECORDS records), a VICAR2 label (the IMAGE_HEADER object: ^IMAGE_HEADER
gives its first record, BYTES its length) and the image (^IMAGE). Both labels describe
the same image, so PDS3 readers and VICAR tools (and GDAL's VICAR driver) read it alike.

The VICAR2 label is ASCII text of KEY=VALUE items separated by blanks, padded with
blanks to whole records:
  LBLSIZE   length of the VICAR label in bytes (a multiple of RECSIZE)
  FORMAT    sample type: BYTE (8-bit unsigned), HALF (16-bit signed integer)
  TYPE      IMAGE;  ORG  BSQ (band sequential)
  NL NS NB  lines, samples per line, bands (also N1 = NS, N2 = NL, N3 = NB)
  RECSIZE   bytes per image line; BUFSIZ the same
  NBB NLB   0: no binary prefix bytes or header records
  EOL       0: no label after the image
  INTFMT    HIGH (big-endian integers) or LOW; REALFMT IEEE or RIEEE likewise
  HOST      the byte-order family of the writing machine; B* items for binary parts
The physical meaning of the samples (SCALING_FACTOR, OFFSET, missing DN) is given by
the PDS3 label only.
"""


class HeaderedRecords:
    """Record numbers of a PDS3 file with a header between label and image:
    [PDS3 label | VICAR header | image], all in records of `record_bytes`."""

    def __init__(self, record_bytes: int, label_records: int, header_records: int, data_records: int) -> None:
        self.record_bytes = record_bytes
        self.label_records = label_records
        self.header_records = header_records
        self.data_records = data_records

    @property
    def header_pointer(self) -> int:
        return self.label_records + 1

    @property
    def header_bytes(self) -> int:
        return self.header_records * self.record_bytes

    @property
    def image_pointer(self) -> int:
        return self.label_records + self.header_records + 1

    @property
    def file_records(self) -> int:
        return self.label_records + self.header_records + self.data_records


def with_header(render: Callable[[HeaderedRecords], str], header: bytes, record_bytes: int
                ) -> Callable[[Any], str]:
    """A renderer for write_attached_product whose "label" is the PDS3 label padded to
    whole records followed by `header`; the PDS3 label states the split."""
    header_records = len(header) // record_bytes

    def render_both(layout: Any) -> str:
        label_records = max(layout.label_records - header_records, 1)
        view = HeaderedRecords(record_bytes, label_records, header_records, layout.data_records)
        text = render(view)
        padding = " " * max(label_records * record_bytes - len(text), 0)
        return text + padding + header.decode("ascii")

    return render_both


def pds_label_part(text: str) -> str:
    """The PDS3 label of a file's leading text (everything up to and including END)."""
    end = label_length(text.encode("latin-1", errors="replace"))  # one byte per character
    if end is None:
        raise ValueError("the text holds no END line")
    return text[:end]
