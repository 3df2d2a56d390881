"""The paper's method beside ours: both verdicts on the same samples near the transition.

The paper decided each sample with a local minimiser and "energy greater than 0"
(:mod:`tensegrity_rigidity.ensemble.inexact` does so with L-BFGS-B and a relative threshold).
The same grid (rods + cables, compression and dilation, p_t = 0 to 0.3, p_r = 0.40 to 0.80) is
run twice on identical samples, with the certified verdict and with the paper's (sweep key
``verdict = "paper"``). The study counts how often the verdicts differ (overall and where the
exact P lies between 0.1 and 0.9, at the paper's threshold and 100x above and below it) and how
each claim it can measure moves: the shift (paper's way minus ours, same estimator, same
samples, paired bootstrap) is the comparison's evidence for the factor "method".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from ...analysis import estimators as an
from ...ensemble.inexact import PAPER_THRESHOLD
from ..claims import CLAIMS, Measurement
from ..comparison import fmt
from ..study import Result, Scale, Study
from ..template import load
from .rows import PT4, Rows, p_r_grid, strain_name

NAME = "method"
T = load(NAME)
#: thresholds (relative to the affine energy) at which the paper's verdict is also read
THRESHOLDS = (1e-6, PAPER_THRESHOLD, 1e-10)
P_R_RANGE = (0.40, 0.80)
KEYS = ["phi", "p_t", "p_r", "sample"]


@dataclass(frozen=True, kw_only=True)
class Params:
    n: int = 5  # lattice size
    samples: int = 4  # samples per point
    step: float = 0.1  # p_r grid step


PARAMS = {"tiny": Params(), "quick": Params(n=12, samples=16, step=0.05),
          "paper": Params(n=32, samples=16, step=0.025)}  # fmt: skip


@dataclass(frozen=True, eq=False)
class MethodResult(Result):
    """``rows``: per sample and grid point both verdicts (``rigid``, ``paper_rigid`` at
    :data:`~tensegrity_rigidity.ensemble.inexact.PAPER_THRESHOLD`), ``energy`` (E*),
    ``paper_energy`` (where L-BFGS-B stopped), ``affine_energy``, ``iterations``,
    ``converged``; ``disagreement``: :func:`_disagreement`; ``claims``: per claim the value
    with exact verdicts, with the paper's and the shift, with paired bootstrap errors;
    ``iterations``: median and largest L-BFGS-B count, and the runs that stopped at its
    iteration limit (``not_converged``)."""

    rows: pd.DataFrame
    disagreement: pd.DataFrame
    claims: pd.DataFrame
    iterations: dict
    threshold: float
    n: int
    samples: int


def sweeps(scale: Scale) -> dict[str, dict]:
    """Per p_t the same grid with the exact and with the paper's verdict."""
    p = scale[NAME]
    out = {}
    for p_t in PT4:
        spec = {"n": p.n, "p_r": [x for x in p_r_grid(p.step, *P_R_RANGE) if x + p_t <= 1 + 1e-12],
                "p_t": p_t, "f_c": 1.0, "phi": ["compression", "dilation"],
                "samples": p.samples, "seed": 51}  # fmt: skip
        out[f"method_exact_pt{p_t:.1f}"] = spec
        out[f"method_paper_pt{p_t:.1f}"] = spec | {"verdict": "paper"}
    return out


