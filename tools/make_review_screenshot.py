"""Regenerate docs/images/review_page.png: the review page of the demo delivery, as headless
Chromium shows it, for README.md.

Runs the demo into a temporary directory, makes it a PDS3 volume with `pdsgen deliver`, writes
its page as `pdsgen review` does (the data checked too), loads that page from its file URL in
headless Chromium and keeps the first screenful, reduced to a size the README shows whole
(under 300 KB).

Run from the repository root: PYTHONPATH=src python tools/make_review_screenshot.py
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

from PIL import Image

from pdsgen.deliver import make_delivery
from pdsgen.demo import run_demo
from pdsgen.review import write_review

OUT = Path(__file__).resolve().parents[1] / "docs" / "images" / "review_page.png"
WINDOW = (1200, 1500)
WIDTH = 900
MAX_BYTES = 300 * 1024


def screenshot(page: Path, png: Path, work: Path) -> None:
    binary = shutil.which("chromium") or shutil.which("chromium-browser")
    if binary is None:
        raise SystemExit("headless Chromium is needed (Debian: apt-get install chromium)")
    subprocess.run([binary, "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={work / 'profile'}",
                    "--no-first-run", "--disable-background-networking", "--hide-scrollbars",
                    f"--window-size={WINDOW[0]},{WINDOW[1]}", "--virtual-time-budget=5000", f"--screenshot={png}",
                    page.resolve().as_uri()], check=True, capture_output=True, timeout=120)


def main() -> None:
    with tempfile.TemporaryDirectory(prefix="pdsgen-review-shot-") as tmp:
        work = Path(tmp)
        run_demo(work / "demo")
        delivery = make_delivery(work / "demo", work / "DEMO_0001", dialect="pds3", volume_id="DEMO_0001")
        page = write_review(delivery.path).path
        raw = work / "raw.png"
        screenshot(page, raw, work)
        image = Image.open(raw).convert("RGB")
        image = image.resize((WIDTH, round(image.height * WIDTH / image.width)), Image.LANCZOS)
        image = image.quantize(colors=128, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
        OUT.parent.mkdir(parents=True, exist_ok=True)
        image.save(OUT, optimize=True)
        size = OUT.stat().st_size
        print(f"{OUT.name}: {image.width} x {image.height}, {size // 1024} KB")
        if size > MAX_BYTES:
            raise SystemExit(f"{OUT.name}: over {MAX_BYTES // 1024} KB")


if __name__ == "__main__":
    main()
