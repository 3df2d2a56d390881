"""Study results are typed and self-contained: exclusions travel inside them, no module state."""

from __future__ import annotations

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity.model.strain import NAMED_STRAINS
from tensegrity_rigidity.paper import report, studies
from tensegrity_rigidity.paper.claims import CLAIMS
from tensegrity_rigidity.paper.registry import REGISTRY, SCALES, STUDIES
from tensegrity_rigidity.paper.report import _excluded, bracketed_rows, excluded_samples
from tensegrity_rigidity.paper.studies import fig2, nonaffinity, rows
from tensegrity_rigidity.paper.studies.field import FIELD_P_T
from tensegrity_rigidity.paper.studies.rows import (
    interval_straddles,
    keep_decided,
    strain_name,
)
from tensegrity_rigidity.paper.study import Scale

from .conftest import TINY


def _threshold_rows(decided, est, lo=None, hi=None):
    df = pd.DataFrame(
        {"sample": np.arange(1, len(decided) + 1), "decided": decided, "threshold_p_r": est}
    )
    if lo is not None:
        df["threshold_p_r_low"], df["threshold_p_r_high"] = lo, hi
    return df


def test_no_module_level_undecided_counter():
    assert not hasattr(studies, "UNDECIDED")


def test_undecided_grid_and_old_threshold_rows_are_dropped_and_counted():
    grid = pd.DataFrame({"decided": [True, False, True], "rigid": [True, False, False]})
    kept, n = keep_decided(grid)
    assert n == 1 and len(kept) == 2
    old = _threshold_rows([True, False, True], [0.6, np.nan, 0.7])
    kept, n = keep_decided(old)
    assert n == 1 and list(kept["sample"]) == [1, 3]


def test_undecided_grid_rows_with_a_bracketed_energy_enter_only_the_energies():
    """An undecided grid row whose relaxed energy (an upper bound on E*) is at most
    ENERGY_BRACKETED of its affine energy is kept for the energy analyses at E = 0, one whose
    energy is certified at that energy; others are dropped. Every undecided row is counted."""
    grid = pd.DataFrame(
        {
            "decided": [True, False, False, False, True],
            "rigid": [True, False, False, False, False],
            "energy": [2.0, 5e-13, 1.0, 7.5, 0.0],
            "energy_lower": [2.0, 1e-32, 1e-20, 7.5, 0.0],
            "affine_energy": [5e3] * 5,
        }
    )
    near_zero, certified = rows.energy_bracketed(grid)
    assert near_zero.tolist() == [False, True, False, False, False]
    assert certified.tolist() == [False, False, False, True, False]
    kept, n = keep_decided(grid, energy=True)
    assert n == 3 and kept.energy.tolist() == [2.0, 0.0, 7.5, 0.0]
    kept, n = keep_decided(grid)
    assert n == 3 and kept.energy.tolist() == [2.0, 0.0]
    # threshold rows are never kept on their energy
    th = _threshold_rows([False], [np.nan]).assign(energy=0.0, affine_energy=1.0)
    assert keep_decided(th, energy=True)[1] == 1


def test_fig2_means_energies_over_bracketed_rows_and_p_over_decided_ones(monkeypatch):
    """Fig. 2's mean energy at a point includes an undecided sample whose energy is bracketed
    near zero (at E = 0); P, Gamma and the taut cables there do not; both counts travel in the
    result."""
    rows = []
    for k in range(1, 5):
        for p_r in (0.5, 0.6):
            undecided = k == 4 and p_r == 0.6
            rigid = p_r == 0.6 and not undecided
            rows.append(
                {
                    "sample": k, "p_r": p_r, "p_t": 0.0, "phi": math.pi, "f_c": 1.0,
                    "decided": not undecided, "rigid": rigid,
                    "energy": 3.0 if rigid else (1e-14 if undecided else 0.0),
                    "energy_lower": 3.0 if rigid else 0.0, "affine_energy": 10.0,
                    "nonaffinity": np.nan if undecided else 2.0, "nonaffinity_lower": np.nan,
                    "min_norm_ok": not undecided, "frac_cables_taut": 0.4 if rigid else np.nan,
                }
            )  # fmt: skip
    frame = pd.DataFrame(rows)

    thresholds = pd.DataFrame(
        {"sample": range(1, 5), "p_t": 0.0, "phi": math.pi, "threshold_p_r": 0.55}
    )
    # the rows Fig. 2 reads: one grid (p_t = 0) and its thresholds, no field sweeps
    sweeps = {"fig2_pt0.0": keep_decided(frame, True), "fig2_thresholds": (thresholds, 0)}
    r = fig2.analyse(sweeps, TINY)
    at = r.curves.set_index("p_r").loc[0.6]  # three rigid samples at E = 3, one at E ~ 0
    assert at.energy == pytest.approx(2.25) and at.energy_n == 4 and at.N == 3 and at.P == 1
    assert r.bracketed == {"fig2_pt0.0": 1} and r.excluded["fig2_pt0.0"] == 1
    assert len(r.rows) == 7


