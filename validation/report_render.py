"""Render a results folder's ``report.html`` in headless Chromium and check what a reader would see.

Checks, each printed with its figure:

1. every ``<img>`` of the page has a ``data:image/png;base64`` URI that decodes to a PNG
   matplotlib can read (no broken image, no external asset); no ``src`` or ``href`` of the
   page points outside it;
2. the screenshot Chromium takes of the page is not blank: the share of pixels that are
   not the page's white background, and the standard deviation of the grey levels, are
   above small floors (:data:`MIN_INK`, :data:`MIN_STD`);
3. Chromium's own DOM (``--dump-dom``) holds as many images as the HTML, each decoded by
   the browser (``naturalWidth > 0`` is not visible in a dump, so the dumped ``src`` is
   decoded again).

Chromium is Debian's ``chromium`` package (``apt-get install chromium``); ``--chromium``
names another binary. The page is written first if the folder has none.

Usage::

    python validation/report_render.py RESULTS_DIR [--out report.png] [--width 1200] [--height 3000]

Exit status 0 when every check passes, 1 when one fails, 2 for a bad RESULTS_DIR.
"""

from __future__ import annotations

import argparse
import base64
import io
import shutil
import subprocess
import sys
import tempfile
from html.parser import HTMLParser
from pathlib import Path

import numpy as np

MIN_INK = 0.02
"""Smallest share of non-background pixels of a page that is not blank."""

MIN_STD = 5.0
"""Smallest standard deviation of the screenshot's grey levels (0-255) of a page that is not blank."""

CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync")


class _Assets(HTMLParser):
    """The ``src`` of every ``<img>`` and every other ``src``/``href`` of a page."""

    def __init__(self):
        super().__init__()
        self.images: list[str] = []
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        attributes = dict(attrs)
        if tag == "img":
            self.images.append(attributes.get("src") or "")
        else:
            self.links += [attributes[key] for key in ("src", "href") if attributes.get(key)]


def decode_images(text: str) -> tuple[list[tuple[int, int]], list[str]]:
    """Decode every ``<img>`` of the HTML ``text``: the (width, height) of the good ones and the problems."""
    import matplotlib.image

    parser = _Assets()
    parser.feed(text)
    sizes, problems = [], []
    prefix = "data:image/png;base64,"
    for k, source in enumerate(parser.images):
        if not source.startswith(prefix):
            problems.append(f"image {k}: not an embedded PNG ({source[:40]!r})")
            continue
        try:
            pixels = matplotlib.image.imread(io.BytesIO(base64.b64decode(source[len(prefix):], validate=True)),
                                             format="png")
        except (ValueError, OSError, SyntaxError) as error:
            problems.append(f"image {k}: does not decode ({error})")
            continue
        sizes.append((pixels.shape[1], pixels.shape[0]))
    problems += [f"external asset: {link[:60]}" for link in parser.links if not link.startswith(("data:", "#"))]
    return sizes, problems


def blankness(png: Path) -> tuple[float, float]:
    """(share of pixels differing from the most common colour, std of the grey levels 0-255) of a PNG."""
    import matplotlib.image

    pixels = matplotlib.image.imread(png)[..., :3]
    grey = 255.0 * pixels.mean(axis=2)
    values, counts = np.unique(np.round(grey).astype(int), return_counts=True)
    background = values[np.argmax(counts)]
    return float(np.mean(np.abs(grey - background) > 8.0)), float(grey.std())


def chromium(binary: str, *arguments: str) -> subprocess.CompletedProcess:
    """Run headless Chromium with a fresh profile folder."""
    with tempfile.TemporaryDirectory() as profile:
        return subprocess.run([binary, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", *arguments],
                              capture_output=True, text=True, timeout=180)


def main(argv=None) -> int:
    """Render, check, print; 0 when all checks pass."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results_dir", type=Path)
    parser.add_argument("--out", type=Path, help="screenshot PNG (default RESULTS_DIR/report.png)")
    parser.add_argument("--width", type=int, default=1200)
    parser.add_argument("--height", type=int, default=3000)
    parser.add_argument("--chromium", default="chromium", help="Chromium binary")
    arguments = parser.parse_args(argv)

    from corneasim.errors import InputError
    from corneasim.output import REPORT, write_run_report

    page = arguments.results_dir / REPORT
    try:
        if not page.is_file():
            write_run_report(arguments.results_dir)
    except InputError as error:
        print(f"report_render: {error}", file=sys.stderr)
        return 2
    binary = shutil.which(arguments.chromium)
    if binary is None:
        print(f"report_render: {arguments.chromium} not found (apt-get install chromium)", file=sys.stderr)
        return 2
    text = page.read_text()
    sizes, problems = decode_images(text)
    print(f"images: {len(sizes)} decoded, {len(problems)} problems")
    for problem in problems:
        print(f"  {problem}")

    out = arguments.out or arguments.results_dir / "report.png"
    url = page.resolve().as_uri()
    shot = chromium(binary, f"--screenshot={out.resolve()}", f"--window-size={arguments.width},{arguments.height}",
                    "--hide-scrollbars", url)
    if not out.is_file():
        print(f"screenshot: Chromium wrote none (exit {shot.returncode}): {shot.stderr.strip()[-300:]}")
        return 1
    ink, std = blankness(out)
    blank = ink < MIN_INK or std < MIN_STD
    print(f"screenshot: {out} ({arguments.width} x {arguments.height}), non-background pixels {100 * ink:.1f}% "
          f"(floor {100 * MIN_INK:g}%), grey std {std:.1f} (floor {MIN_STD:g}): {'BLANK' if blank else 'not blank'}")

    dom = chromium(binary, "--dump-dom", url)
    dom_sizes, dom_problems = decode_images(dom.stdout)
    dom_ok = len(dom_sizes) == len(sizes) and not dom_problems
    print(f"Chromium DOM: {len(dom_sizes)} images decoded of {len(sizes)}, {len(dom_problems)} problems")
    return 0 if not problems and not blank and dom_ok and sizes else 1


if __name__ == "__main__":
    raise SystemExit(main())
