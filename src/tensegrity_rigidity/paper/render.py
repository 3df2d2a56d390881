"""A report as a list of blocks, rendered to Markdown and to self-contained HTML.

A block is a tuple: ``("h2", title)``, ``("h3", title)``, ``("p", text)``, ``("ul", items)``,
``("table", frame)`` or ``("figure", id, png_path, caption)``. Text may carry the inline
Markdown ``**strong**``, ``*emphasis*`` and ```code```: Markdown keeps it, HTML turns it into
tags, so neither shows raw markup. Paragraphs longer than :data:`MAX_WORDS` are split at
sentence ends. The HTML opens with a table of contents of the ``h2`` blocks and embeds its
figures as base64 PNG (no external reference of any kind).
"""

from __future__ import annotations

import base64
import html
import re
from pathlib import Path

import pandas as pd

from .template import ABBREVIATIONS

#: the longest paragraph the report prints (words); a longer one is split at sentence ends
MAX_WORDS = 120

#: the style of the HTML report
STYLE = (Path(__file__).with_name("templates") / "report.css").read_text()


#: a sentence ends at ".", "!" or "?" only: a semicolon joins clauses of one sentence, so a
#: paragraph is never broken after one (a template's "2D ...; 3D ..." stays whole)
_SENTENCE_END = re.compile(r"(?<=[.!?])\s+(?=[A-Z0-9(*`'\"])")

#: a missing number inside a cell's text ("nan / 0"), printed as :data:`MISSING`
_NAN = re.compile(r"(?<![\w/])nan(?![\w/])", re.I)
#: how a table prints a missing number
MISSING = "-"


def split_paragraph(text: str, max_words: int = MAX_WORDS) -> list[str]:
    """``text`` as paragraphs of at most ``max_words`` words, broken at sentence ends (a single
    sentence longer than that stays whole; never after an abbreviation such as "Fig.")."""
    pieces: list[str] = []
    for piece in _SENTENCE_END.split(text.strip()):
        if pieces and pieces[-1].rsplit(None, 1)[-1] in ABBREVIATIONS:  # "Fig. 2B" is one
            pieces[-1] += " " + piece
        else:
            pieces.append(piece)
    out, current = [], ""
    for sentence in pieces:
        joined = f"{current} {sentence}".strip()
        if current and len(joined.split()) > max_words:
            out.append(current)
            current = sentence
        else:
            current = joined
    return [*out, current] if current else out


def inline_html(text: str) -> str:
    """``text`` escaped for HTML, its inline Markdown turned into ``strong``, ``em``, ``code``."""
    s = html.escape(str(text), quote=False)
    s = re.sub(r"`([^`]+)`", r"<code>\1</code>", s)
    s = re.sub(r"\*\*([^*]+)\*\*", r"<strong>\1</strong>", s)
    return re.sub(r"(?<![\w*])\*([^*\s][^*]*)\*(?![\w*])", r"<em>\1</em>", s)


def anchor(title: str) -> str:
    """The id of a heading: its words in lower case joined by hyphens."""
    return re.sub(r"[^a-z0-9]+", "-", title.lower()).strip("-")


def cell(value) -> str:
    """A table cell as text: a missing number (None, NaN, NA, or "nan" within a formatted cell
    such as "nan / 0") printed as :data:`MISSING`."""
    if value is None or (pd.api.types.is_scalar(value) and pd.isna(value)):
        return MISSING
    return _NAN.sub(MISSING, str(value))


def md_table(df: pd.DataFrame) -> str:
    """A frame as a Markdown table (``|`` in cells written as ``/``, a missing number as
    :data:`MISSING`)."""
    cols = list(df.columns)
    lines = ["| " + " | ".join(map(str, cols)) + " |", "|" + "---|" * len(cols)]
    for _, row in df.iterrows():
        lines.append("| " + " | ".join(cell(row[c]).replace("|", "/") for c in cols) + " |")
    return "\n".join(lines)


def html_table(df: pd.DataFrame) -> str:
    """A frame as an HTML table; a ``verdict`` column marks its rows and cells for the style."""
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in df.columns)
    body = []
    for _, row in df.iterrows():
        cls = f' class="{html.escape(str(row["verdict"]))}"' if "verdict" in df else ""
        cells = "".join(
            f'<td class="{html.escape(str(c))}">{inline_html(cell(row[c]))}</td>'
            for c in df.columns
        )
        body.append(f"<tr{cls}>{cells}</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def to_markdown(title: str, blocks: list[tuple]) -> str:
    """The report in Markdown, with a list of its sections after the title."""
    heads = [b[1] for b in blocks if b[0] == "h2"]
    out = [f"# {title}", ""]
    if heads:
        out += ["Contents: " + " · ".join(f"[{h}](#{anchor(h)})" for h in heads), ""]
    for b in blocks:
        kind = b[0]
        if kind in ("h2", "h3"):
            out += [("## " if kind == "h2" else "### ") + b[1], ""]
        elif kind == "p":
            for para in split_paragraph(b[1]):
                out += [para, ""]
        elif kind == "ul":
            out += [f"- {item}" for item in b[1]] + [""]
        elif kind == "table":
            out += [md_table(b[1]), ""]
        elif kind == "figure":
            _, fid, path, caption = b
            out += [f"![Figure {fid}](figures/{Path(path).name})", "", f"**{fid}.** {caption}", ""]
    return "\n".join(out).rstrip() + "\n"


def to_html(title: str, blocks: list[tuple]) -> str:
    """The report as one self-contained HTML page with a table of contents."""
    heads = [b[1] for b in blocks if b[0] == "h2"]
    toc = "".join(f'<li><a href="#{anchor(h)}">{html.escape(h)}</a></li>' for h in heads)
    body = []
    for b in blocks:
        kind = b[0]
        if kind == "h2":
            body.append(f'<h2 id="{anchor(b[1])}">{inline_html(b[1])}</h2>')
        elif kind == "h3":
            body.append(f"<h3>{inline_html(b[1])}</h3>")
        elif kind == "p":
            body += [f"<p>{inline_html(p)}</p>" for p in split_paragraph(b[1])]
        elif kind == "ul":
            body.append("<ul>" + "".join(f"<li>{inline_html(i)}</li>" for i in b[1]) + "</ul>")
        elif kind == "table":
            body.append(html_table(b[1]))
        elif kind == "figure":
            _, fid, path, caption = b
            data = base64.b64encode(Path(path).read_bytes()).decode()
            body.append(
                f'<figure id="fig{html.escape(fid)}"><img alt="Figure {html.escape(fid)}" '
                f'src="data:image/png;base64,{data}"><figcaption><b>{html.escape(fid)}</b> '
                f"{inline_html(caption)}</figcaption></figure>"
            )
    return (
        f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
        f"<style>{STYLE}</style></head><body><h1>{html.escape(title)}</h1>"
        f'<nav id="contents"><b>Contents</b><ol>{toc}</ol></nav>' + "".join(body) + "</body></html>"
    )