def test_the_report_counts_the_bracketed_rows():
    results = {
        "a": SimpleNamespace(excluded={"x": 3, "y": 1}, bracketed={"x": 2, "y": 0}, straddling=1),
        "b": SimpleNamespace(excluded={}, bracketed={}, straddling=None),
    }
    assert bracketed_rows(results) == {"x": 2, "y": 0}
    values = report.numbers(results, [], "tiny", {}, {}, pd.DataFrame())
    assert (values["excluded"], values["bracketed"], values["straddling"]) == (4, 2, "a: 1")
    assert values["energy_bracketed"] == 1e-9
    assert _excluded(results).to_dict("list") == {
        "sweep": ["x", "y"],
        "excluded": [3, 1],
        "still": [2, 0],
    }
    none = {"a": SimpleNamespace(excluded={"y": 1}, bracketed={"y": 0}, straddling=None)}
    values = report.numbers(none, [], "tiny", {}, {}, pd.DataFrame())
    assert values["bracketed"] is None and values["straddling"] is None


def test_threshold_interval_keeps_undecided_samples():
    rows = _threshold_rows(
        [True, False, False, False],
        [0.6, 0.63, np.nan, np.nan],
        lo=[0.6, 0.62, 0.64, np.nan],
        hi=[0.6, 0.64, 0.66, np.nan],
    )
    kept, n = keep_decided(rows)
    # the last has no finite interval: dropped; the third is kept at its interval's midpoint
    assert n == 1 and list(kept["sample"]) == [1, 2, 3]
    assert kept.threshold_p_r.tolist() == pytest.approx([0.6, 0.63, 0.65])
    # only intervals of positive width straddle a grid value
    assert interval_straddles(kept, [0.6, 0.65]) == 1
    assert interval_straddles(kept, [0.5, 0.7]) == 0
    assert interval_straddles(_threshold_rows([True], [0.6], [0.6], [0.6]), [0.6]) == 0
    # rows written before the interval columns existed: not recorded, not zero
    assert interval_straddles(_threshold_rows([True], [0.6]), [0.6]) is None


def test_strain_names_come_from_the_model():
    for name, phi in NAMED_STRAINS.items():
        assert strain_name(phi) == name
    assert strain_name(math.pi / 4) == "0.785"


@pytest.fixture(scope="module")
def mini(tiny_results):
    """The studies on the session's tiny reproduction."""
    return tiny_results


def test_results_are_frozen_dataclasses_that_carry_their_exclusions(mini):
    for name, r in mini.items():
        assert dataclasses.is_dataclass(r), name
        with pytest.raises(dataclasses.FrozenInstanceError):
            r.excluded = {}
        assert all(isinstance(v, int) for v in r.excluded.values())
    total = excluded_samples(mini)
    assert set(total) >= {"fig1b", "fig1c_rods", "fig1c_mixed", "fig2_thresholds", "fig4_centre"}


def test_drawn_samples_come_from_the_sweeps_and_are_solved(mini):
    field = mini["fig2"].field
    assert field.instance is not None and field.result.rigid
    assert field.p_t == FIELD_P_T
    assert field.mixed_result is not None and field.mixed_result.rigid
    assert field.instance.network.n_nodes == max(TINY["fig2"].n, 8) ** 2


def test_every_claim_names_its_source():
    assert all(c.source and c.text and c.paper for c in CLAIMS.values())


# --------------------------------------------------------------------------- heavy tails


