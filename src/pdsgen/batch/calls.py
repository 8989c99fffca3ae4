"""The one library call a batch job makes, per kind: the same call its CLI command makes.

A job's parameters are those its click command parsed (see manifest.py), under the
click parameter names; each function here passes them to the library function
behind the command and returns what the job wrote: `outputs` (every file) and
`products` (the files a later job reads: a DTM's .IMG, an orthoimage's .LBL).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

Outputs = dict[str, list[str]]


def run_dtm(p: Mapping[str, Any], overwrite: bool) -> Outputs:
    common = dict(product_id=p["product_id"], source_product_ids=tuple(p["source_ids"]),
                  params=p["params_file"], version=p["product_version"], overwrite=overwrite)
    if p["profile"] == "imars":
        from ..imars import write_imars_dtm

        imars = write_imars_dtm(p["input_path"], p["outdir"], kind=p["kind"][:2],
                                vertical_datum=p["vertical_datum"], areoid=p["areoid"],
                                precision=p["precision"], **common)
        return _written([imars.tiff_path, imars.pvl_path, imars.footprint_path], [imars.tiff_path])
    if p["profile"] == "hrsc":
        from ..hrsc import write_hrsc_dtm

        hrsc = write_hrsc_dtm(p["input_path"], p["outdir"], kind=p["kind"], vertical_datum=p["vertical_datum"],
                              areoid=p["areoid"], precision=p["precision"], reproject_input=p["reproject"],
                              byte_order=p["byte_order"] or "msb", **common)
        return _written([hrsc.path], [hrsc.path])
    from ..dtm import write_dtm

    dtm = write_dtm(p["input_path"], p["outdir"], profile=p["profile"], byte_order=p["byte_order"] or "lsb",
                    institution=p["institution"], **common)
    return _written([dtm.path], [dtm.path])


def run_ortho(p: Mapping[str, Any], overwrite: bool) -> Outputs:
    from ..errors import PdsgenError

    value_range = tuple(p["value_range"]) if p["value_range"] else None
    common = dict(product_id=p["product_id"], params=p["params_file"], version=p["product_version"],
                  overwrite=overwrite)
    if p["profile"] in ("hrsc", "imars") and p["bits"] not in (None, "8"):
        raise PdsgenError(None, f"--profile {p['profile']} orthoimages are 8-bit; --bits {p['bits']} does not apply")
    if p["profile"] == "hrsc":
        from ..hrsc import write_hrsc_nd4

        nd4 = write_hrsc_nd4(p["input_path"], p["outdir"], value_range=value_range, reproject_input=p["reproject"],
                             source_product_ids=tuple(p["source_ids"]), **common)
        return _written([nd4.path], [nd4.path])
    if p["profile"] == "imars":
        from ..imars import write_imars_ori

        ori = write_imars_ori(p["input_path"], p["outdir"], source_product_ids=tuple(p["source_ids"]),
                              value_range=value_range, **common)
        return _written([ori.tiff_path, ori.pvl_path, ori.footprint_path], [ori.tiff_path])
    from ..ortho import write_ortho

    ortho = write_ortho(p["input_path"], p["outdir"], profile=p["profile"],
                        bits=int(p["bits"]) if p["bits"] else None, value_range=value_range,
                        observation_id=p["observation_id"], source_dtm_id=p["source_dtm_id"],
                        sequence=p["sequence"], gmljp2=p["gmljp2"], **common)
    return _written([ortho.jp2_path, ortho.label_path], [ortho.label_path])


def run_extras(p: Mapping[str, Any], overwrite: bool) -> Outputs:
    from ..extras import make_extras

    written = make_extras(p["products"], p["outdir"], credit=p["credit"], params=p["params_file"],
                          browse_width=p["browse_width"], thumb_width=p["thumb_width"], azimuth=p["azimuth"],
                          altitude=p["altitude"], exaggeration=p["exaggeration"], kind=p["kind"],
                          profile=p["profile"], overwrite=overwrite)
    return _written(written, [])


class ProblemsFound(Exception):
    """A validation that ran and found errors: the job failed, with the report's summary as reason."""


def run_validate(p: Mapping[str, Any], overwrite: bool) -> Outputs:
    """Validate; the report goes to `output` (written whole, then renamed) when given."""
    from ..staging import StagedOutputs
    from ..validate import render, validate_paths

    report = validate_paths(p["paths"], strict=p["strict"], jobs=p["jobs"], labels_only=p["labels_only"],
                            dictionaries=p["dictionaries"])
    written: list[Path] = []
    if p["output"]:
        output = Path(p["output"])
        output.parent.mkdir(parents=True, exist_ok=True)
        with StagedOutputs([output], overwrite=True) as staged:
            staged.path(output).write_text(render(report, p["fmt"]), encoding="utf-8")
        written.append(output)
    else:
        print(render(report, p["fmt"]), end="")  # into the job's log
    if report.exit_code != 0:
        raise ProblemsFound(report.summary_line())
    return _written(written, [])


def _written(outputs: list[Path], products: list[Path]) -> Outputs:
    return {"outputs": [str(o) for o in outputs], "products": [str(p) for p in products]}


RUNNERS: dict[str, Callable[[Mapping[str, Any], bool], Outputs]] = {
    "dtm": run_dtm, "ortho": run_ortho, "extras": run_extras, "validate": run_validate,
}
