"""The paper's effective size: chi-square of its numbers against ours at each size."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from tensegrity_rigidity.analysis.agreement import chi2_against
from tensegrity_rigidity.analysis.limits import ACCEPT_P
from tensegrity_rigidity.paper import budget
from tensegrity_rigidity.paper.claims import CLAIMS
from tensegrity_rigidity.paper.registry import SCALES
from tensegrity_rigidity.paper.report import render
from tensegrity_rigidity.paper.studies import fss as fsm

#: the claims of one finite-size run at each size (as the headline study measures them)
KEYS = [
    "st_sr_cables_compression",
    "st_sr_struts_dilation",
    "st_sr_cables_dilation",
    "st_sr_half_shear",
    "rods_only_pc",
    "p_crit_compression_0.1",
    "p_crit_dilation_0.0",
    "alpha_dilation_0.2",
    "taut_cables_transition",
]


def _by_size(shifts: dict[int, float], err: float = 0.01) -> pd.DataFrame:
    """Every claim of KEYS at each size, at the paper's value plus ``shift`` combined errors."""
    rows = []
    for n, shift in shifts.items():
        for k in KEYS:
            c = CLAIMS[k]
            sigma = np.hypot(err, c.error)
            rows.append({"key": k, "n": n, "value": c.value + shift * sigma, "err": err})
    return pd.DataFrame(rows)


def test_chi2_against_a_known_answer():
    chi2, dof, p = chi2_against([1.0, 2.0], [0.3, 0.0], [1.5, 0.0], [0.4, 1.0])
    assert chi2 == pytest.approx(1.0 + 4.0) and dof == 2
    assert p == pytest.approx(np.exp(-2.5))  # chi2_2 survival
    assert chi2_against([], [], [], [])[1] == 0
    assert chi2_against([1.0], [0.0], [2.0], [0.0])[0] == np.inf


def test_only_the_papers_own_numbers_enter():
    """A theory's exact value, a literature value and a repeat by symmetry are left out."""
    entering = {k for k in KEYS if fsm.paper_number(k)}
    assert entering == {"st_sr_cables_compression", "st_sr_cables_dilation",
                        "p_crit_compression_0.1", "alpha_dilation_0.2",
                        "taut_cables_transition"}  # fmt: skip


def test_the_size_where_ours_equal_the_papers_is_the_effective_one():
    fit = fsm.paper_fit(_by_size({4: 3.0, 6: 0.0, 8: 1.0, 10: 3.0}))
    every = fit[fit.figure == fsm.ALL_FIGURES].set_index("n")
    assert list(every.dof) == [5] * 4 and (every.missing == 0).all()
    assert every.chi2[6] == pytest.approx(0.0) and every.p_value[6] == pytest.approx(1.0)
    assert every.chi2[8] == pytest.approx(5.0)
    assert every.chi2[4] == pytest.approx(45.0)
    assert every.p_value[8] == pytest.approx(stats.chi2.sf(5.0, 5))
    best = fsm.effective_size(fit)
    assert best is not None
    assert best["n"] == 6 and best["dof"] == 5 and best["p_value"] == pytest.approx(1.0)
    assert best["fitting"] == [6, 8]  # p(5, 5) = 0.42; 45 for 5 claims does not fit
    # per figure: Fig. 1C holds both S_t/S_r numbers of the paper
    fig1c = fit[(fit.figure == "1C") & (fit.n == 4)]
    assert int(fig1c.dof.iloc[0]) == 2 and fig1c.chi2.iloc[0] == pytest.approx(18.0)
    assert set(fit.figure) == {fsm.ALL_FIGURES, "1C", "2B", "2C", "2D"}


def test_no_size_fits_and_a_missing_value_is_counted():
    by = _by_size({8: 3.0, 16: 4.0})
    by.loc[(by.n == 8) & (by.key == "taut_cables_transition"), "value"] = np.nan
    fit = fsm.paper_fit(by)
    every = fit[fit.figure == fsm.ALL_FIGURES].set_index("n")
    assert every.missing[8] == 1 and every.dof[8] == 4 and every.missing[16] == 0
    best = fsm.effective_size(fit)
    assert best is not None and best["n"] == 8 and best["fitting"] == []
    assert not fit.fits.any()


