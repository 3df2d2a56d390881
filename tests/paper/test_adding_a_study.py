"""The study of docs/guide/adding-a-study.md works as the guide says: its module, placed in
``paper/studies/`` with its template, runs its sweep, measures its claim and fills its template,
and the budget refuses it until its analysis has a measured cost.

The guide's module has the relative imports of a module of the package, so the runner of the
guides' examples (tests/test_examples_in_docs.py) leaves it to this test, which executes it as
``tensegrity_rigidity.paper.studies.percolation``.
"""

from __future__ import annotations

import dataclasses
import re
import sys
import types
from pathlib import Path

import pytest

from tensegrity_rigidity.errors import InputError
from tensegrity_rigidity.paper import study as study_module
from tensegrity_rigidity.paper import template as template_module
from tensegrity_rigidity.paper.budget import COSTS
from tensegrity_rigidity.paper.report import render
from tensegrity_rigidity.paper.study import Study
from tensegrity_rigidity.paper.template import parse

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "guide" / "adding-a-study.md"
FENCE = re.compile(r"^```(\w+)\n(.*?)^```\n", flags=re.S | re.M)
PACKAGE = "tensegrity_rigidity.paper.studies"


def _guide_blocks(lang: str) -> list[str]:
    return [m.group(2) for m in FENCE.finditer(GUIDE.read_text()) if m.group(1) == lang]


@pytest.fixture
def percolation(monkeypatch):
    """The guide's module executed in the package, its template the guide's."""
    (module,) = _guide_blocks("python")
    (text,) = _guide_blocks("markdown")
    original = template_module.load
    mine = parse(text, "percolation")

    def load(name: str):
        return mine if name == "percolation" else original(name)

    monkeypatch.setattr(template_module, "load", load)
    monkeypatch.setattr(study_module, "load", load)
    mod = types.ModuleType(f"{PACKAGE}.percolation")
    mod.__package__ = PACKAGE
    monkeypatch.setitem(sys.modules, mod.__name__, mod)
    exec(compile(module, str(GUIDE), "exec", dont_inherit=True), mod.__dict__)
    return mod.__dict__


def test_the_guides_study_runs_measures_and_fills_its_template(percolation, tmp_path):
    from tensegrity_rigidity.paper.registry import SCALES

    study = percolation["STUDY"]
    assert isinstance(study, Study) and study.name == "percolation"
    tiny = SCALES["tiny"]
    scale = dataclasses.replace(
        tiny,
        params=dict(tiny.params, percolation=study.params["tiny"]),
        studies=("percolation",),
    )
    result = study(tmp_path, scale, workers="serial", scheduler=None, progress=False)
    assert 0 < result.p_c < 1 and result.p_c_err >= 0 and result.n == 5
    assert (tmp_path / "studies" / "percolation").is_dir()
    (m,) = result.measured
    assert m.claim == "rods_only_pc" and m.system == "n = 5, rods only"
    blocks = render(study.template, study.numbers(result), {}, {}, [])
    text = " ".join(str(b[1]) for b in blocks if b[0] in ("p", "h2"))
    assert f"{result.p_c:.4f} ± {result.p_c_err:.4f} at n = 5" in text
    assert "{" not in text and "moves by" not in text  # the fragment without its number
    with pytest.raises(InputError, match="has no work model"):
        study.cost(scale, COSTS)
