"""The rendering of blocks to Markdown: paragraphs split only at sentence ends, missing numbers
in tables printed as "-"."""

import math

import numpy as np
import pandas as pd

from tensegrity_rigidity.paper.render import html_table, md_table, split_paragraph


def test_a_semicolon_never_ends_a_paragraph():
    # reports/limit: "Sizes (nodes, samples): 2D ...; 3D ..." was split after the semicolon
    words = " ".join(["word"] * 10)
    text = f"{words}; 3D {words}; A {words}; 12 {words}. Next {words}."
    parts = split_paragraph(text, max_words=12)
    assert parts == [f"{words}; 3D {words}; A {words}; 12 {words}.", f"Next {words}."]
    assert not any(p.endswith(";") for p in parts)


def test_a_paragraph_still_splits_at_full_stops_question_and_exclamation_marks():
    words = " ".join(["word"] * 10)
    text = f"{words}. Two {words}? Three {words}! Four {words}."
    assert len(split_paragraph(text, max_words=12)) == 4


def test_a_missing_number_in_a_table_prints_as_a_dash():
    df = pd.DataFrame(
        {"a": [1.5, math.nan], "b": [None, "x"], "c": [np.float64("nan"), pd.NA], "d": ["n/a", 2]}
    )
    md = md_table(df)
    assert "nan" not in md.lower().replace("n/a", "") and "None" not in md and "<NA>" not in md
    assert md.splitlines()[2:] == ["| 1.5 | - | - | n/a |", "| - | x | - | 2 |"]
    html = html_table(df)
    assert "nan" not in html.lower().replace("n/a", "") and "None" not in html


def test_a_missing_number_inside_a_formatted_cell_prints_as_a_dash():
    # reports/paper-size: "nan / 0" in the chi-square / dof column of a fit on two sizes
    df = pd.DataFrame({"chi2": ["nan / 0", "1.08 / 0"], "z": ["n/a", "nan"], "w": ["nano", "x"]})
    assert md_table(df).splitlines()[2:] == ["| - / 0 | n/a | nano |", "| 1.08 / 0 | - | x |"]