def test_rows_without_minimum_norm_displacements_lose_their_nonaffinity():
    rows = pd.DataFrame({"nonaffinity": [1.0, 2.0, 3.0], "energy": [0.0, 1.0, 2.0]})
    same, count = nonaffinity.mask_min_norm(rows)
    assert count is None and same.nonaffinity.tolist() == [1.0, 2.0, 3.0]
    rows["min_norm_ok"] = [True, False, None]  # None: a part written before the column
    masked, count = nonaffinity.mask_min_norm(rows)
    assert count == 1
    assert np.isnan(masked.nonaffinity[1]) and masked.nonaffinity[[0, 2]].tolist() == [1.0, 3.0]
    assert masked.energy.tolist() == [0.0, 1.0, 2.0]


def test_rigid_rows_without_certified_tensions_lose_their_taut_fractions():
    """A rigid row whose relaxed energy is not within the energy gap of its lower bound has
    tensions that need not be t*: its taut fractions become NaN (counted); certified rigid
    rows and floppy rows keep theirs, and rows without ``energy_lower`` are left alone."""
    rows = pd.DataFrame(
        {
            "rigid": [True, True, False, True],
            "energy": [1.0, 1.0, 0.0, 2.0],
            "frac_cables_taut": [0.3, 0.5, 0.0, 0.4],
            "frac_struts_taut": [0.2, 0.6, 0.0, 0.1],
        }
    )
    same, count = nonaffinity.mask_uncertified_tensions(rows)
    assert count is None and same.frac_cables_taut.tolist() == [0.3, 0.5, 0.0, 0.4]
    rows["energy_lower"] = [1.0 - 1e-12, 0.9, 0.0, 2.0]
    masked, count = nonaffinity.mask_uncertified_tensions(rows)
    assert count == 1
    assert np.isnan(masked.frac_cables_taut[1]) and np.isnan(masked.frac_struts_taut[1])
    assert masked.frac_cables_taut[[0, 2, 3]].tolist() == [0.3, 0.0, 0.4]
    assert masked.energy.tolist() == rows.energy.tolist()


def test_tail_statistics_show_what_the_mean_hangs_on():
    at = pd.DataFrame(
        {
            "p_t": 0.2,
            "p_r": 0.55,
            "sample": range(1, 6),
            "nonaffinity": [1.0, 2.0, 3.0, 4.0, 990.0],
            "energy": [0.0, 0.0, 1.0, 1.0, 2.0],
            "rigid": [False, False, True, True, True],
        }
    )
    t = nonaffinity.tail_statistics(at)
    g = t[t.observable == "Gamma"].iloc[0]
    assert g["mean"] == 200.0 and g["median"] == 3.0 and g["top_share"] == 0.99
    assert g["mean_without_top"] == 2.5 and (g["q25"], g["q75"]) == (2.0, 4.0)
    assert nonaffinity.worst_tail(t)["top_share"] == 0.99


def test_fig2_gives_quantiles_beside_the_mean(mini):
    r = mini["fig2"]
    c = r.curves
    for stat in ("median", "q25", "q75"):
        assert f"gamma_{stat}" in c and f"energy_{stat}" in c
    ok = c.gamma_n > 0
    assert (c.gamma_q25[ok] <= c.gamma_median[ok] + 1e-12).all()
    assert (c.gamma_median[ok] <= c.gamma_q75[ok] + 1e-12).all()
    assert r.min_norm_failed is None or r.min_norm_failed >= 0
    assert set(r.at_pcrit.p_t) <= set(rows.PT4) and len(r.tails)


