"""The jamming-onset study beyond the paper: its sweeps and price, its analysis on synthetic
outcomes with a known answer, the packing it draws, and its report section."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.ensemble.jamming import sample_seconds
from tensegrity_rigidity.errors import InputError
from tensegrity_rigidity.paper import budget
from tensegrity_rigidity.paper.registry import SCALES, STUDIES
from tensegrity_rigidity.paper.report import render
from tensegrity_rigidity.paper.studies import jamming_onset as jo
from tensegrity_rigidity.paper.studies.rows import study_spec
from tensegrity_rigidity.paper.study import Scale

from .conftest import SERIAL

TINY_JAMMING = SCALES["tiny-jamming"]


def _scale(**params) -> Scale:
    return Scale(name="synthetic", params={jo.NAME: jo.Params(**params)}, bootstrap=60)


def test_the_study_is_registered_and_its_sweeps_are_packing_sweeps():
    assert STUDIES[jo.NAME] is jo.STUDY
    assert SCALES["jamming"].studies == (jo.NAME,) and TINY_JAMMING.studies == (jo.NAME,)
    p = SCALES["jamming"][jo.NAME]
    assert p.sizes == (64, 128, 256, 512, 1024) and len(p.samples) == len(p.sizes)
    specs = jo.sweeps(SCALES["jamming"])
    assert list(specs) == [f"packings_n{n}" for n in p.sizes]
    for n, raw in zip(p.sizes, specs.values(), strict=True):
        spec = study_spec(raw)
        assert spec.mode == "packing" and spec.grid["n"] == [n]
        assert spec.grid["fraction"] == list(p.fractions) and spec.grid["seed"] == [jo.SEED]
        assert 1 <= spec.chunk_size <= 32
    assert jo.chunk_size(1024) < jo.chunk_size(64)


def test_the_budget_prices_every_packing_by_the_measured_per_sample_costs():
    est = budget.estimate("jamming", workers=2)
    p = SCALES["jamming"][jo.NAME]
    assert {s.mode for s in est.sweeps} == {"packing"}
    for s, n, k in zip(est.sweeps, p.sizes, p.samples, strict=True):
        assert s.n == n and s.new_rows == s.rows == k * len(p.fractions)
        assert s.cpu_seconds == pytest.approx(s.rows * sample_seconds(n))
    t = est.table()
    assert int(t.packings.sum()) == sum(k * len(p.fractions) for k in p.samples)
    assert "packings" in budget.describe(est) and not est.over_budget


def _synthetic(phi_j: dict[int, float], width: float, fractions, samples: int, seed: int = 1):
    """Rows of a packing sweep per size, drawn from a logistic P(phi) centred on ``phi_j[n]``;
    every jammed packing strictly jammed above phi_j + width; where two are jammed, one strict
    test undecided and one jammed packing below the isostatic count per size (which a correct
    test never gives: the study must count it)."""
    rng = np.random.default_rng(seed)
    rows = {}
    for n, centre in phi_j.items():
        out = []
        for phi in fractions:
            p = 1 / (1 + np.exp(-(phi - centre) / width))
            for k in range(1, samples + 1):
                jammed = rng.random() < p
                iso = 2 * (n - 1) + 1
                out.append({"n": n, "fraction": phi, "seed": 0, "sample": k,
                            "collective": "jammed" if jammed else "unjammed",
                            "strict": "jammed" if jammed and phi > centre + width else "unjammed",
                            "rattlers": 2 if jammed else n, "contacts": iso + 3,
                            "backbone_contacts": iso + 1 if jammed else 0,
                            "isostatic_contacts": iso if jammed else 0})  # fmt: skip
        df = pd.DataFrame(out)
        jammed = df.index[df.collective == "jammed"]
        if len(jammed) >= 2:
            df.loc[jammed[0], "strict"] = "undecided"
            df.loc[jammed[1], "backbone_contacts"] = df.loc[jammed[1], "isostatic_contacts"] - 1
        rows[f"packings_n{n}"] = (df, 3)  # three undecided samples excluded per sweep
    return rows


FRACTIONS = tuple(np.round(np.linspace(0.80, 0.88, 17), 4))


def test_the_analysis_recovers_known_jamming_points_and_counts_every_sample():
    truth = {n: 0.842 - 0.25 * n**-0.7 for n in (64, 128, 256, 512, 1024)}
    scale = _scale(sizes=tuple(truth), samples=(120,) * 5, fractions=FRACTIONS)
    r = jo.analyse(_synthetic(truth, 0.006, FRACTIONS, 120), scale)
    assert r.drawn is None  # no point to draw at (0, 0)
    for q in r.points:
        assert abs(q.phi_j.value - truth[q.n]) < 4 * q.phi_j.err + 5e-4, q
    assert r.shift is not None and r.shift.accepted
    assert abs(r.shift.phi_inf - 0.842) <= r.shift.spread + 2e-3
    by = r.by_size.set_index("n")
    assert (by.undecided == 3).all() and (by.strict_undecided == 1).all()
    assert (by.below_isostatic == 1).all() and (by.samples == 17 * 120).all()
    assert (by.strict_tested == by.jammed - 1).all()
    table = r.table
    assert (table.decided == 120).all() and set(table.n) == set(truth)
    assert r.excluded == {f"packings_n{n}": 3 for n in truth}
    v = jo.numbers(r)
    assert v["excluded"] == 15 and v["strict_undecided"] == 5 and v["below_isostatic"] == 5
    assert v["sizes"] == list(truth) and v["drawn_n"] is None


def test_a_width_below_the_grid_step_is_called_unresolved():
    """A transition narrower than the packing-fraction grid's step (N = 1024 on the jamming
    scale: 0.0014 against 0.0025) rests on one point inside it: the width is flagged."""
    truth = {64: 0.835, 1024: 0.84}
    scale = _scale(sizes=tuple(truth), samples=(120, 120), fractions=FRACTIONS)
    r = jo.analyse(_synthetic(truth, 0.0002, FRACTIONS, 120), scale)
    v = jo.numbers(r)
    step = FRACTIONS[1] - FRACTIONS[0]
    assert v["step"] == pytest.approx(step)
    coarse = [w for w in v["widths"] if "not resolved by the grid" in w]
    assert coarse and len(coarse) == len(v["widths"])


def test_a_size_without_a_crossing_is_reported_and_no_shift_from_one_size():
    fractions = FRACTIONS[:6]  # all below the centre: P never reaches 1/2 at N = 256
    scale = _scale(sizes=(64, 256), samples=(40, 40), fractions=fractions)
    rows = _synthetic({64: 0.79, 256: 0.86}, 0.004, fractions, 40)
    r = jo.analyse(rows, scale)
    pts = jo.points_frame(r).set_index("n")
    assert not np.isfinite(pts.phi_j).any()  # P above 1/2 at N = 64, below at 256 throughout
    assert r.shift is None and jo.shift_frame(r).empty
    v = jo.numbers(r)
    assert v["phi_inf"] is None and v["points"] is None and v["unresolved"] == [64, 256]


def _text(study, result, figdir) -> str:
    figures = study.figures(result, figdir)
    blocks = render(study.template, study.numbers(result), figures, study.report_tables(result), [])
    text = " ".join(str(b[1]) for b in blocks if b[0] in ("p", "h2", "h3"))
    return text + " ".join(b[3] for b in blocks if b[0] == "figure")


def test_the_template_renders_with_the_synthetic_numbers(tmp_path):
    truth = {n: 0.842 - 0.25 * n**-0.7 for n in (64, 256, 1024)}
    scale = _scale(sizes=tuple(truth), samples=(60,) * 3, fractions=FRACTIONS)
    r = jo.analyse(_synthetic(truth, 0.006, FRACTIONS, 60), scale)
    text = _text(jo.STUDY, r, tmp_path)
    assert "{" not in text and "[[" not in text
    v = jo.numbers(r)
    assert v["phi_inf"] in text and all(p in text for p in v["points"])
    assert "collective test was undecided (counted, left out of P): 9." in text
    assert (tmp_path / "figjamming.png").exists() and not (tmp_path / "figpacking.png").exists()


@pytest.fixture(scope="module")
def micro(tmp_path_factory):
    """The study at one small size and two packing fractions, run once (a few seconds)."""
    scale = _scale(sizes=(16,), samples=(3,), fractions=(0.80, 0.86), drawn=(16, 0.86))
    out = tmp_path_factory.mktemp("jamming_onset")
    return jo.STUDY(out, scale, **SERIAL), out, scale


def test_the_drawn_packing_is_its_sweep_row_tested_again(micro, tmp_path):
    r, out, scale = micro
    d = r.drawn
    assert d is not None and (d.n, d.fraction) == (16, 0.86)
    row = r.table[(r.table.n == 16) & np.isclose(r.table.phi, 0.86)].iloc[0]
    assert d.result.status == "jammed" and row.jammed >= 1
    forces = d.result.contact_forces()
    assert forces.shape == (d.network.n_sites,) and forces.min() >= 0 and forces.max() > 0
    figures = jo.STUDY.figures(r, tmp_path)
    assert set(figures) == {"jamming", "packing"}
    # a row that does not match its packing is refused, never drawn in its place
    from tensegrity_rigidity.paper.studies.rows import load_sweeps

    rows = jo.rows_of(load_sweeps(out, jo.sweeps(scale), workers="stored", scheduler=None,
                                  progress=False))  # fmt: skip
    rows.loc[rows.collective == "jammed", "contacts"] += 1
    with pytest.raises(InputError, match="not its sweep row"):
        jo.draw(rows, 16, 0.86)


def test_the_micro_run_renders_and_quotes_its_counts(micro, tmp_path):
    r, _, _ = micro
    text = _text(jo.STUDY, r, tmp_path)
    assert "[[" not in text and "6 at N = 16" in text
    assert dataclasses.is_dataclass(r) and r.excluded == {"packings_n16": 0}


@pytest.mark.slow
def test_the_tiny_jamming_scale_reproduces_end_to_end(tmp_path):
    out = tmp_path / "run"
    args = ["reproduce", "--scale", "tiny-jamming", "--out", str(out), "--workers", "2"]
    assert main([*args, "--no-progress"]) == 0
    report = (out / "report.md").read_text()
    assert "when is a random disk packing jammed" in report
    points = pd.read_csv(out / "tables" / "jamming_points.csv")
    assert list(points.n) == list(TINY_JAMMING[jo.NAME].sizes)
    assert np.isfinite(points.phi_j).all()
