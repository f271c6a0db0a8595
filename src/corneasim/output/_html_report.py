"""One self-contained HTML page of sections, tables and figures (a run's or a study's report).

The page needs nothing but itself: the style sheet is inline and every figure is a PNG
embedded as a base64 ``data:`` URI, so the file can be mailed, archived with the results
or opened offline, and it shows the same everywhere. A report is a title and a list of
:class:`Section` objects, each a heading and a list of blocks (:class:`Paragraph`,
:class:`Table`, :class:`Image`); :func:`render_page` turns them into HTML and
:func:`write_page` writes it atomically. All text is escaped.
"""

from __future__ import annotations

import base64
import html
from dataclasses import dataclass, field
from pathlib import Path

from corneasim.output._files import atomic_write_text

STYLE = """
body { font-family: system-ui, -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; margin: 2em auto;
       max-width: 1100px; padding: 0 1em; color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 1.6em; }
p.subtitle { color: #555; margin-top: 0; }
table { border-collapse: collapse; margin: 0.6em 1.5em 0.6em 0; font-size: 0.92em; display: inline-table;
        vertical-align: top; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #f2f2f2; }
td.number { text-align: right; font-variant-numeric: tabular-nums; }
td.met { background: #e3f4e1; }
td.missed { background: #fbe1df; }
figure { display: inline-block; margin: 0.5em 1em 0.5em 0; vertical-align: top; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.88em; color: #444; max-width: 640px; }
caption { caption-side: bottom; font-size: 0.88em; color: #444; text-align: left; padding-top: 0.3em; }
"""


@dataclass(frozen=True)
class Paragraph:
    """A paragraph of plain text."""

    text: str


@dataclass(frozen=True)
class Mark:
    """A table cell that meets (``met=True``) or misses its target, coloured accordingly."""

    text: str
    met: bool


@dataclass(frozen=True)
class Table:
    """A table: column headings and rows of cells (str, number, :class:`Mark` or None)."""

    header: list
    rows: list
    caption: str = ""


@dataclass(frozen=True)
class Image:
    """A PNG figure, embedded in the page; ``width`` (CSS pixels) scales it, e.g. to set two in a row."""

    png: bytes
    caption: str = ""
    width: int | None = None

    @classmethod
    def from_file(cls, path: str | Path, caption: str = "", width: int | None = None) -> Image:
        """The PNG file ``path`` as an image block."""
        return cls(Path(path).read_bytes(), caption, width)


@dataclass(frozen=True)
class Section:
    """A heading and its blocks, in order."""

    heading: str
    blocks: list = field(default_factory=list)


def data_uri(png: bytes) -> str:
    """``data:image/png;base64,...`` of PNG bytes."""
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _cell(value) -> str:
    if isinstance(value, Mark):
        return f'<td class="{"met" if value.met else "missed"}">{html.escape(value.text)}</td>'
    if value is None:
        return "<td>–</td>"
    if isinstance(value, bool):
        return f"<td>{'yes' if value else 'no'}</td>"
    if isinstance(value, (int, float)):
        return f'<td class="number">{value:.4g}</td>'
    return f"<td>{html.escape(str(value))}</td>"


def _block(block) -> str:
    if isinstance(block, Paragraph):
        return f"<p>{html.escape(block.text)}</p>"
    if isinstance(block, Table):
        head = "".join(f"<th>{html.escape(str(h))}</th>" for h in block.header)
        body = "\n".join("<tr>" + "".join(_cell(c) for c in row) + "</tr>" for row in block.rows)
        caption = f"<caption>{html.escape(block.caption)}</caption>" if block.caption else ""
        return f"<table>{caption}\n<thead><tr>{head}</tr></thead>\n<tbody>\n{body}\n</tbody></table>"
    if isinstance(block, Image):
        caption = f"<figcaption>{html.escape(block.caption)}</figcaption>" if block.caption else ""
        alt = html.escape(block.caption or "figure", quote=True)
        width = f' style="width: {int(block.width)}px"' if block.width else ""
        return f'<figure{width}><img alt="{alt}" src="{data_uri(block.png)}">{caption}</figure>'
    raise TypeError(f"not a report block: {block!r}")


def render_page(title: str, sections, subtitle: str = "") -> str:
    """The HTML text of a page: ``title``, an optional ``subtitle`` line, then the sections."""
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en">',
        "<head>",
        '<meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{html.escape(title)}</title>",
        f"<style>{STYLE}</style>",
        "</head>",
        "<body>",
        f"<h1>{html.escape(title)}</h1>",
    ]
    if subtitle:
        parts.append(f'<p class="subtitle">{html.escape(subtitle)}</p>')
    for section in sections:
        parts.append(f"<section>\n<h2>{html.escape(section.heading)}</h2>")
        parts.extend(_block(block) for block in section.blocks)
        parts.append("</section>")
    parts += ["</body>", "</html>", ""]
    return "\n".join(parts)


def write_page(path: str | Path, title: str, sections, subtitle: str = "") -> Path:
    """Write :func:`render_page` to ``path`` atomically; returns the path."""
    path = Path(path)
    atomic_write_text(path, render_page(title, sections, subtitle))
    return path
