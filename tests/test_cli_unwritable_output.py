"""An output the system refuses - a read-only file system, a full disk - is one line naming the
path and the reason, exit status 2, for every command that writes; never a traceback, and
the staging clean-up never raises over the real error.

The file systems are real: small tmpfs mounts, one remounted read-only, one of a few KiB that
fills up. Tests run as root here, and root ignores permission bits (a chmod 555 directory
stays writable to it), so a mount is the honest refusal; where mounting is not allowed the
tests are skipped.
"""

from __future__ import annotations

import subprocess
import uuid
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from pdsgen.cli import main

from helpers import ORIGINS, elevation_array, write_raster


def _mount(point: Path, options: str) -> bool:
    point.mkdir(parents=True, exist_ok=True)
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(point)], capture_output=True)
    return done.returncode == 0


@pytest.fixture(scope="module")
def places(tmp_path_factory) -> Iterator[dict[str, Path]]:
    """A read-only file system holding one empty directory per command, and a 16 KiB one."""
    root = tmp_path_factory.mktemp("mounts")
    read_only, full = root / "ro", root / "full"
    if not _mount(read_only, "size=64k"):
        pytest.skip("mounting a tmpfs is not allowed here")
    for name in COMMANDS:
        (read_only / name).mkdir()
    remounted = subprocess.run(["mount", "-o", "remount,ro", str(read_only)], capture_output=True).returncode == 0
    mounted_full = _mount(full, "size=16k")
    try:
        if not remounted or not mounted_full:
            pytest.skip("remounting read-only or mounting a second tmpfs is not allowed here")
        yield {"read-only file system": read_only, "no space left on device": full}
    finally:
        for point in (read_only, full):
            subprocess.run(["umount", str(point)], capture_output=True)


@pytest.fixture(scope="module")
def inputs(tmp_path_factory) -> dict[str, Path]:
    """A DTM and an orthoimage GeoTIFF, and a PDS3 DTM product made from the first."""
    folder = tmp_path_factory.mktemp("inputs")
    crs, transform = ORIGINS["equirectangular"]
    dtm = write_raster(folder / "dtm.tif", elevation_array(96, 96), crs, transform)
    image = np.linspace(0, 60000, 96 * 96, dtype=np.uint16).reshape(96, 96)
    ortho = write_raster(folder / "ortho.tif", image, crs, transform)
    made = CliRunner().invoke(main, ["dtm", str(dtm), "-o", str(folder / "product"), "--product-id", "DTM_A"])
    assert made.exit_code == 0, made.output
    return {"dtm": dtm, "ortho": ortho, "product": folder / "product" / "DTM_A.IMG", "tree": folder / "product"}


# command -> its arguments, OUT being the output it is told to write (a directory or a file)
COMMANDS: dict[str, list[str]] = {
    "params": ["params", "--template", "generic", "-o", "OUT/p.toml"],
    "dtm": ["dtm", "{dtm}", "-o", "OUT"],
    "ortho": ["ortho", "{ortho}", "-o", "OUT"],
    "extras": ["extras", "{product}", "-o", "OUT"],
    "migrate": ["migrate", "{product}", "-o", "OUT", "--bundle-lid", "urn:nasa:pds:test"],
    "mosaic": ["mosaic", "{product}", "{product}", "--product-id", "MOSAIC_A", "-o", "OUT"],
    "validate": ["validate", "--no-config", "{product}", "--format", "json", "-o", "OUT/report.json"],
    "baseline": ["validate", "--no-config", "{product}", "--write-baseline", "OUT/baseline.toml"],
    "review": ["review", "{tree}", "-o", "OUT/review.html"],
    "deliver": ["deliver", "{tree}", "-o", "OUT/delivery", "--volume-id", "TEST_0001"],
    "demo": ["demo", "OUT"],
}


@pytest.mark.parametrize("refusal", ["read-only file system", "no space left on device"])
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_an_unwritable_output_is_one_line_and_exit_2(command, refusal, places, inputs):
    if refusal == "no space left on device" and command in ("params", "validate", "baseline"):
        pytest.skip("its file is smaller than the disk: only the read-only file system refuses it")
    out = places[refusal] / (command if refusal == "read-only file system" else uuid.uuid4().hex)
    out.mkdir(exist_ok=refusal == "read-only file system")
    args = [arg.format(**inputs).replace("OUT", str(out)) for arg in COMMANDS[command]]
    done = CliRunner().invoke(main, args)
    assert done.exit_code == 2, (done.output, done.exception)
    lines = done.stderr.strip().splitlines()
    errors = [line for line in lines if line.startswith("pdsgen: error: ")]
    assert len(errors) == 1 and "Traceback" not in done.output, done.output
    error = errors[0]
    assert str(places[refusal]) in error  # the path refused ...
    assert refusal in error.lower() or "not writable" in error, error  # ... and why
    leftovers = [path for path in places[refusal].rglob("*") if path.is_file()]
    if refusal == "no space left on device":
        assert not [path for path in leftovers if path.is_relative_to(out) and ".part" in path.name]


def test_the_clean_up_never_hides_the_real_error(places):
    """A temporary never made, on a file system that refuses its removal too: the write's own
    error is what is raised, naming the file the caller asked for, not the temporary."""
    from pdsgen.errors import OutputError
    from pdsgen.storage.staging import staged_file

    target = places["read-only file system"] / "params" / "x.txt"
    with pytest.raises(OutputError) as raised, staged_file(target) as staged:
        staged.write_text("x")
    assert str(raised.value) == f"{target}: cannot write: read-only file system"
