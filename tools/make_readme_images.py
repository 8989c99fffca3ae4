"""Regenerate docs/images/: small example Extras pictures for README.md, from the demo.

Runs the demo into a temporary directory, makes the Extras of its DTM and of its
orthoimage (the demo's .JP2 product, or one written here with pdsgen.write_ortho from the
demo's orthoimage input when the demo makes none), and stores the colour-coded and
the orthoimage annotated browses and a strip of the four thumbnails, each under
150 KB. The README shows each picture at its own size, one per row: the annotation
text is sized for that (about 13 px), so it stays legible.

Run from the repository root: PYTHONPATH=src python tools/make_readme_images.py
"""

from __future__ import annotations

import io
import tempfile
from pathlib import Path

from PIL import Image

from pdsgen import write_ortho
from pdsgen.demo import run_demo
from pdsgen.extras import make_extras

OUT = Path(__file__).resolve().parents[1] / "docs" / "images"
MAX_BYTES = 150 * 1024
BROWSE_WIDTH = 520  # annotation text scales with the browse width: legible at this size


def save_small(image: Image.Image, path: Path) -> None:
    """Save as JPEG at the highest quality that stays under MAX_BYTES."""
    for quality in range(90, 40, -5):
        buffer = io.BytesIO()
        image.save(buffer, format="JPEG", quality=quality, subsampling=0 if quality >= 80 else 2)
        if buffer.tell() <= MAX_BYTES:
            path.write_bytes(buffer.getvalue())
            print(f"{path.name}: {image.width} x {image.height}, {buffer.tell() // 1024} KB")
            return
    raise SystemExit(f"{path.name}: cannot get under {MAX_BYTES} bytes")


def thumbnail_strip(paths: list[Path]) -> Image.Image:
    thumbs = [Image.open(p).convert("RGB") for p in paths]
    gap = 8
    strip = Image.new("RGB", (sum(t.width for t in thumbs) + gap * (len(thumbs) + 1),
                              max(t.height for t in thumbs) + 2 * gap), (255, 255, 255))
    x = gap
    for t in thumbs:
        strip.paste(t, (x, gap))
        x += t.width + gap
    return strip


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="pdsgen-readme-images-") as tmp:
        demo = run_demo(Path(tmp) / "demo")
        dtm = next(p for p in demo.products if p.suffix.upper() == ".IMG")
        labels = [p for p in demo.products if p.suffix.upper() in (".LBL", ".JP2")]
        if labels:
            ortho = labels[0]
        else:
            source = next(p for p in demo.inputs if "ortho" in p.name)
            ortho = write_ortho(source, Path(tmp) / "ortho").label_path
        extras = Path(tmp) / "extras"
        made = make_extras([dtm], extras, browse_width=BROWSE_WIDTH)
        made += make_extras([ortho], extras / "ortho", browse_width=BROWSE_WIDTH)
        by_suffix = {p.name.split(".", 1)[1]: p for p in made}
        for code, name in (("ca.jpg", "extras_colour_annotated.jpg"),
                           ("abrowse.jpg", "extras_ortho_annotated.jpg")):
            save_small(Image.open(by_suffix[code]).convert("RGB"), OUT / name)
        strip = thumbnail_strip([by_suffix[c] for c in ("th.jpg", "st.jpg", "ct.jpg",
                                                         "thumb.jpg")])
        save_small(strip, OUT / "extras_thumbnails.jpg")


if __name__ == "__main__":
    main()
