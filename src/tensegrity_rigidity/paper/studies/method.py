"""The paper's method beside ours: both verdicts on the same samples near the transition.

The paper decided each sample with a local minimiser and "energy greater than 0"
(:mod:`tensegrity_rigidity.ensemble.inexact` reproduces that with L-BFGS-B and a relative
threshold). This study runs the same grid twice, once with the certified verdict and once with
the paper's (sweep key ``verdict = "paper"``), on identical samples (common random numbers:
a sample's disorder depends only on ``(seed, n, delta, sample)``), and reports

* how often the two verdicts differ, in which direction, overall and where the exact P lies
  between 0.1 and 0.9, at the threshold of the verdict and at 100x above and below it (the
  energies are stored, so the verdict at another threshold needs no new minimisation);
* how each claim it can measure moves: S_t/S_r of rods + cables under compression and dilation
  (and rods + struts under dilation, equal to the first by the e -> -e symmetry, which the
  minimiser respects too), the rods-only P = 1/2 point, p_crit and the energy exponent alpha
  per p_t. Each is computed both ways with the same estimator on the same samples; the shift
  (paper's way minus ours) has a paired bootstrap error and is handed to the comparison as the
  evidence for the factor "method".

Grid: rods + cables (f_c = 1), compression and dilation, p_t in {0, 0.1, 0.2, 0.3}, p_r from
0.40 to 0.80 (the transition region at every p_t) at the scale's ``method_step``; lattice
``n_method`` with ``samples_method`` samples per point.

Like the figure modules: ``sweeps(scale)``, ``analyse(rows, scale)``, ``claims(result)`` and
``study(out, scale, **kw)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from ...analysis import estimators as an
from ...ensemble.inexact import PAPER_THRESHOLD
from ..claims import Measurement
from .rows import PT4, Rows, load_sweeps, p_r_grid, strain_name
from .scales import Scale

#: thresholds (relative to the affine energy) at which the paper's verdict is also read
THRESHOLDS = (1e-6, PAPER_THRESHOLD, 1e-10)
P_R_RANGE = (0.40, 0.80)
KEYS = ["phi", "p_t", "p_r", "sample"]


@dataclass(frozen=True, eq=False)
class MethodResult:
    """Both verdicts on the same samples and what the difference does to the claims.

    Attributes
    ----------
    rows : DataFrame
        One row per sample and grid point: ``rigid`` (certified), ``paper_rigid`` (the paper's
        verdict at :data:`~tensegrity_rigidity.ensemble.inexact.PAPER_THRESHOLD`), ``energy``
        (exact E*), ``paper_energy`` (where L-BFGS-B stopped), ``affine_energy``,
        ``iterations``, ``converged``.
    disagreement : DataFrame
        Per threshold and region ("all", "0.1 <= P <= 0.9"): verdicts, distinct samples,
        verdicts that differ (count, fraction with a 95 % interval from a bootstrap over whole
        samples, and the row-wise Wilson interval for comparison), and the two directions; see
        :func:`_disagreement`.
    claims : DataFrame
        Per claim: its key, the value with exact verdicts, with the paper's, and the shift
        (paper's - exact) with paired bootstrap errors.
    iterations : dict
        Median and largest L-BFGS-B iteration count, and the samples where it stopped at its
        iteration limit without meeting its tolerances (``not_converged``).
    """

    rows: pd.DataFrame
    disagreement: pd.DataFrame
    claims: pd.DataFrame
    iterations: dict
    threshold: float
    n: int
    samples: int
    excluded: dict[str, int]
    measured: tuple[Measurement, ...] = ()


def sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec: per p_t the same grid with the exact and with the paper's verdict."""
    p_r = p_r_grid(scale.method_step, *P_R_RANGE)
    out = {}
    for p_t in PT4:
        spec = {
            "n": scale.n_method,
            "p_r": [p for p in p_r if p + p_t <= 1 + 1e-12],
            "p_t": p_t,
            "f_c": 1.0,
            "phi": ["compression", "dilation"],
            "samples": scale.samples_method,
            "seed": 51,
        }
        out[f"method_exact_pt{p_t:.1f}"] = spec
        out[f"method_paper_pt{p_t:.1f}"] = spec | {"verdict": "paper"}
    return out


def analyse(rows: Rows, scale: Scale) -> MethodResult:
    """Both verdicts of the rows of :func:`sweeps`, compared sample by sample."""
    excluded, parts = {}, []
    for p_t in PT4:
        name = f"method_exact_pt{p_t:.1f}"
        exact, excluded[name] = rows[name]
        paper, _ = rows[f"method_paper_pt{p_t:.1f}"]
        merged = exact[[*KEYS, "rigid", "energy", "affine_energy"]].merge(
            paper[[*KEYS, "rigid", "energy", "iterations", "converged"]].rename(
                columns={"rigid": "paper_rigid", "energy": "paper_energy"}
            ),
            on=KEYS,
        )
        parts.append(merged)
    both = pd.concat(parts, ignore_index=True)
    both["rigid"] = both.rigid.astype(bool)
    both["paper_rigid"] = both.paper_rigid.astype(bool)
    shifts = _claims(both, scale)
    return MethodResult(
        rows=both,
        # percentiles need many replicas, and these cost microseconds: at least 1000
        disagreement=_disagreement(both, max(scale.bootstrap, 1000), scale),
        claims=shifts,
        iterations={
            "median": float(both.iterations.median()),
            "max": int(both.iterations.max()),
            "not_converged": int((~both.converged.astype(bool)).sum()),
        },
        threshold=PAPER_THRESHOLD,
        n=scale.n_method,
        samples=scale.samples_method,
        excluded=excluded,
        measured=_measurements(shifts, scale),
    )


def claims(result: MethodResult) -> tuple[Measurement, ...]:
    """The shifts as evidence for the factor "method" (:attr:`MethodResult.measured`)."""
    return result.measured


def study(out, scale: Scale, **kw) -> MethodResult:
    """Run (or resume) the grid with both verdicts into ``out`` and analyse it."""
    return analyse(load_sweeps(out, sweeps(scale), **kw), scale)


def _disagreement(rows: pd.DataFrame, n_boot: int, scale: Scale) -> pd.DataFrame:
    """How often the verdicts differ, per threshold and region, with a cluster interval.

    The rows are a few disorders (column ``sample``) each decided at many grid points
    ``(phi, p_t, p_r)``: one sample's verdicts are strongly correlated, so the independent unit
    is the sample, not the row. The interval therefore resamples whole samples.

    Parameters
    ----------
    rows : pandas.DataFrame
        One row per sample and grid point with ``phi``, ``p_t``, ``p_r``, ``sample``,
        ``rigid`` (exact verdict), ``paper_energy`` and ``affine_energy``.
    n_boot : int
        Bootstrap replicas of the cluster interval (:func:`analyse` passes the scale's
        ``bootstrap``, at least 1000).
    scale : Scale
        Its ``rng("disagreement")`` draws the replicas; every (threshold, region) restarts
        that stream, so the same rows give the same numbers.

    Returns
    -------
    pandas.DataFrame
        One row per threshold and region ("all", "0.1 <= P <= 0.9", P the exact rigidity
        probability at the row's grid point):

        * ``samples``: verdicts (rows) in the region; ``units``: distinct samples among them;
        * ``differ``, ``fraction``: verdicts that differ and their share ``differ / samples``;
        * ``lo``, ``hi``: 95 % cluster-bootstrap interval of ``fraction``. A replica draws
          ``units`` samples with replacement and pools all their rows in the region
          (``sum differ / sum rows``); the interval is the 2.5 and 97.5 percentiles of the
          replicas;
        * ``wilson_lo``, ``wilson_hi``: the Wilson interval that counts every row as
          independent, for comparison only (too narrow when a sample's verdicts are
          correlated);
        * ``interval_note``: why the interval is not the percentile one, else "";
        * ``exact_rigid_paper_floppy``, ``exact_floppy_paper_rigid``: the two directions.

    Notes
    -----
    Where the percentile interval cannot be read:

    * no unit: ``lo = hi = NaN``;
    * one unit: ``[0, 1]``; resampling one sample shows no spread between samples, and
      nothing else bounds the fraction;
    * no verdict differs (``differ = 0``): every replica is 0 and the percentiles collapse to
      ``[0, 0]``, which claims a certainty the data do not have. The bound is then the exact
      one-sided 95 % upper bound on the probability that a sample has any disagreement in the
      region, from 0 such samples in ``U`` independent ones: ``[0, 1 - 0.05**(1/U)]`` (about
      ``3 / U``, the rule of three, counted in samples rather than rows). The share of
      differing rows cannot exceed the share of samples with a differing row (if the samples
      have equal numbers of rows), so this bounds ``fraction`` too, conservatively. Since the
      fraction cannot be below 0, ``[0, hi]`` is a 95 % interval like the others.
    * every verdict differs: the mirror image, ``[0.05**(1/U), 1]``.
    """
    P = rows.groupby(["phi", "p_t", "p_r"]).rigid.transform("mean")
    regions = {"all": np.ones(len(rows), bool), "0.1 <= P <= 0.9": ((P >= 0.1) & (P <= 0.9))}
    sample = rows["sample"].to_numpy()
    out = []
    for tau in THRESHOLDS:
        paper = rows.paper_energy > tau * rows.affine_energy
        for region, m in regions.items():
            m = np.asarray(m, bool)
            exact_r, paper_r = rows.rigid.to_numpy()[m], paper.to_numpy()[m]
            wrong = exact_r != paper_r
            differ = int(wrong.sum())
            _, w_lo, w_hi = an.wilson(differ, m.sum())
            lo, hi, note, units = _cluster_interval(
                wrong, sample[m], n_boot, scale.rng("disagreement")
            )
            out.append(
                {
                    "threshold": tau,
                    "region": region,
                    "samples": int(m.sum()),
                    "units": units,
                    "differ": differ,
                    "fraction": differ / m.sum() if m.sum() else np.nan,
                    "lo": lo,
                    "hi": hi,
                    "wilson_lo": float(w_lo),
                    "wilson_hi": float(w_hi),
                    "interval_note": note,
                    "exact_rigid_paper_floppy": int((exact_r & ~paper_r).sum()),
                    "exact_floppy_paper_rigid": int((~exact_r & paper_r).sum()),
                }
            )
    return pd.DataFrame(out)


def _cluster_interval(
    wrong: np.ndarray, unit: np.ndarray, n_boot: int, rng: np.random.Generator
) -> tuple[float, float, str, int]:
    """95 % interval of ``wrong.mean()`` resampling whole units (see :func:`_disagreement`).

    Parameters
    ----------
    wrong : (R,) bool
        Whether each row's two verdicts differ.
    unit : (R,) array
        Each row's independent unit (its sample).
    n_boot : int
        Replicas.
    rng : numpy.random.Generator
        Source of the replicas.

    Returns
    -------
    lo, hi : float
        The interval.
    note : str
        Why it is not the percentile interval ("" when it is).
    units : int
        Distinct units.
    """
    units = an.n_units(wrong.size, unit)
    if units == 0:
        return np.nan, np.nan, "no samples in the region", 0
    if units == 1:
        return 0.0, 1.0, "one sample: no spread between samples to resample", 1
    differ = int(wrong.sum())
    if differ == 0:
        hi = 1 - 0.05 ** (1 / units)
        return 0.0, hi, f"no verdict differs: exact 95 % upper bound over {units} samples", units
    if differ == wrong.size:
        lo = 0.05 ** (1 / units)
        return lo, 1.0, f"every verdict differs: exact 95 % lower bound over {units} samples", units
    # per-unit totals: a replica's pooled fraction is sum(differ) / sum(rows) of its units
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


def _claims(rows: pd.DataFrame, scale: Scale) -> pd.DataFrame:
    """Each measurable claim computed with both verdicts on the same samples."""
    out = []
    n_boot = scale.bootstrap

    def add(key, est: an.PairedEstimate, note=""):
        out.append(
            {
                "key": key,
                "exact": est.a,
                "exact_err": est.a_err,
                "paper": est.b,
                "paper_err": est.b_err,
                "shift": est.diff,
                "shift_err": est.diff_err,
                "note": note,
            }
        )

    for phi in (math.pi, 0.0):
        sub = rows[np.isclose(rows.phi, phi)]
        strain = strain_name(phi)
        ya, pr, pt = _matrix(sub, "rigid")
        yb, _, _ = _matrix(sub, "paper_rigid")

        def lam(y, pr=pr, pt=pt):
            ok = np.all(np.isfinite(y), axis=1)
            return an.fit_collapse(y[ok], pr, pt, n_boot=0).lam

        est = an.paired_bootstrap(lam, ya, yb, n_boot, rng=scale.rng("paired"))
        add(f"st_sr_cables_{strain}", est, "collapse fit over p_t = 0, 0.1, 0.2, 0.3")
        if strain == "compression":
            add("st_sr_struts_dilation", est, "equal to rods + cables under compression (e -> -e)")
        for p_t in PT4:
            one = sub[np.isclose(sub.p_t, p_t)]
            ya, pr1, _ = _matrix(one, "rigid")
            yb, _, _ = _matrix(one, "paper_rigid")

            def cross(y, x=pr1):
                return an.crossing_point(y, x, n_boot=0).value

            est = an.paired_bootstrap(cross, ya, yb, n_boot, rng=scale.rng("paired"))
            add(f"p_crit_{strain}_{p_t}", est, "P = 1/2 of a logistic fit over the p_r grid")
            ea, _, _ = _matrix(one, "energy")
            eb, _, _ = _matrix(one, "paper_energy")

            def alpha(stack, x=pr1, G=pr1.size):
                y, e = stack[:, :G], stack[:, G:]
                pc = an.crossing_point(y, x, n_boot=0).value
                fit = an.fit_energy_power_law(x, np.nanmean(e, axis=0), pc)
                return fit.alpha

            est = an.paired_bootstrap(
                alpha, np.hstack([ya, ea]), np.hstack([yb, eb]), n_boot, rng=scale.rng("paired")
            )
            add(f"alpha_{strain}_{p_t}", est, "mean energies from each method, its own p_crit")
    rods = rows[np.isclose(rows.p_t, 0.0)]
    stack = [
        _matrix(rods[np.isclose(rods.phi, phi)], c)[0]
        for phi in (math.pi, 0.0)
        for c in ("rigid", "paper_rigid")
    ]
    x = _matrix(rods[np.isclose(rods.phi, math.pi)], "rigid")[1]
    ya, yb = np.vstack([stack[0], stack[2]]), np.vstack([stack[1], stack[3]])
    # the two strains' rows of one sample are one unit of the bootstrap (rods-only verdicts
    # hardly depend on the strain)
    units = [
        rods[np.isclose(rods.phi, phi)].pivot_table(index="sample", values="rigid").index
        for phi in (math.pi, 0.0)
    ]  # the rows of stack[0] and stack[2]
    est = an.paired_bootstrap(
        lambda y: an.crossing_point(y, x, n_boot=0).value,
        ya,
        yb,
        n_boot,
        rng=scale.rng("paired"),
        groups=np.concatenate(units),
    )
    add("rods_only_pc", est, "P = 1/2 of a logistic fit, p_t = 0, both strains")
    return pd.DataFrame(out)


def _measurements(claims: pd.DataFrame, scale: Scale) -> tuple[Measurement, ...]:
    """Shifts (paper's verdict - ours, same samples) as evidence for the factor "method"."""
    label = f"ours + shift to the paper's verdict (L-BFGS-B, E > {PAPER_THRESHOLD:g} E_aff)"
    system = f"shift from n = {scale.n_method}, {scale.samples_method} samples per point"
    return tuple(
        Measurement.scalar(
            row.key, row.shift, row.shift_err, system, factor="method", label=label, shift=True
        )
        for row in claims.itertuples()
        if np.isfinite(row.shift) and np.isfinite(row.shift_err)
    )
