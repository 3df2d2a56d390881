"""The paper's studies as sweep specs plus their analysis.

Each study is a set of sweep specs (run by :func:`tensegrity_rigidity.ensemble.sweep.run_sweep` into
``DIR/studies/<name>``, so an interrupted reproduction resumes) and a function that turns the
rows into the numbers the figures and the comparison table need. Sizes and sample counts come
from a :class:`Scale`.

Estimators (documented in :mod:`~tensegrity_rigidity.analysis.estimators`):

* S_t/S_r (Fig. 1C): binomial-likelihood fit of P = F(p_r + lam p_t) to per-sample thresholds
  along p_r at p_t in {0, 0.1, 0.2, 0.3}; bootstrap errors over samples. The strain average
  pools the samples of five strains phi in {0, pi/4, pi/2, 3pi/4, pi}.
* S_r, S_t, dP/df_c (Fig. 4): paired central differences on common random numbers at
  (p_r, p_t) = (0.3, 0.6), with steps matched in x = p_r + p_t/2 (h_r = 0.025, h_t = 0.05) and
  the strain average over phi in {0, pi/4, pi/2, 3pi/4, pi};
  S_c = S_t + (1 - f_c) dP/df_c / p_t and S_s = S_t - f_c dP/df_c / p_t
  (from S_t = f_c S_c + (1 - f_c) S_s and dP/df_c = p_t (S_c - S_s)).
* p_crit (Fig. 2): the median per-sample threshold (P = 1/2), bootstrap error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis import estimators as an
from ..analysis.single_node import simulate_single_node, single_node_probability
from ..ensemble.spec import parse_spec
from ..ensemble.sweep import load_results, run_sweep

PHI5 = [0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4, math.pi]
FC5 = [0.0, 0.25, 0.5, 0.75, 1.0]
PT4 = [0.0, 0.1, 0.2, 0.3]


@dataclass(frozen=True)
class Scale:
    """System sizes and sample counts of a reproduction."""

    name: str
    n_threshold: int  # lattice size of threshold studies (Figs. 1, 2 p_crit)
    n_grid: int  # lattice size of grid studies (Figs. 2, 4)
    samples_threshold: int
    samples_grid: int
    samples_fig4: int
    p_r_step: float
    node_trials: int
    bootstrap: int


SCALES = {
    "tiny": Scale("tiny", 5, 5, 6, 4, 6, 0.1, 300, 10),
    "quick": Scale("quick", 12, 12, 48, 24, 96, 0.05, 4000, 100),
    "paper": Scale("paper", 32, 32, 400, 100, 800, 0.025, 40000, 200),
}


#: samples excluded because a verdict was below double-precision resolution, per study
UNDECIDED: dict[str, int] = {}


def _run(out: Path, name: str, spec: dict, workers, scheduler, progress) -> pd.DataFrame:
    """Run (or resume) one sweep; drop and count undecided samples."""
    path = out / "studies" / name
    run_sweep(parse_spec(spec), path, executor=workers, scheduler=scheduler, progress=progress)
    df = load_results(path)
    bad = ~df["decided"].astype(bool)
    UNDECIDED[name] = int(bad.sum())
    return df[~bad].reset_index(drop=True)


def _p_r_grid(step: float, lo: float = 0.2, hi: float = 0.95) -> list[float]:
    return [round(x, 6) for x in np.arange(lo, hi + 1e-9, step)]


# --------------------------------------------------------------------------- Fig. 1


def study_fig1b(out, scale: Scale, **kw) -> dict:
    """P(p_r, p_t) at f_c = 0.5 under shear, from per-sample thresholds along p_r."""
    p_t = [round(x, 3) for x in np.arange(0.0, 0.81, 0.1)]
    df = _run(
        out,
        "fig1b",
        {
            "n": scale.n_threshold,
            "p_t": p_t,
            "f_c": 0.5,
            "phi": "shear",
            "samples": scale.samples_threshold,
            "seed": 11,
            "threshold": {"path": "p_r"},
        },
        **kw,
    )
    p_r = np.linspace(0, 1, 101)
    P = np.full((len(p_t), p_r.size), np.nan)
    for i, pt in enumerate(p_t):
        t = df[np.isclose(df.p_t, pt)].threshold_p_r.to_numpy()
        ok = p_r + pt <= 1 + 1e-12
        P[i, ok] = an.probability_from_thresholds(t, p_r[ok])
    return {
        "p_r": p_r,
        "p_t": np.array(p_t),
        "P": P,
        "rows": df,
        "n": scale.n_threshold,
        "samples": scale.samples_threshold,
    }


def study_fig1c(out, scale: Scale, **kw) -> dict:
    """S_t/S_r versus f_c for each strain and the strain average (collapse fits)."""
    df = _run(
        out,
        "fig1c",
        {
            "n": scale.n_threshold,
            "p_t": PT4,
            "f_c": FC5,
            "phi": PHI5,
            "samples": scale.samples_threshold,
            "seed": 12,
            "threshold": {"path": "p_r"},
        },
        **kw,
    )
    grid = np.arange(0.3, 0.9001, 0.01)
    fits = []
    for f_c in FC5:
        pooled = []
        for phi in PHI5:
            sub = df[np.isclose(df.f_c, f_c) & np.isclose(df.phi, phi)]
            y, pr, pt = an.outcomes_from_thresholds(sub, grid)
            pooled.append(y)
            if phi in (0.0, math.pi / 2, math.pi):
                fit = an.fit_collapse(y, pr, pt, n_boot=scale.bootstrap)
                fits.append({"f_c": f_c, "strain": _strain_name(phi), "phi": phi, **fit.__dict__})
        fit = an.fit_collapse(np.vstack(pooled), pr, pt, n_boot=scale.bootstrap)
        fits.append({"f_c": f_c, "strain": "average", "phi": np.nan, **fit.__dict__})
    rods_only = df[np.isclose(df.p_t, 0.0)].drop_duplicates(["phi", "sample"])
    return {
        "fits": pd.DataFrame(fits),
        "rows": df,
        "n": scale.n_threshold,
        "samples": scale.samples_threshold,
        "rods_only_pc": an.critical_point(rods_only.threshold_p_r.to_numpy()),
        "rods_only_samples": len(rods_only),
    }


def _strain_name(phi: float) -> str:
    return {0.0: "dilation", math.pi / 2: "shear", math.pi: "compression"}.get(phi, f"{phi:.3f}")


# --------------------------------------------------------------------------- Fig. 2


def study_fig2(out, scale: Scale, **kw) -> dict:
    """Rods + cables (f_c = 1): nonaffinity, energies and engaged cables versus p_r."""
    p_r = _p_r_grid(scale.p_r_step, 0.3, 0.95)
    grids = []
    for p_t in PT4:
        pr = [p for p in p_r if p + p_t <= 1 + 1e-12]
        grids.append(
            _run(
                out,
                f"fig2_pt{p_t:.1f}",
                {
                    "n": scale.n_grid,
                    "p_r": pr,
                    "p_t": p_t,
                    "f_c": 1.0,
                    "phi": ["compression", "dilation"],
                    "samples": scale.samples_grid,
                    "seed": 21,
                },
                **kw,
            )
        )
    rows = pd.concat(grids, ignore_index=True)
    th = _run(
        out,
        "fig2_thresholds",
        {
            "n": scale.n_grid,
            "p_t": PT4,
            "f_c": 1.0,
            "phi": ["compression", "dilation"],
            "samples": scale.samples_threshold,
            "seed": 21,
            "threshold": {"path": "p_r"},
        },
        **kw,
    )
    curves = (
        rows.groupby(["phi", "p_t", "p_r"])
        .agg(
            energy=("energy", "mean"),
            energy_sem=("energy", "sem"),
            gamma=("nonaffinity", "mean"),
            gamma_sem=("nonaffinity", "sem"),
            P=("rigid", "mean"),
            N=("rigid", "size"),
        )
        .reset_index()
    )
    taut = (
        rows[rows.rigid]
        .groupby(["phi", "p_t", "p_r"])
        .frac_cables_taut.agg(["mean", "sem", "size"])
        .reset_index()
    )
    fits, crit = [], []
    for (phi, p_t), sub in curves.groupby(["phi", "p_t"]):
        tsub = th[np.isclose(th.phi, phi) & np.isclose(th.p_t, p_t)].threshold_p_r.to_numpy()
        pc, pc_err = an.critical_point(tsub)
        fit = an.fit_energy_power_law(sub.p_r.to_numpy(), sub.energy.to_numpy(), pc)
        fits.append(
            {
                "phi": phi,
                "strain": _strain_name(phi),
                "p_t": p_t,
                "p_crit_err": pc_err,
                **fit.__dict__,
            }
        )
        g = sub.set_index("p_r").gamma
        crit.append({"phi": phi, "p_t": p_t, "p_crit": pc, "gamma_peak_p_r": float(g.idxmax())})
    return {
        "curves": curves,
        "taut": taut,
        "fits": pd.DataFrame(fits),
        "crit": pd.DataFrame(crit),
        "rows": rows,
        "n": scale.n_grid,
        "samples": scale.samples_grid,
        "field": _displacement_field(scale),
    }


def _displacement_field(scale: Scale) -> dict:
    """One rods + cables sample under compression near its threshold (Fig. 2A, 1A)."""
    from ..ensemble.thresholds import find_threshold
    from ..model.elements import place_elements
    from ..model.network import Instance
    from ..model.sampling import lattice_geometry
    from ..model.strain import strain_tensor
    from ..solver.core import solve

    n = max(scale.n_grid, 8)
    for seed in range(50):
        rng = np.random.default_rng(1000 + seed)
        net, u, v = lattice_geometry(n, 0.2, rng)
        eps = strain_tensor("compression")
        th = find_threshold(net, u, v, eps, 0.2, 1.0)
        if np.isfinite(th.s) and th.s > 0:
            p_r = min(th.s + 0.02, 0.8)
            inst = Instance(net.with_kinds(place_elements(u, v, p_r, 0.2, 1.0)), eps)
            res = solve(inst)
            if res.rigid:
                break
    # a mixed sample for Fig. 1A: rods, cables and struts, rigid under shear
    for seed in range(50):
        rng = np.random.default_rng(2000 + seed)
        net2, u2, v2 = lattice_geometry(n, 0.2, rng)
        inst2 = Instance(
            net2.with_kinds(place_elements(u2, v2, 0.55, 0.4, 0.5)), strain_tensor("shear")
        )
        res2 = solve(inst2)
        if res2.rigid:
            break
    return {
        "instance": inst,
        "result": res,
        "p_r": p_r,
        "p_t": 0.2,
        "mixed_instance": inst2,
        "mixed_result": res2,
    }


# --------------------------------------------------------------------------- Fig. 3


def study_fig3(out, scale: Scale, **kw) -> dict:
    """Single node: analytic P_N versus f_c, and simulation with Wilson intervals."""
    rng = np.random.default_rng(31)
    f_c = np.linspace(0, 1, 41)
    p_rs = [0.1, 0.3, 0.5, 0.7]
    analytic = {
        p: np.array([single_node_probability(p, f * (1 - p), (1 - f) * (1 - p)) for f in f_c])
        for p in p_rs
    }
    sim = []
    for p in p_rs:
        for f in np.linspace(0, 1, 9):
            k, n = simulate_single_node(p, f * (1 - p), (1 - f) * (1 - p), scale.node_trials, rng)
            P, lo, hi = an.wilson(k, n)
            sim.append(
                {
                    "p_r": p,
                    "f_c": f,
                    "P": float(P),
                    "lo": float(lo),
                    "hi": float(hi),
                    "analytic": single_node_probability(p, f * (1 - p), (1 - f) * (1 - p)),
                }
            )
    return {"f_c": f_c, "analytic": analytic, "sim": pd.DataFrame(sim), "trials": scale.node_trials}


# --------------------------------------------------------------------------- Fig. 4

FIG4_PHI = PHI5
FIG4_FC = [i / 8 for i in range(9)]
#: steps of the central differences, matched in the mean-field variable x = p_r + p_t / 2 (both
#: move x by +-0.025): near the edge of the transition P is strongly curved and a secant is
#: steeper the wider it is, so unmatched spans would bias S_t / S_r.
H_R, H_T = 0.025, 0.05


def study_fig4(out, scale: Scale, **kw) -> dict:
    """P versus f_c at (p_r, p_t) = (0.3, 0.6) and the efficacies S_c, S_s from paired
    differences on common random numbers."""
    base = {
        "n": scale.n_grid,
        "f_c": FIG4_FC,
        "phi": FIG4_PHI,
        "samples": scale.samples_fig4,
        "seed": 41,
    }
    centre = _run(out, "fig4_centre", base | {"p_r": 0.3, "p_t": 0.6}, **kw)
    d_r = _run(out, "fig4_dpr", base | {"p_r": [0.3 - H_R, 0.3 + H_R], "p_t": 0.6}, **kw)
    d_t = _run(out, "fig4_dpt", base | {"p_r": 0.3, "p_t": [0.6 - H_T, 0.6 + H_T]}, **kw)

    samples = np.arange(1, scale.samples_fig4 + 1)

    def outcomes(df, **sel):
        """Rigidity per sample index (nan where the sample was undecided and dropped)."""
        m = np.ones(len(df), bool)
        for key, val in sel.items():
            m &= np.isclose(df[key], val)
        return df[m].set_index("sample").rigid.astype(float).reindex(samples).to_numpy()

    per_phi = []
    for phi in FIG4_PHI:
        for i, f in enumerate(FIG4_FC):
            S_r = an.paired_derivative(
                outcomes(d_r, phi=phi, f_c=f, p_r=0.3 - H_R),
                outcomes(d_r, phi=phi, f_c=f, p_r=0.3 + H_R),
                H_R,
            )
            S_t = an.paired_derivative(
                outcomes(d_t, phi=phi, f_c=f, p_t=0.6 - H_T),
                outcomes(d_t, phi=phi, f_c=f, p_t=0.6 + H_T),
                H_T,
            )
            # dP/df_c: central difference inside, second-order one-sided at f_c = 0 and 1
            last = len(FIG4_FC) - 1
            if 0 < i < last:
                coef = {i - 1: -1.0, i + 1: 1.0}
                step = FIG4_FC[i + 1] - FIG4_FC[i - 1]
            else:
                j = (1, 2) if i == 0 else (last - 1, last - 2)
                sign = 1.0 if i == 0 else -1.0
                coef = {i: -3.0 * sign, j[0]: 4.0 * sign, j[1]: -1.0 * sign}
                step = 2 * abs(FIG4_FC[j[0]] - FIG4_FC[i])
            diff = sum(c * outcomes(centre, phi=phi, f_c=FIG4_FC[k]) for k, c in coef.items())
            diff = diff[np.isfinite(diff)]
            D_f = float(diff.mean() / step)
            D_f_err = float(diff.std(ddof=1) / np.sqrt(diff.size) / step)
            P = outcomes(centre, phi=phi, f_c=f)
            P = P[np.isfinite(P)]
            per_phi.append(
                {
                    "phi": phi,
                    "f_c": f,
                    "P": P.mean(),
                    "N": P.size,
                    "S_r": S_r.value,
                    "S_r_err": S_r.err,
                    "S_t": S_t.value,
                    "S_t_err": S_t.err,
                    "D_f": D_f,
                    "D_f_err": D_f_err,
                }
            )
    per_phi = pd.DataFrame(per_phi)
    p_t = 0.6
    per_phi["S_c"] = per_phi.S_t + (1 - per_phi.f_c) * per_phi.D_f / p_t
    per_phi["S_s"] = per_phi.S_t - per_phi.f_c * per_phi.D_f / p_t

    def summarise(frame):
        # average the derivatives over strains, then take ratios to S_r
        g = frame.groupby("f_c")
        out_rows = []
        for f, sub in g:
            k = len(sub)
            S_r, S_r_e = sub.S_r.mean(), np.sqrt((sub.S_r_err**2).sum()) / k
            S_t, S_t_e = sub.S_t.mean(), np.sqrt((sub.S_t_err**2).sum()) / k
            D, D_e = sub.D_f.mean(), np.sqrt((sub.D_f_err**2).sum()) / k
            S_c, S_s = S_t + (1 - f) * D / p_t, S_t - f * D / p_t
            S_c_e = np.hypot(S_t_e, (1 - f) * D_e / p_t)
            S_s_e = np.hypot(S_t_e, f * D_e / p_t)
            rc, rs = S_c / S_r, S_s / S_r
            out_rows.append(
                {
                    "f_c": f,
                    "S_r": S_r,
                    "S_c_rel": rc,
                    "S_s_rel": rs,
                    "S_c_rel_err": abs(rc) * np.hypot(S_c_e / S_c if S_c else 0, S_r_e / S_r),
                    "S_s_rel_err": abs(rs) * np.hypot(S_s_e / S_s if S_s else 0, S_r_e / S_r),
                    "sum_rel": (S_c + S_s) / S_r,
                    "sum_rel_err": abs((S_c + S_s) / S_r)
                    * np.hypot(
                        np.hypot(S_c_e, S_s_e) / abs(S_c + S_s) if S_c + S_s else 0, S_r_e / S_r
                    ),
                }
            )
        return pd.DataFrame(out_rows)

    average = summarise(per_phi)
    dil = summarise(per_phi[np.isclose(per_phi.phi, 0.0)])
    comp = summarise(per_phi[np.isclose(per_phi.phi, math.pi)])
    return {
        "per_phi": per_phi,
        "average": average,
        "dilation": dil,
        "compression": comp,
        "n": scale.n_grid,
        "samples": scale.samples_fig4,
    }


STUDIES = {
    "fig1b": study_fig1b,
    "fig1c": study_fig1c,
    "fig2": study_fig2,
    "fig3": study_fig3,
    "fig4": study_fig4,
}
