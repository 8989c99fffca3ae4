"""Batch manifests: checked whole, with the CLI commands' own checks, before any cluster starts."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from pdsgen.batch import ManifestError, Settings, load_manifest, plan
from pdsgen.batch.calls import RUNNERS
from pdsgen.batch.progress import Progress
from pdsgen.batch.run import make_task
from pdsgen.demo import DEMO_PARAMS, DEMO_PARAMS_TEXT
from pdsgen.validate import validate_paths

from helpers import ORIGINS, elevation_array, run_cli, write_raster


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "batch.toml"
    path.write_text(text, encoding="utf-8")
    return path


def problems(tmp_path: Path, text: str) -> list[str]:
    with pytest.raises(ManifestError) as caught:
        load_manifest(write(tmp_path, text), tmp_path / "out")
    return caught.value.problems


def test_example_parses_and_its_jobs_run(tmp_path):
    """`pdsgen batch --example` on inputs named as in its comment makes a valid delivery."""
    example = run_cli("batch", "--example")
    assert example.returncode == 0
    crs, transform = ORIGINS["equirectangular"]
    (tmp_path / "input").mkdir()
    elevation = elevation_array(64, 64)
    write_raster(tmp_path / "input" / "demo_dtm.tif", elevation, crs, transform)
    write_raster(tmp_path / "input" / "demo_ortho_red.tif", (elevation + 4100) / 1000, crs, transform)
    (tmp_path / "input" / DEMO_PARAMS).write_text(DEMO_PARAMS_TEXT)  # the demo's identification, as it writes it
    manifest = load_manifest(write(tmp_path, example.stdout))
    assert [j.kind for j in manifest.jobs] == ["dtm", "ortho", "extras", "validate"]
    assert manifest.outdir == tmp_path / "delivery"
    products: dict[str, list[str]] = {}
    for job in manifest.jobs:
        products[job.id] = RUNNERS[job.kind](make_task(job, manifest, Settings(), products)["params"], False, 1)[
            "products"]
    assert validate_paths([tmp_path / "delivery"], strict=True).exit_code == 0
    assert (tmp_path / "delivery" / "extras" / "README.TXT").is_file()


def test_every_problem_reported_at_once_exit_2(tmp_path):
    path = write(tmp_path, """
[batch]
outdir = "out"
colour = "blue"

[[dtm]]
id = "a"
input = "a.tif"
prodcut_id = "X"

[[dtm]]
id = "b"
input = "b.tif"
precision = "fine"
profile = "hrsc"

[[dtm]]
id = "c"
input = "c.tif"
institution = "U"
profile = "hrsc"

[[ortho]]
input = "o.tif"
version = 1.10
after = ["nobody"]
""")
    proc = run_cli("batch", path)
    assert proc.returncode == 2 and proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert all(line.startswith(f"pdsgen: error: {path}: ") for line in lines)
    text = proc.stderr
    assert "[batch]: unknown key 'colour'" in text
    assert "(a): unknown key 'prodcut_id'" in text
    assert "'precision'" in text and "'fine' is not a valid float" in text
    assert "--institution does not apply to --profile hrsc" in text
    assert "version must be a string" in text
    assert len(lines) == 5
    assert not (tmp_path / "out").exists()


def test_values_are_parsed_by_the_commands(tmp_path):
    (job,) = load_manifest(write(tmp_path, """
[[ortho]]
input = "in/o.tif"
outdir = "sub"
bits = 10
range = [-1, 5.5]
source_dtm_id = "D"
gmljp2 = true
"""), tmp_path / "out").jobs
    assert job.id == "o"
    assert job.params["bits"] == "10" and job.params["value_range"] == (-1.0, 5.5) and job.params["gmljp2"]
    assert job.params["sequence"] == 1  # the command's default
    assert job.params["input_path"] == str(tmp_path / "in" / "o.tif")  # inputs: from the manifest's folder
    assert job.params["outdir"] == str(tmp_path / "out" / "sub")  # outputs: from the batch outdir


@pytest.mark.parametrize(("text", "expected"), [
    ('[[dtm]]\ninput = "a.tif"\nsource_product_id = "P"\n', "source_product_id must be a list"),
    ('[[dtm]]\ninput = "a.tif"\noverwrite = "yes"\n', "overwrite must be true or false"),
    ('[[dtm]]\ninput = "a.tif"\nmemory = "lots"\n', "memory must be a whole number of bytes"),
    ('[[dtm]]\nprofile = "hirise"\n', "Missing argument 'input'"),
    ('[[validate]]\ninputs = ["."]\nlist_rules = true\n', "unknown key 'list_rules'"),
    ('[[dtm]]\ninput = "a.tif"\n[[dtm]]\ninput = "b/a.tif"\n', "job id 'a' is used twice"),
    ('[[dtm]]\nid = "x"\ninput = "a.tif"\nafter = ["y"]\n[[dtm]]\nid = "y"\ninput = "b.tif"\nafter = ["x"]\n',
     "in a circle"),
    ('[[extras]]\ninputs = ["a.IMG"]\n[[extras]]\ninputs = ["b.IMG"]\n', "both write"),
    ("[[dtm]]\n[pdsgen]\n", "unknown table [pdsgen]"),
])
def test_mistakes(tmp_path, text, expected):
    assert any(expected in p for p in problems(tmp_path, text)), problems(tmp_path, text)


def test_dry_run_plan(tmp_path):
    crs, transform = ORIGINS["equirectangular"]
    write_raster(tmp_path / "a.tif", elevation_array(8, 8), crs, transform)
    manifest = load_manifest(write(tmp_path, """