def analyse(rows: Rows, scale: Scale) -> MethodResult:
    """Both verdicts of the rows of :func:`sweeps`, compared sample by sample."""
    excluded, parts = {}, []
    for p_t in PT4:
        exact, excluded[f"method_exact_pt{p_t:.1f}"] = rows[f"method_exact_pt{p_t:.1f}"]
        paper, _ = rows[f"method_paper_pt{p_t:.1f}"]
        paper = paper[[*KEYS, "rigid", "energy", "iterations", "converged"]]
        parts.append(
            exact[[*KEYS, "rigid", "energy", "affine_energy"]].merge(
                paper.rename(columns={"rigid": "paper_rigid", "energy": "paper_energy"}), on=KEYS
            )
        )
    both = pd.concat(parts, ignore_index=True)
    both["rigid"], both["paper_rigid"] = both.rigid.astype(bool), both.paper_rigid.astype(bool)
    shifts, p = _claims(both, scale), scale[NAME]
    it = {"median": float(both.iterations.median()), "max": int(both.iterations.max()),
          "not_converged": int((~both.converged.astype(bool)).sum())}  # fmt: skip
    # percentiles need many replicas, and these cost microseconds: at least 1000
    dis = _disagreement(both, max(scale.bootstrap, 1000), scale)
    return MethodResult(rows=both, disagreement=dis, claims=shifts, iterations=it,
                        threshold=PAPER_THRESHOLD, n=p.n, samples=p.samples, excluded=excluded,
                        measured=_measurements(shifts, scale))  # fmt: skip


def _disagreement(rows: pd.DataFrame, n_boot: int, scale: Scale) -> pd.DataFrame:
    """How often the verdicts differ, per threshold and region ("all", "0.1 <= P <= 0.9", P
    the exact rigidity probability of the grid point).

    Per row: ``samples`` (verdicts) and ``units`` (distinct samples), ``differ`` and
    ``fraction``, a 95 % interval (``lo``, ``hi``) that resamples whole samples (one sample's
    verdicts at many grid points are correlated: :func:`_cluster_interval`, ``interval_note``
    says where it is not the percentile one), the row-wise Wilson interval for comparison only
    (``wilson_lo``, ``wilson_hi``; too narrow), and the two directions. Every (threshold,
    region) restarts the ``disagreement`` stream, so the same rows give the same numbers.
    """
    P = rows.groupby(["phi", "p_t", "p_r"]).rigid.transform("mean")
    regions = {"all": np.ones(len(rows), bool), "0.1 <= P <= 0.9": ((P >= 0.1) & (P <= 0.9))}
    sample, out = rows["sample"].to_numpy(), []
    for tau in THRESHOLDS:
        paper = rows.paper_energy > tau * rows.affine_energy
        for region, m in regions.items():
            m = np.asarray(m, bool)
            exact_r, paper_r = rows.rigid.to_numpy()[m], paper.to_numpy()[m]
            wrong = exact_r != paper_r
            differ = int(wrong.sum())
            _, w_lo, w_hi = an.wilson(differ, m.sum())
            lo, hi, note, units = _cluster_interval(wrong, sample[m], n_boot,
                                                    scale.rng("disagreement"))  # fmt: skip
            out.append({
                "threshold": tau, "region": region, "samples": int(m.sum()), "units": units,
                "differ": differ, "fraction": differ / m.sum() if m.sum() else np.nan,
                "lo": lo, "hi": hi, "wilson_lo": float(w_lo), "wilson_hi": float(w_hi),
                "interval_note": note, "exact_rigid_paper_floppy": int((exact_r & ~paper_r).sum()),
                "exact_floppy_paper_rigid": int((~exact_r & paper_r).sum()),
            })  # fmt: skip
    return pd.DataFrame(out)


