"""The efficacy-limit study beyond the paper: its sweeps and price, its analysis on synthetic
paired thresholds with a known answer (a vanishing and a finite asymmetry), a tiny run, and its
report section."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity.ensemble.spec import parse_spec
from tensegrity_rigidity.paper import budget
from tensegrity_rigidity.paper.registry import SCALES, STUDIES
from tensegrity_rigidity.paper.report import render
from tensegrity_rigidity.paper.studies import efficacy_limit as el
from tensegrity_rigidity.paper.study import Scale

from .conftest import SERIAL

TINY = SCALES["tiny-limit"]


def test_the_study_is_registered_and_pairs_its_samples():
    assert STUDIES[el.NAME] is el.STUDY
    assert SCALES["limit"].studies == (el.NAME,) and TINY.studies == (el.NAME,)
    p = SCALES["limit"][el.NAME]
    specs = el.sweeps(SCALES["limit"])
    assert len(specs) == 2 * (len(p.sizes_2d) + len(p.sizes_3d))
    for dim, sizes in p.by_dim().items():
        for n, samples in sizes:
            rods, cables = specs[f"limit_{dim}d_rods_n{n}"], specs[f"limit_{dim}d_cables_n{n}"]
            # one seed and one sample count: sample k is one disorder in both sweeps
            assert rods["seed"] == cables["seed"] == el.SEEDS[dim]
            assert rods["samples"] == cables["samples"] == samples
            assert rods["p_t"] == 0.0 and cables["p_t"] == el.P_T and cables["f_c"] == 1.0
            assert sorted(cables["phi"]) == [el.DILATION, el.COMPRESSION]
            assert parse_spec(cables).lattice == ("fcc" if dim == 3 else "triangular")


def test_the_budget_prices_every_search_within_the_scales_budget():
    est = budget.estimate("limit", workers=2)
    p = SCALES["limit"][el.NAME]
    searches = sum(3 * s for s in (*p.samples_2d, *p.samples_3d))
    assert sum(s.rows for s in est.sweeps) == searches
    assert not est.over_budget


def _rows(asym, total: float, sizes, samples: int, dim: int = 2, seed: int = 3):
    """Rows of the two sweeps per size: rods thresholds r_k, and under compression and
    dilation r_k - lambda p_t (+ a common noise and a small one of each), with lambda_D -
    lambda_C = asym(N) and lambda_C + lambda_D = total exactly."""
    rng = np.random.default_rng(seed)
    rows = {}
    for n in sizes:
        a = asym(float(n**dim))
        lam_c, lam_d = (total - a) / 2, (total + a) / 2
        r = 0.66 + 0.05 * n**-0.8 * rng.standard_normal(samples)
        common = 0.01 * rng.standard_normal(samples)
        base = {"sample": np.arange(1, samples + 1), "threshold_rods": 100.0,
                "threshold_one_sided": 30.0}  # fmt: skip
        rods = pd.DataFrame(base | {"phi": el.DILATION, "threshold_p_r": r})
        strains = ((el.COMPRESSION, lam_c), (el.DILATION, lam_d))
        cables = pd.concat([pd.DataFrame(base | {
            "phi": phi, "threshold_p_r": r - lam * el.P_T + common
            + 1e-4 * rng.standard_normal(samples)}) for phi, lam in strains])  # fmt: skip
        rows[f"limit_{dim}d_rods_n{n}"] = (rods, 0)
        rows[f"limit_{dim}d_cables_n{n}"] = (cables, 0)
    return rows


def _scale(sizes) -> Scale:
    return Scale(name="synthetic", params={el.NAME: el.Params(
        sizes_2d=sizes, samples_2d=(1,) * len(sizes))}, bootstrap=100)  # fmt: skip


SIZES = (8, 12, 16, 24, 32, 48, 64)


@pytest.mark.parametrize(("asym", "verdict"), [
    (lambda N: 0.6 * N**-0.4, "vanishes"),
    (lambda N: 0.08 + 0.6 * N**-0.4, "finite"),
])  # fmt: skip
def test_the_asymmetry_and_its_verdict_are_recovered(asym, verdict):
    r = el.analyse(_rows(asym, 1.0, SIZES, 200), _scale(SIZES))
    by = r.by_size.set_index("n")
    for n in SIZES:
        assert by.asym[n] == pytest.approx(asym(n**2), abs=4 * by.asym_err[n] + 1e-9)
        assert by.total[n] == pytest.approx(1.0, abs=4 * by.total_err[n] + 1e-9)
        # paired: A is far better determined than either efficacy
        assert by.asym_err[n] < 0.2 * by.c_err[n]
    li = r.limits.set_index("series")
    assert li.verdict["asym"] == verdict and li.verdict["asym_mean"] == verdict
    assert li.value["total"] == pytest.approx(1.0, abs=0.01)
    if verdict == "finite":
        assert li.value["asym"] == pytest.approx(0.08, abs=3 * li.stat["asym"] + 0.01)


def test_a_sample_missing_a_threshold_is_counted_not_paired():
    rows = _rows(lambda N: 0.1, 1.0, (8, 16), 20)
    cables, _ = rows["limit_2d_cables_n8"]
    missing = (cables["sample"] == 3) & np.isclose(cables.phi, el.COMPRESSION)
    rows["limit_2d_cables_n8"] = (cables[~missing], 1)
    r = el.analyse(rows, _scale((8, 16)))
    by = r.by_size.set_index("n")
    assert (by.samples[8], by.lost[8], by.samples[16], by.lost[16]) == (19, 1, 20, 0)
    assert r.excluded["limit_2d_cables_n8"] == 1


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """The study at the tiny-limit scale (2D n = 4, 6, 8; FCC n = 2, 3), run once, serially."""
    return el.STUDY(tmp_path_factory.mktemp("limit"), TINY, **SERIAL)


def test_a_tiny_run_pairs_every_sample_and_renders(tiny, tmp_path):
    p = TINY[el.NAME]
    by = tiny.by_size
    assert list(zip(by.dim, by.n, by.samples, strict=True)) == [
        *((2, n, s) for n, s in zip(p.sizes_2d, p.samples_2d, strict=True)),
        *((3, n, s) for n, s in zip(p.sizes_3d, p.samples_3d, strict=True))]  # fmt: skip
    assert (by.lost == 0).all() and np.isfinite(by.asym).all()
    assert list(by.N) == [n**2 for n in p.sizes_2d] + [n**3 for n in p.sizes_3d]
    # the efficacies are the P = 1/2 shifts over p_t: (p_c(0) - p_c(p_t)) / p_t in (0, 1)
    assert ((by.c > 0) & (by.d > 0) & (by.c < 1.5) & (by.d < 1.5)).all()
    figures = el.STUDY.figures(tiny, tmp_path)
    assert set(figures) == {"limit"} and all(f.exists() for f in figures["limit"])
    numbers = el.STUDY.numbers(tiny)
    assert math.isclose(numbers["paper_asym"], 0.67 - 0.372)
    blocks = render(el.STUDY.template, numbers, figures, el.STUDY.report_tables(tiny), [])
    text = " ".join(str(b[1]) for b in blocks if b[0] == "p")
    assert f"{by.asym.iloc[0]:.3f}" in text and "{" not in text


def test_sizes_meet_at_nearly_equal_node_counts_and_the_question_gets_its_answer():
    by = pd.DataFrame({"dim": [2, 2, 2, 3, 3, 3], "n": [8, 16, 32, 4, 6, 10],
                       "N": [64, 256, 1024, 64, 216, 1000]})  # fmt: skip
    pairs = [(int(a.n), int(b.n)) for a, b in el.equal_nodes(by)]
    assert pairs == [(8, 4), (16, 6), (32, 10)]
    # 3D n = 5 (125 nodes) is 2.0x from 2D n = 8 and n = 16: no partner
    by.loc[4, ["n", "N"]] = [5, 125]
    assert [(int(a.n), int(b.n)) for a, b in el.equal_nodes(by)] == [(8, 4), (32, 10)]
    words = {"two": "vanishes", "three": "finite"}
    assert el._answer({2: "vanishes", 3: "finite"}) == el.T.label("answer.vanishes.finite", **words)
    # limits less than two errors apart: a 2D limit consistent with 0 is not an answer "yes"
    close = el._answer({2: "vanishes", 3: "finite"}, apart=False)
    assert close == el.T.label("answer.vanishes.finite.close", **words)
    assert close.startswith("Not established") and "yes" not in close
    assert el._answer({2: "finite", 3: "finite"}) == el.T.label("answer.finite.finite")
    assert '"undetermined" in 2D' in el._answer({2: "undetermined", 3: "finite"})
    assert el._answer({2: "vanishes"}) is None


def test_thresholds_that_are_intervals_are_counted_and_bracket_the_asymmetry():
    rows = _rows(lambda N: 0.1, 1.0, (8, 16), 40)
    cables, _ = rows["limit_2d_cables_n16"]
    cables = cables.assign(threshold_p_r_low=cables.threshold_p_r,
                           threshold_p_r_high=cables.threshold_p_r)  # fmt: skip
    # three samples under compression end as intervals of 0.01 around their centre
    wide = np.isclose(cables.phi, el.COMPRESSION) & cables["sample"].isin([1, 2, 3])
    cables.loc[wide, "threshold_p_r_low"] -= 0.005
    cables.loc[wide, "threshold_p_r_high"] += 0.005
    rows["limit_2d_cables_n16"] = (cables, 0)
    by = el.analyse(rows, _scale((8, 16))).by_size.set_index("n")
    assert (by.intervals[8], by.intervals[16]) == (0, 3)
    assert by.asym_lo[8] == by.asym[8] == by.asym_hi[8]
    assert by.asym_lo[16] <= by.asym[16] <= by.asym_hi[16] and by.asym_hi[16] > by.asym_lo[16]
    assert by.asym_hi[16] - by.asym_lo[16] <= 0.01 / el.P_T + 1e-12


def test_a_bracket_names_one_value_when_its_ends_agree_and_counts_intervals_in_words():
    # reports/limit: "0.170 to 0.170 at n = 8 in 2D (1 intervals)"
    from types import SimpleNamespace

    one = SimpleNamespace(n=8, dim=2, intervals=1, asym_lo=0.17, asym_hi=0.1700001)
    many = SimpleNamespace(n=64, dim=2, intervals=19, asym_lo=0.045, asym_hi=0.061)
    assert el._bracket(one) == "0.170 at n = 8 in 2D (1 interval)"
    assert el._bracket(many) == "0.045 to 0.061 at n = 64 in 2D (19 intervals)"


def test_the_answer_says_when_the_sizes_cannot_tell_the_dimensions_apart():
    # the committed limit run: 2D -0.018 +- 0.071 (stat) +- 0.018 (fit form), 3D 0.1201 +- 0.0023
    # with the power law to zero rejected at the slowest decay the fit tries
    two = pd.Series({"value": -0.018, "stat": 0.071, "syst": 0.018, "zero_ok": True,
                     "zero_x": 0.28})  # fmt: skip
    # as a row of the limits table: numpy booleans
    three = pd.DataFrame({"value": [0.1201], "stat": [0.0023], "syst": [0.0],
                          "zero_ok": [False], "zero_x": [el.limits.X_GRID[0]]}).iloc[0]  # fmt: skip
    c = el._caveats({2: two, 3: three})
    err = np.hypot(np.hypot(0.071, 0.018), 0.0023)
    assert c["not_apart"] == el.T.label("not_apart", diff=0.1381, err=err)
    assert c["slowest"] == [el.T.label("slowest", dim=3, x=0.1)]
    # a 2D limit tight about zero is told apart from 3D, and a power law rejected at an
    # interior exponent needs no caveat
    tight = two.copy()
    tight[["stat", "syst"]] = 0.01, 0.0
    three["zero_x"] = 0.5
    assert el._caveats({2: tight, 3: three}) == {"slowest": None}
    # so is a 2D limit far above the 3D one, not only one far below
    above = tight.copy()
    above["value"] = 0.30
    assert "not_apart" not in el._caveats({2: above, 3: three})


def test_the_answer_stands_without_its_caveats():
    """The caveats are their own sentences: without them the answer is still printed."""
    v = {"answer": el.T.label("answer.finite.finite"), "not_apart": None, "slowest": None}
    text = " ".join(" ".join(b[1]) if isinstance(b[1], list) else str(b[1])
                    for b in render(el.STUDY.template, v, {}, {}, []))  # fmt: skip
    assert el.T.label("answer.finite.finite") in text and "rejected only" not in text