[[dtm]]
input = "a.tif"
[[dtm]]
input = "elsewhere/b.tif"
[[extras]]
after = ["a", "b"]
"""), tmp_path / "out")
    out = io.StringIO()
    plan(manifest, Settings(), out)
    text = out.getvalue()
    assert "to do   dtm      a\n" in text and "blocked extras   extras-1  (after a, b)" in text
    assert "3 jobs: 2 to do, 0 done, 1 blocked" in text
    assert f"not visible from here (must exist on the workers): {tmp_path / 'elsewhere' / 'b.tif'}" in text
    assert not (tmp_path / "out").exists()


def test_progress_bar_on_a_terminal_lines_otherwise():
    outcome = {"id": "a", "status": "done", "seconds": 1.25, "error": None}
    failed = {"id": "b", "status": "failed", "seconds": 0.5, "error": "b.tif: no such file"}
    plain, bar = io.StringIO(), io.StringIO()
    for stream, is_bar in ((plain, False), (bar, True)):
        progress = Progress(2, stream, bar=is_bar)
        progress.started()
        progress.started()
        progress.finished(outcome, "dtm")
        progress.finished(failed, "ortho")
        progress.close()
    assert plain.getvalue() == "done    dtm      a  1.2 s\nFAILED  ortho    b: b.tif: no such file\n"
    assert "\r" in bar.getvalue() and "2/2" in bar.getvalue() and "running 0" in bar.getvalue()
    assert "FAILED  ortho    b: b.tif: no such file\n" in bar.getvalue()


def test_bar_only_when_the_stream_is_a_terminal():
    import os
    import pty

    leader, follower = pty.openpty()
    try:
        with os.fdopen(follower, "w", closefd=False) as terminal:
            assert Progress(1, terminal).bar
    finally:
        os.close(leader)
        os.close(follower)
    assert not Progress(1, io.StringIO()).bar


def test_readme_manifest_is_a_valid_manifest(tmp_path):
    import docs_text
    block = docs_text.section_starting("Batch").split("```toml\n", 1)[1].split("```", 1)[0]
    manifest = load_manifest(write(tmp_path, block))
    assert [j.kind for j in manifest.jobs] == ["dtm", "ortho", "extras", "validate"]
    assert manifest.jobs[0].params["institution"] == "U"  # from [defaults.dtm]


def test_a_marker_temporary_of_a_killed_batch_is_removed_and_a_live_ones_kept(tmp_path):
    """A batch killed between writing a job marker and renaming it leaves `.ID.json.PID.part`
    beside the markers; the next run removes it when that process is gone."""
    import os
    import subprocess
    import sys

    from pdsgen.batch.resume import marker_path, remove_interrupted_leftovers

    marker = marker_path(tmp_path, "s0_dtm")
    marker.parent.mkdir(parents=True)
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True, check=True)
    stale = marker.parent / f".{marker.name}.{gone.stdout.strip()}.part"
    live = marker.parent / f".{marker.name}.{os.getpid()}.part"
    stale.write_text("{")
    live.write_text("{")
    assert remove_interrupted_leftovers([marker]) == [stale]
    assert not stale.exists() and live.exists()


def test_a_marker_temporary_whose_process_id_was_reused_is_removed(tmp_path):
    """Process ids come round again (32768 of them on many Linux systems): a process that
    started after the temporary was written, under the killed writer's id, did not write it."""
    import os
    import subprocess
    import sys
    import time

    from pdsgen.batch.resume import marker_path, remove_interrupted_leftovers

    marker = marker_path(tmp_path, "s0_ortho")
    marker.parent.mkdir(parents=True)
    newcomer = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        reused = marker.parent / f".{marker.name}.{newcomer.pid}.part"
        reused.write_text("{")
        an_hour_ago = time.time() - 3600
        os.utime(reused, (an_hour_ago, an_hour_ago))  # written long before the newcomer started
        mine = marker.parent / f".{marker.name}.{os.getpid()}.part"
        mine.write_text("{")  # written by this process, after it started: kept
        assert remove_interrupted_leftovers([marker]) == [reused]
        assert not reused.exists() and mine.exists()
    finally:
        newcomer.kill()
        newcomer.wait()