def _cluster_interval(wrong: np.ndarray, unit: np.ndarray, n_boot: int,
                      rng: np.random.Generator) -> tuple[float, float, str, int]:  # fmt: skip
    """95 % interval of ``wrong.mean()`` resampling whole units: (lo, hi, note, units).

    A replica draws the units with replacement and pools all their rows (sum of differing rows
    over sum of rows); the interval is its 2.5 and 97.5 percentiles. Where they cannot be read:
    no unit, NaN; one unit, [0, 1]; no verdict differs, [0, 1 - 0.05^(1/U)], the exact one-sided
    95 % bound on the share of samples with a difference (the rule of three counted in samples,
    a bound on the share of rows too); every verdict differs, its mirror image.
    """
    units = an.n_units(wrong.size, unit)
    if units == 0:
        return np.nan, np.nan, T.label("none"), 0
    if units == 1:
        return 0.0, 1.0, T.label("one"), 1
    differ = int(wrong.sum())
    if differ == 0:
        return 0.0, 1 - 0.05 ** (1 / units), T.label("no_difference", units=units), units
    if differ == wrong.size:
        return 0.05 ** (1 / units), 1.0, T.label("all_differ", units=units), units
    _, inverse = np.unique(unit, return_inverse=True)
    d = np.bincount(inverse, weights=wrong.astype(float))
    n = np.bincount(inverse).astype(float)
    ci = stats.bootstrap(
        (d, n), lambda d, n, axis=-1: d.sum(axis=axis) / n.sum(axis=axis), paired=True,
        n_resamples=n_boot, rng=rng, method="percentile",
    ).confidence_interval  # fmt: skip
    return float(ci.low), float(ci.high), "", units