def test_no_claim_of_the_paper_no_effective_size():
    by = pd.DataFrame({"key": ["rods_only_pc"] * 2, "n": [32, 64], "value": [0.66, 0.66],
                       "err": [0.001, 0.001]})  # fmt: skip
    fit = fsm.paper_fit(by)
    assert not len(fit) and fsm.effective_size(fit) is None
    assert fsm._effective(SimpleNamespace(paper_fit=fit)) == {}


def _result(by: pd.DataFrame, paper_pcrit: pd.DataFrame | None = None) -> SimpleNamespace:
    return SimpleNamespace(paper_fit=fsm.paper_fit(by, paper_pcrit), paper_pcrit=paper_pcrit,
                           paper_claims=fsm.paper_claims(by, paper_pcrit),
                           energy_samples=(24,))  # fmt: skip


def _render(r) -> tuple[str, dict]:
    names = ("effective", "effective_paper", "effective_size", "reproduced")
    blocks = [b for b in fsm.T.blocks if b.name in names]
    tables = {"effective_size": fsm._effective_table(r), "reproduced": fsm._reproduced_table(r)}
    out = render(fsm.T, fsm._effective(r), {}, tables, [], blocks=blocks)
    return " ".join(b[1] for b in out if b[0] == "p"), tables


def _text(shifts, missing=None) -> tuple[str, pd.DataFrame | None]:
    by = _by_size(shifts)
    if missing is not None:  # one claim of the paper without a value at that size
        by.loc[(by.n == missing) & (by.key == "taut_cables_transition"), "value"] = np.nan
    text, tables = _render(_result(by))
    return text, tables["effective_size"]


def test_the_report_names_the_effective_size_and_the_sizes_that_fit():
    text, table = _text({4: 3.0, 6: 0.0, 8: 1.0})
    assert "fit best at n = 6 (chi-square 0.0 for 5 claims, p = 1)" in text
    assert f"n = 6, 8 fit at p >= {ACCEPT_P}" in text and "no size fits" not in text
    assert "Fig. 1C, n = 6 (chi-square 0.0 for 2 claims," in text and "{" not in text
    assert "claim(s)" not in text
    assert "left out of the sums" not in text
    assert table is not None and list(table.n) == [4, 6, 8]
    assert list(table.fits) == [fsm.T.label("no"), fsm.T.label("yes"), fsm.T.label("yes")]
    assert "Fig. 2C" in table.columns


def test_the_report_says_when_no_size_fits():
    text, _ = _text({8: 3.0, 16: 4.0}, missing=8)
    assert "fit best at n = 8" in text
    assert f"no size fits at p >= {ACCEPT_P}" in text and "fit at p" not in text
    assert 'left out of the sums (column "missing" of tables/fss_paper_fit.csv): 1.' in text


def test_the_paper_size_scale_is_declared_and_priced():
    scale = SCALES["paper-size"]
    assert scale.studies == ("fss",)
    p = scale["fss"]
    assert p.sizes == fsm.PAPER_SIZES == (4, 6, 8, 10, 12)
    assert not p.pc  # the rods-only point from the headline sweeps
    est = budget.estimate("paper-size", workers=2)
    assert 0 < est.wall_seconds <= 60 * scale.budget_minutes <= 60 * 15
    assert {s.study for s in est.sweeps} == {"fss"}


def test_a_long_paragraph_is_never_split_after_fig():
    from tensegrity_rigidity.paper.render import split_paragraph

    words = " ".join(["word"] * 8)
    text = f"{words}. Then {words} Fig. 2B, n = 4; Fig. 2C, n = 12. Then {words}."
    parts = split_paragraph(text, max_words=12)
    assert not any(p.endswith("Fig.") for p in parts)
    assert any("Fig. 2B, n = 4" in p for p in parts) and len(parts) > 1


def _grid(first: dict[float, float], samples: int = 4) -> pd.DataFrame:
    """Energy grid rows of rods + cables at p_t = 0.1: per phi, every sample's energy is 0 below
    the p_r ``first[phi]`` and positive from there (sample 0 only, so the mean is positive
    there but the median threshold of the samples lies higher); one undecided row with a
    positive energy below it, which must not count."""
    rows = []
    for phi, p_r0 in first.items():
        for p_r in np.round(np.arange(0.5, 0.7001, 0.025), 6):
            for k in range(samples):
                on = p_r >= p_r0 and (k == 0 or p_r >= p_r0 + 0.05)
                rows.append({"phi": phi, "p_t": 0.1, "p_r": p_r, "sample": k,
                             "energy": 1e-3 * on, "decided": True})  # fmt: skip
    rows.append({"phi": np.pi, "p_t": 0.1, "p_r": 0.5, "sample": samples, "energy": 1.0,
                 "decided": False})  # fmt: skip
    return pd.DataFrame(rows)