def test_samples_known_only_from_below_bracket_the_median_nonaffinity():
    """Rows whose projection stalled keep a certified lower bound on Gamma
    (``nonaffinity_lower``): the median over every sample is bracketed between the median with
    them at their bounds and at infinity, and the section quotes the widest bracket; rows
    written before the bound existed count such samples at 0."""
    grid = pd.DataFrame(
        {
            "phi": math.pi,
            "p_t": 0.2,
            "p_r": [0.5] * 4 + [0.6] * 3,
            "nonaffinity": [1.0, 2.0, 3.0, np.nan, 4.0, np.nan, np.nan],
            "nonaffinity_lower": [1.0, 2.0, 3.0, 50.0, 4.0, 60.0, np.nan],
        }
    )
    b = nonaffinity.gamma_median_brackets(grid).set_index("p_r")
    assert b.loc[0.5, "gamma_median_low"] == 2.5 and b.loc[0.5, "gamma_median_high"] == 2.5
    assert b.loc[0.6, "gamma_median_low"] == 4.0 and np.isinf(b.loc[0.6, "gamma_median_high"])
    assert b.gamma_bounded.tolist() == [1, 1]
    curves = b.reset_index().assign(gamma_median=[2.0, 4.0], phi=math.pi)

    def numbers(c):
        return fig2.numbers(SimpleNamespace(
            curves=c, worst_tail=None, min_norm_failed=0, tensions_uncertified=0, n=5, samples=4,
            field=SimpleNamespace(p_r=0.6),
        ))  # fmt: skip

    v = numbers(curves)
    assert (v["bounded"], v["agree"], v["points"]) == (2, 1, 2)
    assert (v["widest_low"], v["widest_high"], v["widest_p_r"]) == ("4", "inf", 0.6)
    old = nonaffinity.gamma_median_brackets(grid.drop(columns="nonaffinity_lower")).set_index("p_r")
    assert old.loc[0.5, "gamma_median_low"] == 1.5 and old.gamma_bounded.tolist() == [0, 0]
    v = numbers(old.reset_index().assign(gamma_median=[2.0, 4.0], phi=math.pi))
    assert v["bounded"] is None and v["widest_low"] is None


def test_scales_are_keyword_only_and_seed_each_estimator_on_its_own_stream():
    with pytest.raises(TypeError):
        Scale("paper", {}, ())  # type: ignore[misc]
    scale = Scale(name="x", bootstrap=5)
    assert scale.bootstrap == 5 and scale.studies == ()
    # a fresh generator per call, the same draws each time, one stream per estimator
    a = scale.rng("collapse").integers(0, 1000, 8)
    assert np.array_equal(a, scale.rng("collapse").integers(0, 1000, 8))
    assert not np.array_equal(a, scale.rng("contour").integers(0, 1000, 8))
    shifted = dataclasses.replace(scale, bootstrap_seed=100)
    assert not np.array_equal(a, shifted.rng("collapse").integers(0, 1000, 8))
    with pytest.raises(KeyError):
        scale.rng("no such estimator")


def test_every_study_is_one_registered_plug_in_with_its_template():
    """Each study: its callables, its parameters at the scales that run it (a scale runs exactly
    the studies that give parameters for it) and its template, every label it asks for there."""
    assert [s.name for s in REGISTRY] == list(STUDIES)
    for s in REGISTRY:
        for fn in ("sweeps", "analyse", "claims", "cost", "numbers", "figures", "tables"):
            assert callable(getattr(s, fn)), (s.name, fn)
        assert isinstance(s.sweeps(TINY), dict) and s.template.name == s.name
        assert {n for n, sc in SCALES.items() if s.name in sc.studies} == set(s.params)
    assert not hasattr(studies, "MODULES")


def test_undecided_verdicts_are_counted_by_kind_for_every_sweep(tmp_path):
    """A search of the affine stage alone leaves near-threshold probes and grid rows undecided,
    every one not resolved; the table counts them per sweep, probes for threshold sweeps and
    rows for grid sweeps."""
    import tomllib

    from tensegrity_rigidity.ensemble.spec import parse_spec
    from tensegrity_rigidity.ensemble.sweep import load_results, run_sweep
    from tensegrity_rigidity.paper.studies.rows import undecided_by_kind

    base = 'n = 6\np_t = 0.3\nf_c = 0.5\nphi = "shear"\nsamples = 4\nseed = 9\n'
    base += '[solver]\nstages = ["affine"]\nmin_norm = false\n'
    specs = {"thresholds": base + '[threshold]\npath = "p_r"\n', "grid": "p_r = 0.4\n" + base}
    for name, text in specs.items():
        run_sweep(
            parse_spec(tomllib.loads(text)), tmp_path / name, executor="serial", progress=False
        )
    table = undecided_by_kind(tmp_path).set_index("sweep")
    probes = int(load_results(tmp_path / "thresholds").threshold_undecided.sum())
    assert probes > 0 and table.loc["thresholds", "undecided"] == probes
    assert table.loc["thresholds", "counted"] == "probes"
    rows = load_results(tmp_path / "grid")
    assert table.loc["grid", "undecided"] == int((~rows.decided).sum()) > 0
    for sweep in ("thresholds", "grid"):
        assert table.loc[sweep, "not_resolved"] == table.loc[sweep, "undecided"]
        assert table.loc[sweep, "within"] == 0