def _matrix(sub: pd.DataFrame, column: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(S, G) values by sample and (p_t, p_r) point, with p_r (G,) and p_t (G,)."""
    table = sub.pivot_table(index="sample", columns=["p_t", "p_r"], values=column)
    cols = table.columns.to_frame(index=False)
    return table.to_numpy(float), cols.p_r.to_numpy(float), cols.p_t.to_numpy(float)


def _row(key: str, est: an.PairedEstimate, note: str) -> dict:
    return {"key": key, "exact": est.a, "exact_err": est.a_err, "paper": est.b,
            "paper_err": est.b_err, "shift": est.diff, "shift_err": est.diff_err,
            "note": T.label(note)}  # fmt: skip


def _per_p_t(sub: pd.DataFrame, strain: str, n_boot: int, scale: Scale) -> list[dict]:
    """p_crit (P = 1/2 of a logistic fit) and alpha (from each method's energies and its own
    p_crit) per p_t, both ways."""
    out = []
    for p_t in PT4:
        one = sub[np.isclose(sub.p_t, p_t)]
        (ya, x, _), (yb, _, _) = _matrix(one, "rigid"), _matrix(one, "paper_rigid")
        ea, eb = _matrix(one, "energy")[0], _matrix(one, "paper_energy")[0]

        def cross(y, x=x):
            return an.crossing_point(y, x, n_boot=0).value

        def alpha(stack, x=x, G=x.size):
            pc = an.crossing_point(stack[:, :G], x, n_boot=0).value
            return an.fit_energy_power_law(x, np.nanmean(stack[:, G:], axis=0), pc).alpha

        est = an.paired_bootstrap(cross, ya, yb, n_boot, rng=scale.rng("paired"))
        out.append(_row(f"p_crit_{strain}_{p_t}", est, "note.pc"))
        est = an.paired_bootstrap(alpha, np.hstack([ya, ea]), np.hstack([yb, eb]), n_boot,
                                  rng=scale.rng("paired"))  # fmt: skip
        out.append(_row(f"alpha_{strain}_{p_t}", est, "note.alpha"))
    return out


def _claims(rows: pd.DataFrame, scale: Scale) -> pd.DataFrame:
    """Each measurable claim computed with both verdicts on the same samples."""
    out, n_boot = [], scale.bootstrap
    for phi in (math.pi, 0.0):
        sub, strain = rows[np.isclose(rows.phi, phi)], strain_name(phi)
        (ya, pr, pt), (yb, _, _) = _matrix(sub, "rigid"), _matrix(sub, "paper_rigid")

        def lam(y, pr=pr, pt=pt):
            ok = np.all(np.isfinite(y), axis=1)
            return an.fit_collapse(y[ok], pr, pt, n_boot=0).lam

        est = an.paired_bootstrap(lam, ya, yb, n_boot, rng=scale.rng("paired"))
        out.append(_row(f"st_sr_cables_{strain}", est, "note.collapse"))
        if strain == "compression":  # rods + struts under dilation, by e -> -e
            out.append(_row("st_sr_struts_dilation", est, "note.struts"))
        out += _per_p_t(sub, strain, n_boot, scale)
    rods = rows[np.isclose(rows.p_t, 0.0)]
    by = [rods[np.isclose(rods.phi, phi)] for phi in (math.pi, 0.0)]
    x = _matrix(by[0], "rigid")[1]
    ya = np.vstack([_matrix(b, "rigid")[0] for b in by])
    yb = np.vstack([_matrix(b, "paper_rigid")[0] for b in by])
    # the two strains' rows of one sample are one unit of the bootstrap (rods-only verdicts
    # hardly depend on the strain)
    units = np.concatenate([b.pivot_table(index="sample", values="rigid").index for b in by])
    est = an.paired_bootstrap(lambda y: an.crossing_point(y, x, n_boot=0).value, ya, yb, n_boot,
                              rng=scale.rng("paired"), groups=units)  # fmt: skip
    out.append(_row("rods_only_pc", est, "note.rods"))
    return pd.DataFrame(out)


def _measurements(claims: pd.DataFrame, scale: Scale) -> tuple[Measurement, ...]:
    """Shifts (paper's verdict - ours, same samples) as evidence for the factor "method"."""
    p = scale[NAME]
    label = T.label("label", threshold=PAPER_THRESHOLD)
    system = T.label("system", n=p.n, samples=p.samples)
    return tuple(
        Measurement.scalar(row.key, row.shift, row.shift_err, system, factor="method",
                           label=label, shift=True)
        for row in claims.itertuples() if np.isfinite(row.shift) and np.isfinite(row.shift_err)
    )  # fmt: skip


def numbers(r: MethodResult) -> dict:
    d = r.disagreement[r.disagreement.threshold == r.threshold]
    main, near = d[d.region == "all"].iloc[0], d[d.region != "all"].iloc[0]
    pct = {f"{w}_{c}": 100 * row[c] for w, row in (("all", main), ("near", near))
           for c in ("fraction", "lo", "hi")}  # fmt: skip
    return {"n": r.n, "samples": r.samples, "threshold": r.threshold, "differ": main.differ,
            "verdicts": main.samples, "near_differ": near.differ, "near_verdicts": near.samples,
            "units": main.units, "floppy_called_rigid": main.exact_floppy_paper_rigid,
            "rigid_called_floppy": main.exact_rigid_paper_floppy, **pct,
            "iterations": r.iterations["median"], "most": r.iterations["max"],
            "not_converged": r.iterations["not_converged"]}  # fmt: skip


def report_tables(r: MethodResult) -> dict:
    dis = r.disagreement.copy()
    for col in ("fraction", "lo", "hi", "wilson_lo", "wilson_hi"):
        dis[col] = dis[col].map(lambda x: f"{100 * x:.1f} %" if np.isfinite(x) else "n/a")
    c = r.claims.copy()
    c.insert(1, "claim", [CLAIMS[k].text for k in c.key])
    for col in ("exact", "paper", "shift"):
        c[col] = [fmt(v, e) for v, e in zip(c[col], c[f"{col}_err"], strict=True)]
    return {"disagreement": dis, "claims": c[["claim", "exact", "paper", "shift", "note"]]}


def cost(scale: Scale, costs) -> float:
    return costs.analysis(NAME) * scale.bootstrap / 100


def errors(scale: Scale) -> list[tuple]:
    p = scale[NAME]
    return [("st_sr_cables_compression", NAME, "st_sr_shift", p.n, p.samples),
            ("p_crit_compression_0.3", NAME, "p_crit_shift", p.n, p.samples)]  # fmt: skip


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse,
    claims=lambda r: r.measured, cost=cost, numbers=numbers, report_tables=report_tables,
    errors=errors, tables=lambda r: {"method_disagreement": r.disagreement,
                                     "method_claims": r.claims},
)  # fmt: skip