def test_the_papers_pcrit_is_the_first_p_r_with_a_positive_mean_energy():
    from tensegrity_rigidity.paper.studies.headline import first_positive_pcrit

    got = first_positive_pcrit(_grid({np.pi: 0.575, 0.0: 0.625}), SCALES["tiny"])
    got = got.set_index("key")
    assert set(got.index) == {"p_crit_compression_0.1", "p_crit_dilation_0.1"}
    assert got.value["p_crit_compression_0.1"] == pytest.approx(0.575)
    assert got.value["p_crit_dilation_0.1"] == pytest.approx(0.625)
    assert (got.samples == 4).all()  # the undecided row's sample is not one
    # the error is at least the grid's resolution h / sqrt(12)
    assert (got.err >= 0.025 / np.sqrt(12) - 1e-12).all()
    assert not got.censored.any()
    none = first_positive_pcrit(_grid({np.pi: 0.9}), SCALES["tiny"])
    assert np.isnan(none.value.iloc[0]) and not none.censored.iloc[0]  # no positive mean
    edge = first_positive_pcrit(_grid({np.pi: 0.5}), SCALES["tiny"])
    assert edge.value.iloc[0] == 0.5 and edge.censored.iloc[0]  # positive at the first p_r


def test_a_bound_of_the_papers_estimator_is_missing_not_a_value():
    by = _by_size({6: 0.0, 8: 0.0})
    theirs = _paper_pcrit({6: 0.0, 8: 5.0}).assign(censored=[False, True])
    fit = fsm.paper_fit(by, theirs)
    every = fit[(fit.figure == fsm.ALL_FIGURES) & (fit.estimator == fsm.PAPERS)].set_index("n")
    assert list(every.missing) == [0, 1] and list(every.dof) == [5, 4]
    assert every.chi2[8] == pytest.approx(0.0)
    c = fsm.paper_claims(by, theirs)
    bound = c[(c.estimator == fsm.PAPERS) & (c.n == 8)].iloc[0]
    assert bound.censored and np.isnan(bound.z) and not bound.reproduced
    text, tables = _render(_result(by, theirs))
    assert "left out of its sums as missing: 1 values of the paper's numbers (1 claims" in text
    row = tables["reproduced"].iloc[-1]
    assert row["z, n = 8"] == fsm.T.label("censored", value=theirs.value.iloc[1])
    assert row["reproduced"] == "n = 6"


def _paper_pcrit(shifts: dict[int, float], key: str = "p_crit_compression_0.1", err=0.01):
    """The paper's estimator of one p_crit claim at each size, ``shift`` combined errors off."""
    c = CLAIMS[key]
    sigma = np.hypot(err, c.error)
    return pd.DataFrame([{"key": key, "n": n, "value": c.value + s * sigma, "err": err}
                         for n, s in shifts.items()])  # fmt: skip


def test_the_papers_estimator_moves_chi2_where_the_estimators_differ():
    by = _by_size({6: 0.0, 8: 1.0})
    theirs = pd.concat([_paper_pcrit({6: 4.0, 8: 0.0}),  # not a number of the paper: ignored
                        _paper_pcrit({6: 9.0, 8: 9.0}, "p_crit_dilation_0.0")])  # fmt: skip
    fit = fsm.paper_fit(by, theirs)
    assert set(fit.estimator) == {fsm.OURS, fsm.PAPERS}
    every = fit[fit.figure == fsm.ALL_FIGURES].set_index(["estimator", "n"]).chi2
    assert every[fsm.OURS, 6] == pytest.approx(0.0) and every[fsm.OURS, 8] == pytest.approx(5.0)
    assert every[fsm.PAPERS, 6] == pytest.approx(16.0)
    assert every[fsm.PAPERS, 8] == pytest.approx(4.0)
    # only Fig. 2C, which holds the substituted claim, changes
    fig = fit[fit.figure != fsm.ALL_FIGURES].set_index(["figure", "n", "estimator"]).chi2
    assert fig["2C", 6, fsm.PAPERS] == pytest.approx(16.0) and fig["2C", 6, fsm.OURS] == 0.0
    for f in ("1C", "2B", "2D"):
        assert fig[f, 8, fsm.PAPERS] == pytest.approx(fig[f, 8, fsm.OURS])
    assert fsm.effective_size(fit)["n"] == 6
    assert fsm.effective_size(fit, estimator=fsm.PAPERS)["n"] == 8
    assert fsm.effective_size(fit, "2C", fsm.PAPERS)["n"] == 8
    # ours are left as they were
    assert fsm.with_paper_pcrit(by, None) is by and by.value.equals(_by_size({6: 0, 8: 1}).value)


