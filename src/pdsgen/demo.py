"""`pdsgen demo`: every product the tool makes, from a built-in synthetic scene.

The demo is also the quickest end-to-end check on a new machine: it writes the
inputs it uses under OUTDIR/input/ so a user can rerun any single step by hand.
"""

from __future__ import annotations

import os
import shlex
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .errors import OutputError
from .extras import make_extras
from .formats.jp2 import require_openjpeg
from .products.dtm import DtmProduct, write_dtm
from .products.ortho import OrthoProduct, write_ortho
from .results import CommandResult, files_json
from .storage.staging import prepare_output_dir
from .synthetic import make_scene, write_geotiff
from .validate import validate_paths
from .validate.report import ValidationReport

DEMO_SOURCES = ("PSP_008669_1705", "PSP_009025_1705")
DEMO_INSTITUTION = "U"
DEMO_ORTHO_OBSERVATION = "PSP_008669_1705"
# What the HiRISE profile cannot know of the demo's products (a product left "UNK" is text still to
# write, which validate --strict fails on): stated in a params file, as a user's products are.
DEMO_PARAMS = "demo_params.toml"
DEMO_IDENTIFICATION = {
    "PRODUCER_FULL_NAME": "pdsgen demo",
    "RATIONALE_DESC": "Synthetic terrain and orthoimage made by pdsgen demo to show its products",
}
DEMO_PARAMS_TEXT = (
    "# The demo's identification: what the HiRISE profile leaves UNK (pdsgen params --template hirise)\n"
    + "".join(f'{keyword} = "{value}"\n' for keyword, value in DEMO_IDENTIFICATION.items())
)


@dataclass
class DemoResult(CommandResult):
    """The inputs and products the demo wrote, a line on each product, and the validator's report
    on them: the demo's own products must validate, so its exit status is the validator's."""

    inputs: list[Path] = field(default_factory=list)
    products: list[Path] = field(default_factory=list)
    lines: list[str] = field(default_factory=list)
    validation: ValidationReport | None = None
    named_as: str = "."  # OUTDIR as the caller named it
    warnings: tuple[str, ...] = ()

    @property
    def files(self) -> tuple[Path, ...]:
        return tuple(self.products)

    @property
    def summary_lines(self) -> tuple[str, ...]:
        return (f"inputs in {self.named_as}/input: " + ", ".join(p.name for p in self.inputs), *self.lines)

    @property
    def exit_code(self) -> int:
        return self.validation.exit_code if self.validation else 0

    def details(self) -> dict[str, Any]:
        validation = self.validation
        return {"inputs": files_json(self.inputs),
                "checks": {"validate": validation.summary_line() if validation else "not run",
                           "exit_code": validation.exit_code if validation else None}}


def _write_input(path: Path, data: Any, scene: Any) -> Path:
    """One of the demo's input GeoTIFFs, written whole or not at all. GDAL's refusal to write
    (a full disk, a read-only file system) becomes the one line naming the file: GDAL's own
    message says only "write failed", so the file system's free space tells a full disk."""
    from rasterio.errors import RasterioIOError

    from .storage.staging import staged_file

    with staged_file(path) as staged:
        try:
            write_geotiff(staged, data, scene.transform, scene.crs, None)
        except RasterioIOError as exc:
            full = os.statvfs(path.parent).f_bavail == 0  # before the temporary is removed
            raise OutputError(path, "cannot write: " + ("no space left on device" if full
                                                         else f"GDAL refused it ({exc.__cause__ or exc})")) from None
    return path


def run_demo(outdir: str | os.PathLike[str], overwrite: bool = True) -> DemoResult:
    """Generate the synthetic inputs and every product from them into OUTDIR."""
    require_openjpeg()  # the orthoimage needs it: refuse before anything is written
    named_as, outdir = os.fspath(outdir), prepare_output_dir(outdir)
    input_dir = prepare_output_dir(outdir / "input")
    scene = make_scene()
    result = DemoResult(named_as=named_as)
    dtm_input = _write_input(input_dir / "demo_dtm.tif", scene.elevation, scene)
    ortho_input = _write_input(input_dir / "demo_ortho_red.tif", scene.reflectance, scene)
    params = input_dir / DEMO_PARAMS
    params.write_text(DEMO_PARAMS_TEXT, encoding="ascii")
    result.inputs += [dtm_input, ortho_input, params]

    dtm = write_dtm(
        dtm_input, outdir, profile="hirise", source_product_ids=DEMO_SOURCES,
        institution=DEMO_INSTITUTION, params=params, overwrite=overwrite,
    )
    assert isinstance(dtm, DtmProduct)  # the HiRISE profile writes the standard float32 DTM
    result.products += dtm.written_files
    result.lines.append(
        f"DTM    {dtm.path}: {dtm.geometry.lines} x {dtm.geometry.samples} posts (lines x samples) at "
        f"{dtm.geometry.map_scale:g} m, {dtm.geometry.projection_type.lower()}, "
        f"elevations {dtm.valid_minimum:.1f} .. {dtm.valid_maximum:.1f} m"
    )

    ortho = write_ortho(
        ortho_input, outdir, profile="hirise", observation_id=DEMO_ORTHO_OBSERVATION,
        source_dtm_id=dtm.product_id, params=params, overwrite=overwrite,
    )
    assert isinstance(ortho, OrthoProduct)  # and the standard JP2 + LBL orthoimage
    result.products += ortho.written_files
    result.lines.append(
        f"ORTHO  {ortho.jp2_path} + {' + '.join(path.name for path in ortho.written_files[1:])}: "
        f"{ortho.bits}-bit lossless JPEG 2000, "
        f"I/F = DN * {ortho.scaling_factor:.6g} + {ortho.offset:.6g}"
    )

    extras = make_extras([dtm.path, ortho.label_path], outdir / "extras", overwrite=overwrite)
    result.products += extras
    result.lines.append(
        f"EXTRAS {sum(p.suffix == '.jpg' for p in extras)} preview JPEGs and README.TXT in {outdir / 'extras'}/ "
        f"(greyscale, shaded relief, colour over relief; orthoimage browse)"
    )

    result.validation = validate_paths([outdir], strict=True)
    # the command as a user can paste it: the same check the demo just ran
    result.lines.append(f"CHECK  pdsgen validate --strict {shlex.quote(str(outdir))}: "
                        f"{result.validation.summary_line()}")
    return result
