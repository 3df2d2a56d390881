"""The report's opening names only the studies that ran, in their own templates' words."""

from types import SimpleNamespace

from tensegrity_rigidity.paper import report
from tensegrity_rigidity.paper.template import fill, parse


def _study(text: str, numbers: dict):
    return SimpleNamespace(template=parse(text), numbers=lambda r: numbers)


def _opening(values: dict) -> str:
    block = report.REPORT.blocks[0]
    return " ".join(fill(block.text, values))


def test_the_opening_names_only_the_studies_that_ran(monkeypatch):
    studies = {
        "a": _study("<!-- opening -->\nstudy A asks one question\n", {}),
        "b": _study("<!-- opening compared -->\nstudy B compares\n", {"compared": 3}),
        "c": _study("<!-- opening compared -->\nstudy C compares\n", {"compared": None}),
        "d": _study("<!-- text -->\nno opening\n", {}),
    }
    monkeypatch.setattr(report, "STUDIES", studies)
    assert report.openings({"a": 1, "b": 2, "c": 3, "d": 4}) == [
        "study A asks one question",
        "study B compares",
    ]
    assert report.openings({"c": 3, "d": 4}) == []


def test_the_report_opening_says_no_more_than_what_ran():
    # reports/limit: the opening spoke of the finite-size, node-disorder and 3D studies, absent
    text = _opening({"scale": "limit", "no_claims": "", "openings": "the limit study asks"})
    assert "(the limit study asks)." in text
    said = text.split("no solver noise")[-1].split("solver noise.")[-1]
    for absent in ("finite-size", "node-disorder", "3D", "compares none"):
        assert absent not in said
    text = _opening({"scale": "limit", "no_claims": "", "openings": None})
    assert "say what each measured." in text and "(" not in text.split("measured")[-1]


def test_each_study_opening_that_ships_is_a_clause():
    from tensegrity_rigidity.paper.registry import STUDIES

    for name, study in STUDIES.items():
        for b in study.template.blocks:
            if b.kind == "opening":
                assert b.text and b.text[0].islower() and not b.text.endswith("."), name