def test_each_claim_is_reproduced_where_its_z_is_below_two():
    by = _by_size({8: 3.0, 10: 1.5})
    theirs = _paper_pcrit({8: 0.5, 10: 2.5})
    c = fsm.paper_claims(by, theirs)
    assert set(c.key) == {k for k in KEYS if fsm.paper_number(k)}
    ours = c[c.estimator == fsm.OURS].set_index(["key", "n"])
    assert ours.z["st_sr_cables_compression", 8] == pytest.approx(3.0)
    assert list(ours.reproduced.xs(10, level="n")) == [True] * 5
    assert not ours.reproduced.xs(8, level="n").any()
    paper = c[c.estimator == fsm.PAPERS].set_index("n")
    assert list(paper.key) == ["p_crit_compression_0.1"] * 2
    assert paper.z[8] == pytest.approx(0.5) and list(paper.reproduced) == [True, False]


def test_the_report_gives_the_effective_size_and_reproductions_under_both_estimators():
    by = _by_size({8: 3.0, 10: 4.0})
    text, tables = _render(_result(by, _paper_pcrit({8: 3.0, 10: 0.0})))
    assert "fit best at n = 8 (chi-square 45.0 for 5 claims" in text
    assert "energy over the decided samples of 24 per point" in text
    assert "the chi-square at n = 8, 10 is 45.0, 64.0" in text
    assert "then fit best at n = 8 (chi-square 45.0 for 5 claims" in text
    assert "with the paper's estimator: Fig. 1C, n = 8" in text and "Fig. 2C, n = 10 (chi" in text
    assert "0 of the 5 are reproduced at one size at least with our p_crit" in text
    assert "of the 1 p_crit claims, 0 with ours and 1 with the paper's" in text
    never = text.split("Reproduced at no size under either estimator: ")[1]
    assert CLAIMS["st_sr_cables_compression"].text in never
    assert CLAIMS["p_crit_compression_0.1"].text not in never.split(".")[0]
    assert "Every number of the paper is reproduced" not in text and "{" not in text
    eff = tables["effective_size"]
    assert list(eff.estimator) == [fsm.T.label("estimator.ours")] * 2 + [
        fsm.T.label("estimator.paper")] * 2  # fmt: skip
    assert list(eff.chi2_all) == ["45.0", "80.0", "45.0", "64.0"]
    rep = tables["reproduced"].set_index(["claim", "estimator"]).reproduced
    key = (CLAIMS["p_crit_compression_0.1"].text, fsm.T.label("estimator.paper"))
    assert rep[key] == "n = 10"
    assert rep[CLAIMS["st_sr_cables_compression"].text, fsm.T.label("estimator.ours")] == (
        fsm.T.label("at_no_size"))  # fmt: skip


def test_every_number_reproduced_is_said_and_no_papers_estimator_no_second_fit():
    text, tables = _render(_result(_by_size({6: 0.0, 8: 3.0})))
    assert "5 of the 5 are reproduced" in text and "Every number of the paper" in text
    assert "no size under either" not in text and "then fit best" not in text
    assert "estimator" not in tables["effective_size"].columns


def test_one_claim_is_singular():
    # reports/paper-size: "chi-square 0.0 for 1 claim(s)"
    b = {"n": 4, "chi2": 0.0, "dof": 1, "p_value": 0.95}
    assert "for 1 claim," in fsm.T.label("eff_figure.one", figure="2B", **b)
    assert "for 2 claims," in fsm.T.label("eff_figure", figure="2C", **{**b, "dof": 2})
