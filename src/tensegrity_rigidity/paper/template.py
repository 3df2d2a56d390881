"""Words in Markdown templates, numbers from the studies: the template machinery.

A template (``templates/<name>.md``) is Markdown cut into blocks by comment lines
``<!-- kind [name] [: title] -->``. The kinds a report renders, in the template's order:
``section`` and ``subsection`` (a heading), ``text`` (paragraphs), ``figure ID`` (a figure's
caption, placed where the block stands), ``table NAME`` (a table the study provides, after the
block's paragraphs) and ``claims`` (the comparison's rows of the study's claims). A study's
``opening [name]`` block says in a clause what it measures: the report's opening quotes it
where the report compares none of the paper's claims (only where the study's number ``name``
is present). A ``labels`` block holds short texts, one ``- key: text`` line each (axis labels,
legends, column headers, the labels of measurements), which the code asks for by key.

Placeholders are named, ``{name}`` or ``{name:.3f}``: the code passes numbers (a sequence is
written as its items joined by commas) and the template words them. A sentence with a
placeholder whose value is missing (absent, None or NaN) is dropped, and so is an optional
fragment ``[[...]]``; a paragraph left empty is dropped, and a block of which nothing is left.
Sentences end at ``.``, ``!`` or ``?`` before a capital, a placeholder or a fragment (not
after the abbreviations of :data:`ABBREVIATIONS`). Braces meant literally are doubled.
"""

from __future__ import annotations

import functools
import math
import re
import string
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: where the templates are
TEMPLATES = Path(__file__).with_name("templates")
#: words ending in a full stop that do not end a sentence
ABBREVIATIONS = ("Fig.", "Figs.", "e.g.", "i.e.", "al.", "vs.", "cf.", "Eq.", "Ref.")

_HEAD = re.compile(r"^<!--\s*(\w+)(?:\s+([^\s:]+))?(?:\s*:\s*(.*?))?\s*-->\s*$")
_FRAGMENT = re.compile(r"\[\[(.*?)\]\]", re.S)
_FORMATTER = string.Formatter()


class MissingValue(KeyError):
    """A placeholder without a value (absent, None or NaN)."""


@dataclass(frozen=True)
class Block:
    """One block of a template: its kind, name, title and text (Markdown)."""

    kind: str
    name: str
    title: str
    text: str


@dataclass(frozen=True)
class Template:
    """A parsed template: its blocks in order and its labels."""

    name: str
    blocks: tuple[Block, ...]
    labels: Mapping[str, str]

    def label(self, key: str, **values) -> str:
        """The label ``key`` filled: its fragments ``[[...]]`` optional (dropped for a value of
        None), its other placeholders required (NaN is written as such)."""
        if key not in self.labels:
            raise KeyError(f"template {self.name}: no label {key!r}")
        try:
            return _sentence(self.labels[key], values, strict=True)
        except MissingValue as exc:
            raise KeyError(f"template {self.name}: label {key!r} needs {exc}") from None

    def column(self, key: str) -> str:
        """The header of a table column: the label ``col.<key>``, else the key itself."""
        return self.labels.get(f"col.{key}", key)

    def of(self, kind: str, name: str = "") -> Block | None:
        """The first block of a kind (and name), or None."""
        return next((b for b in self.blocks if b.kind == kind and b.name == name), None)


def parse(text: str, name: str = "") -> Template:
    """A template from its text (see the module docstring)."""
    blocks: list[Block] = []
    labels: dict[str, str] = {}
    head = None
    lines: list[str] = []

    def close():
        if head is None:
            return
        body = "\n".join(lines).strip()
        if head[0] == "labels":
            for line in body.splitlines():
                key, _, value = line.lstrip("- ").partition(": ")
                if key.strip():
                    labels[key.strip()] = value.strip()
        else:
            blocks.append(Block(head[0], head[1] or "", head[2] or "", body))

    for line in text.splitlines():
        m = _HEAD.match(line)
        if m:
            close()
            head, lines = m.groups(), []
        elif head is not None:
            lines.append(line)
    close()
    return Template(name, tuple(blocks), labels)


@functools.cache
def load(name: str) -> Template:
    """The template ``templates/<name>.md``."""
    return parse((TEMPLATES / f"{name}.md").read_text(), name)


def _missing(value, nan: bool) -> bool:
    if value is None:
        return True
    return nan and isinstance(value, float | np.floating) and math.isnan(value)


def _value(field: str, values: Mapping, nan: bool = True):
    try:
        value, _ = _FORMATTER.get_field(field, (), values)
    except (KeyError, AttributeError, IndexError, TypeError) as exc:
        raise MissingValue(field) from exc
    if _missing(value, nan):
        raise MissingValue(field)
    return value


def _one(value, spec: str) -> str:
    if isinstance(value, np.generic):
        value = value.item()
    return format(value, spec)


def _format(text: str, values: Mapping, nan: bool = True) -> str:
    """``text`` with its placeholders filled; :class:`MissingValue` for one without a value
    (None, absent, or with ``nan`` NaN)."""
    out = []
    for literal, field, spec, conversion in _FORMATTER.parse(text):
        out.append(literal)
        if field is None:
            continue
        value = _value(field, values, nan)
        if conversion:
            value = _FORMATTER.convert_field(value, conversion)
        if isinstance(value, Sequence | np.ndarray) and not isinstance(value, str):
            out.append(", ".join(_one(v, spec or "") for v in value))
        else:
            out.append(_one(value, spec or ""))
    return "".join(out)


def sentences(paragraph: str) -> list[str]:
    """A paragraph of a template cut into sentences (fragments and placeholders kept whole)."""
    out, start, depth = [], 0, 0
    for i, ch in enumerate(paragraph):
        depth += ch in "[{"
        depth -= ch in "]}"
        if depth or ch not in ".!?" or i + 2 > len(paragraph) or not paragraph[i + 1].isspace():
            continue
        rest = paragraph[i + 1 :].lstrip()
        word = paragraph[: i + 1].rsplit(None, 1)[-1]
        if rest and (rest[0].isupper() or rest[0] in "{[") and word not in ABBREVIATIONS:
            out.append(paragraph[start : i + 1].strip())
            start = i + 1
    out.append(paragraph[start:].strip())
    return [s for s in out if s]


def _sentence(text: str, values: Mapping, strict: bool = False) -> str:
    """One sentence filled, its fragments without a value dropped ("" if the sentence is, or
    with ``strict`` :class:`MissingValue`)."""
    parts, last, nan = [], 0, not strict
    try:
        for m in _FRAGMENT.finditer(text):
            parts.append(_format(text[last : m.start()], values, nan))
            try:
                parts.append(_format(m.group(1), values, nan))
            except MissingValue:
                parts.append("\0")  # where a fragment was dropped
            last = m.end()
        parts.append(_format(text[last:], values, nan))
    except MissingValue:
        if strict:
            raise
        return ""
    # no space left before the punctuation that followed a dropped fragment
    out = re.sub(r"\s*\0\s*(?=[.,;:)])", "", "".join(parts)).replace("\0", "")
    return re.sub(r"  +", " ", out).strip()


def fill(text: str, values: Mapping) -> list[str]:
    """The paragraphs of ``text`` with their placeholders filled: a sentence or fragment whose
    value is missing dropped, a paragraph left empty dropped."""
    out = []
    for paragraph in re.split(r"\n\s*\n", text.strip()):
        joined = " ".join(line.strip() for line in paragraph.splitlines())
        kept = [s for s in (_sentence(t, values) for t in sentences(joined)) if s]
        if kept:
            out.append(" ".join(kept))
    return out
