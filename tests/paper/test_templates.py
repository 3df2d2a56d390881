"""The template machinery, and every template rendered once with a tiny run's numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tensegrity_rigidity.paper.registry import STUDIES
from tensegrity_rigidity.paper.report import render
from tensegrity_rigidity.paper.template import TEMPLATES, fill, load, parse, sentences

KINDS = {"section", "subsection", "text", "figure", "table", "claims", "studies", "opening"}


def test_a_sentence_whose_number_is_missing_is_dropped():
    text = "A is {a:.2f}. B is {b}. See Fig. 1C, then {c}.\n\nOnly {b}."
    assert fill(text, {"a": 1.234, "b": None, "c": "C"}) == ["A is 1.23. See Fig. 1C, then C."]
    assert fill(text, {"a": math.nan, "c": "C", "b": 2}) == [
        "B is 2. See Fig. 1C, then C.",
        "Only 2.",
    ]


def test_a_fragment_without_its_number_is_dropped_and_sequences_are_listed():
    text = "n = {n}[[ (widths {w:.3f})]] [[and {x}]]."
    assert fill(text, {"n": (8, 16), "w": np.array([0.1, 0.25])}) == [
        "n = 8, 16 (widths 0.100, 0.250)."
    ]
    assert fill(text, {"n": [8], "x": "y"}) == ["n = 8 and y."]


def test_sentences_end_before_a_capital_a_placeholder_or_a_fragment():
    assert sentences("One, i.e. Two. {x} three. [[Four.]] Fig. 2 five.") == [
        "One, i.e. Two.",
        "{x} three.",
        "[[Four.]] Fig. 2 five.",
    ]


def test_labels_need_their_values_and_write_nan():
    t = parse("<!-- labels -->\n- a: z = {z:.2f}[[; at {n} points]]\n")
    assert (
        t.label("a", z=math.nan) == "z = nan" and t.label("a", z=1, n=3) == "z = 1.00; at 3 points"
    )
    with pytest.raises(KeyError, match="needs"):
        t.label("a")
    with pytest.raises(KeyError, match="no label"):
        t.label("b")


def test_every_template_parses_into_known_blocks():
    names = sorted(p.stem for p in TEMPLATES.glob("*.md"))
    assert set(STUDIES) <= set(names)
    for name in names:
        t = load(name)
        assert {b.kind for b in t.blocks} <= KINDS | {"labels"}, name


@pytest.fixture(scope="module")
def results(tiny_results):
    return tiny_results


def test_every_study_template_renders_once_with_its_numbers(results, tmp_path):
    """Each 2D study's template filled with its tiny result: no placeholder left, every figure
    it places drawn by the study and every table it places provided, and the sentences it keeps
    quote the study's numbers."""
    for name, r in results.items():
        study = STUDIES[name]
        figures = study.figures(r, tmp_path)
        tables = study.report_tables(r)
        blocks = render(study.template, study.numbers(r), figures, tables, [])
        placed = {b.name for b in study.template.blocks if b.kind == "figure"}
        assert set(figures) <= placed, name
        wanted = {b.name for b in study.template.blocks if b.kind == "table"}
        assert set(tables) <= wanted, name
        text = " ".join(str(b[1]) for b in blocks if b[0] in ("p", "h2", "h3"))
        text += " ".join(b[3] for b in blocks if b[0] == "figure")
        assert "{" not in text and "[[" not in text, (name, text[:200])
    fig1b = STUDIES["fig1b"]
    p = " ".join(b[1] for b in render(fig1b.template, fig1b.numbers(results["fig1b"]), {}, {}, [])
                 if b[0] == "p")  # fmt: skip
    assert f"lambda = {results['fig1b'].collapse.lam:.3f}" in p
