"""The review page: one self-contained HTML file, from templates/review/.

Offline by construction: the style and the script are inlined, and the page's
Content-Security-Policy (a meta element) allows exactly those two by their SHA-256
hashes and images from the page's own origin (the previews, linked relatively), and
nothing else - no request to the network can be made from it. The page is complete
without the script (the filters are hidden until it runs), and prints without the
controls. Long lists stay quick: each product's entry is laid out only when scrolled
near (CSS content-visibility), thumbnails load lazily and the larger previews only
when opened.
"""

from __future__ import annotations

import base64
import hashlib
import html
import os
from collections import Counter
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import IO

import jinja2
from markupsafe import Markup

from .. import __version__, clock
from ..archive.layout import VOLDESC
from ..encode import html_finalize, shown, shown_lines
from ..errors import PdsgenError
from ..label.read import LabelCache
from ..resources import templates_dir
from ..validate.model import SEVERITIES, Finding
from ..validate.report import FileReport, Tally, Writer
from .collect import Review, review_reports
from .mapview import build_views

PAGE_TEMPLATE = "page.html.j2"


@cache
def _environment() -> jinja2.Environment:
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(templates_dir() / "review")),
                             autoescape=True, trim_blocks=True, lstrip_blocks=True,
                             undefined=jinja2.StrictUndefined, finalize=html_finalize)
    env.filters["size"] = human_size
    env.filters["text"] = text_content
    env.filters["told"] = finding_text
    return env


def finding_text(finding: Finding) -> Markup:
    """A finding's message as the page shows it: after its keyword (in code), unless the message
    already starts with that keyword ("KEY = 1: ..." is not shown as "KEY: KEY = 1: ...")."""
    message = text_content(finding.message)
    keyword = finding.keyword
    if not keyword or finding.message.startswith(keyword):
        return message
    return Markup("<code>{}</code>: {}").format(shown(keyword), message)


def text_content(value: str) -> Markup:
    """Text for an element's content: <, > and & escaped; quotes need not be (index rows are full
    of them, and a page of 10,000 rows is smaller without &#34;)."""
    return Markup(html.escape(shown_lines(value), quote=False))


def human_size(size: int) -> str:
    if size < 0:
        return "missing"
    value = float(size)
    for unit in ("B", "KiB", "MiB", "GiB"):
        if value < 1024 or unit == "GiB":
            return f"{value:.0f} {unit}" if unit == "B" else f"{value:.1f} {unit}"
        value /= 1024
    return f"{value:.1f} TiB"


def _hash(text: str) -> str:
    return "'sha256-" + base64.b64encode(hashlib.sha256(text.encode("utf-8")).digest()).decode("ascii") + "'"


def content_security_policy(style: str, script: str) -> str:
    """Nothing but the page's own style and script, and images from its own origin."""
    return (f"default-src 'none'; img-src 'self'; style-src {_hash(style)}; script-src {_hash(script)}; "
            "base-uri 'none'; form-action 'none'")


# Thumbnails of each page's first products are in the HTML itself; further ones are built by the
# script as their entries come near the screen (without scripts: their names, and links to the images).
INLINE_THUMBNAILS = 200
# Products per page: a delivery of more is reviewed in pages (the first holds the summary, the map
# of every footprint and the first products; REVIEW-2.html ... the next ones), each opening in
# seconds and complete without scripts. Measured (bench/review.py): about 3.4 KB of HTML per product
# entry, and Chromium's time to open grows with the HTML.
PRODUCTS_PER_PAGE = 500


def page_names(first: str, count: int) -> list[str]:
    """The file names of `count` pages: `first` (REVIEW.html), then REVIEW-2.html ..."""
    stem, dot, suffix = first.rpartition(".")
    if not dot:
        stem, suffix = first, ""
    return [first] + [f"{stem}-{number}{dot}{suffix}" for number in range(2, count + 1)]


@dataclass
class PageRef:
    number: int
    name: str
    first: str  # the first and last product ids on it
    last: str
    counts: dict[str, int]  # its findings by severity


def render_pages(review: Review, first_name: str = "REVIEW.html", inline_thumbnails: int = INLINE_THUMBNAILS,
                 per_page: int | None = PRODUCTS_PER_PAGE) -> list[tuple[str, str]]:
    """The review as (file name, HTML) pages of at most `per_page` products each (None: one page).
    The first page holds the summary, the map (each footprint linked to its entry on whichever
    page holds it) and the other files' findings; every page links every other."""
    products = review.products
    size = max(1, per_page or len(products) or 1)
    chunks = [products[start:start + size] for start in range(0, len(products), size)] or [[]]
    names = page_names(first_name, len(chunks))
    refs = []
    for number, (name, chunk) in enumerate(zip(names, chunks, strict=True), 1):
        for position, product in enumerate(chunk):
            product.inline = position < inline_thumbnails
            product.page = "" if number == 1 else name
        found = Counter(f.severity for p in chunk for f in p.findings)
        refs.append(PageRef(number, name, chunk[0].product_id if chunk else "", chunk[-1].product_id if chunk else "",
                            {s: found.get(s, 0) for s in SEVERITIES}))
    env = _environment()
    style = (templates_dir() / "review" / "review.css").read_text(encoding="utf-8")
    script = (templates_dir() / "review" / "review.js").read_text(encoding="utf-8")
    outlines = [(p.product_id, p.link, p.target or "UNKNOWN BODY", p.outline, p.kind)
                for p in products if p.outline is not None]
    common = dict(review=review, counts=review.counts(), severities=SEVERITIES, style=style, script=script,
                  csp=content_security_policy(style, script), version=__version__, pages=refs,
                  made=clock.timestamp())
    template = env.get_template(PAGE_TEMPLATE)
    pages = []
    for ref, chunk in zip(refs, chunks, strict=True):
        first = ref.number == 1
        pages.append((ref.name, template.render(
            **common, page=ref, products=chunk, views=build_views(outlines) if first else [],
            without_outline=[p for p in products if p.outline is None] if first else [])))
    return pages


def delivery_title(root: Path, shown: str, labels: LabelCache | None = None) -> str:
    """What the page is titled by: a PDS3 volume's VOLUME_ID and VOLUME_NAME (VOLDESC.CAT), else a
    PDS4 bundle's title (its bundle label), else the directory as the user named it - the
    delivery's own name rather than the directory's twice ("Review: delivery (delivery)")."""
    voldesc = root / VOLDESC
    if voldesc.is_file():
        try:
            label = (labels or LabelCache()).open_pds3(voldesc)
        except PdsgenError:
            label = None
        volume_id = label.first("VOLUME_ID") if label is not None else None
        if volume_id:
            name = label.first("VOLUME_NAME") if label is not None else None
            return f"{volume_id}: {name}" if name and "TO BE WRITTEN" not in name else volume_id
    for bundle in sorted(root.glob("bundle*.xml")):
        title = _bundle_title(bundle)
        if title:
            return title
    return Path(shown).name or shown


def _bundle_title(bundle: Path) -> str | None:
    """The title of a PDS4 bundle label (Identification_Area/title); None when it has none or
    cannot be read (the checks report such a label)."""
    from lxml import etree

    try:
        tree = etree.parse(str(bundle), etree.XMLParser(no_network=True, resolve_entities=False))
    except (OSError, etree.XMLSyntaxError):
        return None
    found = tree.find("{*}Identification_Area/{*}title")
    text = " ".join((found.text or "").split()) if found is not None else ""
    return text if text and "TO BE WRITTEN" not in text else None


def render_page(review: Review, inline_thumbnails: int = INLINE_THUMBNAILS) -> str:
    """The review as one page, however many products (`pdsgen validate --format html` writes a
    stream)."""
    return render_pages(review, inline_thumbnails=inline_thumbnails, per_page=None)[0][1]


def page_directory(out: IO[str]) -> Path:
    """Where a page written to `out` lies (its links are relative to it): the file's directory,
    or the working directory for standard output."""
    name = getattr(out, "name", None)
    if isinstance(name, str) and os.path.isfile(name):
        return Path(name).resolve().parent
    return Path.cwd()


class HtmlWriter(Writer):
    """`pdsgen validate --format html`: the review page of the labels checked (each label with a
    PRODUCT_ID a product), written when the run ends."""

    def start(self) -> None:
        self.reports: list[FileReport] = []

    def file(self, report: FileReport, failed: bool) -> None:
        self.reports.append(report)

    def finish(self, tally: Tally) -> None:
        review = review_reports(self.reports, page_directory(self.out), "labels checked by pdsgen validate")
        review.files = tally.files
        review.verdict = tally.summary_line()
        self.out.write(render_page(review))
