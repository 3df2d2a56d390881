"""The headline claims at one size and node disorder: the sweeps both finite-size studies run.

:func:`headline_sweeps` gives exact per-sample thresholds along p_r (rods only; rods +
one-sided elements at p_t = 0.3 with f_c = 0, 0.5, 1; rods + cables at p_t = 0.1, 0.2) under
dilation, shear and compression; :func:`energy_sweeps` the energy grids of rods + cables on
the first samples of the same disorders; :func:`rods_pc_sweep` the rods-only thresholds of
the p_c extrapolation. :func:`headline` reads the claims at one (n, delta) from their rows:
the rods-only P = 1/2 point, S_t/S_r per strain and per one-sided system, p_crit of rods +
cables per p_t, the energy exponents alpha and the taut-cable fraction at the transition.
Estimates pooled over strains bootstrap samples, not rows.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd
from scipy import stats

from ...analysis import estimators as an
from ..claims import CLAIMS, REFERENCES, Measurement
from ..comparison import verdict, z_score
from ..study import Scale
from ..template import load
from .energy import energy_exponent, taut_with_error
from .nonaffinity import mask_uncertified_tensions
from .rows import COLLAPSE_PT, PT4, Rows, p_r_grid, per_sample, strain_name, threshold_bounds

STRAINS3 = [0.0, math.pi / 2, math.pi]
FC3 = [0.0, 0.5, 1.0]
#: (claim key, f_c, strain) of the S_t/S_r claims measured here
LAMBDA_CLAIMS = [
    ("st_sr_half_dilation", 0.5, "dilation"),
    ("st_sr_half_shear", 0.5, "shear"),
    ("st_sr_half_compression", 0.5, "compression"),
    ("st_sr_cables_compression", 1.0, "compression"),
    ("st_sr_struts_dilation", 0.0, "dilation"),
    ("st_sr_cables_dilation", 1.0, "dilation"),
]
T = load("headline")
#: most samples per point of the energy grids by default (the threshold sweeps have up to 400)
ENERGY_SAMPLES = 24
#: the check on the fitted exponent and the extrapolated threshold
NU_CHECK = REFERENCES["nu_moukarzel_duxbury"]
PC_CHECK = REFERENCES["pc_javerzat_notarmuzi"]

#: seed of the 3D sweeps, shared by every FCC study (sample k's disorder derives from
#: (seed, n, delta, k))
SEED_3D = 33


def chunk_size(n: int) -> int:
    """Samples per chunk of the threshold sweeps at size ``n`` (the unit of resumption).

    One threshold search takes about 1.6 s at n = 32, 48 s at n = 64 and, extrapolated, 25 min
    at n = 128 (``data/costs.toml``): chunks of 2
    samples at n = 64 and 1 beyond keep what an interruption loses to a few minutes per worker
    and let two workers share the last chunks of a sweep. Rows do not depend on it.
    """
    return 32 if n < 64 else max(1, 128 // n)


def chunk_size_3d(n: int) -> int:
    """Samples per chunk at size ``n``: a search at p_t = 0.3 takes about 0.35 s at n = 4, 9 s
    at 8, 30 s at 10; chunks of a minute or less keep an interruption's loss small."""
    return {4: 32, 5: 16, 6: 8, 8: 4}.get(n, 2 if n >= 10 else 32)


def headline_sweeps(n: int, delta: float, samples: int) -> dict[str, dict]:
    """Sweep name -> spec of the headline claims at one (n, delta); seed 61, threshold mode.

    ``_rods``: p_t = 0 (f_c does not matter there) under dilation, shear and compression;
    ``_mixed``: p_t = :data:`~.rows.COLLAPSE_PT` at f_c = 0, 0.5, 1
    under the three strains (S_t/S_r from the collapse over p_t = 0 and 0.3, as Fig. 1C);
    ``_pcrit``: p_t = 0.1, 0.2 for rods + cables (f_c = 1) under dilation and compression, for
    p_crit at every p_t. The names carry (n, delta) only, so the two studies share a sweep where
    they meet (the node-disorder study's size among the sizes, delta the default), the smaller
    reading the first samples of the larger.
    """
    name = f"headline_n{n}_delta{delta:g}"
    base = dict(n=n, delta=delta, samples=samples, seed=61, phi=STRAINS3)
    base |= {"threshold": {"path": "p_r"}, "output": {"chunk_size": chunk_size(n)}}
    return {
        f"{name}_rods": base | {"p_t": 0.0, "f_c": 0.5},
        f"{name}_mixed": base | {"p_t": COLLAPSE_PT, "f_c": FC3},
        f"{name}_pcrit": base | {"p_t": PT4[1:-1], "f_c": 1.0, "phi": [0.0, math.pi]},
    }


#: samples per chunk of the pebble-game sweeps of the p_c extrapolation: about a minute of one
#: worker at n = 512 (about 6 s a sample), proportionally more samples below
PEBBLE_CHUNK_SITES = 8 * 512**2


def rods_pc_sweep(n: int, delta: float, samples: int, method: str = "lp") -> dict[str, dict]:
    """Sweep name -> spec of the rods-only thresholds of the p_c extrapolation at (n, delta).

    One strain (dilation): a rods-only threshold does not depend on the strain (identical under
    dilation, shear and compression for all 400 samples at n = 8 and 96 % at n = 32 of the fss
    run), so a second strain would cost a full search for no new information. Seed 61, so
    sample k is the disorder of sample k of :func:`headline_sweeps` (common random numbers).
    ``method`` is the threshold method: ``"lp"`` (certified bisection) or ``"pebble"`` (one
    pebble-game pass, which also records the spanning rigid cluster at the threshold; its sweeps
    are named ``rods_pc_pebble_...``, so they never meet the bisection's).
    """
    spec: dict[str, Any] = dict(n=n, delta=delta, samples=samples, seed=61, phi=[0.0])
    spec |= {"p_t": 0.0, "f_c": 0.5, "threshold": {"path": "p_r"}}
    if method == "pebble":
        spec["threshold"] = dict(path="p_r", method="pebble")
        chunk = max(1, min(256, PEBBLE_CHUNK_SITES // n**2))
        return {f"rods_pc_pebble_n{n}_delta{delta:g}": spec | {"output": {"chunk_size": chunk}}}
    return {f"rods_pc_n{n}_delta{delta:g}": spec | {"output": {"chunk_size": chunk_size(n)}}}


#: spacing of the energy sweeps' p_r grids
ENERGY_STEP = 0.025
#: p_r grid of the energy sweeps: every p_crit of rods + cables lies above 0.45 and the power
#: law is fitted within 0.25 above it (``fit_energy_power_law``)
ENERGY_P_R = p_r_grid(ENERGY_STEP, 0.45, 0.95)
#: below this n the energy grids start at the first step: a few of N = n^2 nodes' 3N bonds
#: more than their mean make a sample rigid at p_r + p_t well under 0.45 (at n = 4 the
#: bond count's spread is 0.07 in p), and the paper's p_crit estimator, the first p_r with a
#: positive mean energy, needs a first point at which every sample is floppy
FULL_ENERGY_GRID_BELOW = 16


def energy_p_r(n: int) -> list[float]:
    """The energy sweeps' p_r grid at size ``n``: :data:`ENERGY_P_R`, extended down to
    ``ENERGY_STEP`` below :data:`FULL_ENERGY_GRID_BELOW`."""
    if n >= FULL_ENERGY_GRID_BELOW:
        return ENERGY_P_R
    return p_r_grid(ENERGY_STEP, ENERGY_STEP, ENERGY_P_R[-1])


def energy_sweeps(n: int, delta: float, *, count: int) -> dict[str, dict]:
    """Sweep name -> spec of the energies of rods + cables at one (n, delta); seed 61, grid mode.

    Per p_t of :data:`~.rows.PT4`, f_c = 1 under dilation and
    compression on :func:`energy_p_r` (``p_r + p_t <= 1``): the energy exponents alpha and the
    fraction of taut cables at the transition at this size, as Fig. 2 measures them at n = 32.
    The same seed as :func:`headline_sweeps`, so sample k is the disorder of threshold sample k
    (common random numbers; where ``count`` exceeds the thresholds' samples, as at n = 64, the
    others have none). ``count`` samples per point
    (:meth:`~.fss.Params.energy_at`); no minimum-norm
    displacements (the energy and the tensions do not need them).
    """
    base: dict[str, Any] = dict(n=n, delta=delta, samples=count, seed=61, f_c=1.0)
    base |= {"phi": [0.0, math.pi], "solver": {"min_norm": False}}
    base |= {"output": {"chunk_size": 32 if n < 64 else 8}}
    return {
        f"energy_n{n}_delta{delta:g}_pt{p_t:.1f}": base
        | {"p_t": p_t, "p_r": [p for p in energy_p_r(n) if p + p_t <= 1 + 1e-12]}
        for p_t in PT4
    }


#: the claims :func:`energy_claims` measures
ENERGY_KEYS = frozenset(
    [f"alpha_{s}_{p_t}" for s in ("compression", "dilation") for p_t in PT4]
    + ["taut_cables_transition"]
)


def energy_claims(
    rows: pd.DataFrame, thresholds: dict[tuple[str, float], pd.DataFrame], scale: Scale
) -> list[dict]:
    """alpha per (strain, p_t) and the taut-cable fraction at the transition from grid rows.

    Parameters
    ----------
    rows : DataFrame
        Grid rows of :func:`energy_sweeps` (every p_t, both strains): the decided ones and the
        undecided ones whose E* is bracketed
        (:func:`~.rows.energy_bracketed`), which enter the mean
        energies and, not being rigid, not the taut fraction.
    thresholds : dict
        (strain name, p_t) -> threshold rows (``sample``, ``threshold_p_r``) of the same
        samples at the same size and delta; their median is p_crit.
    scale : Scale
        Bootstrap replicas and generators of the errors.

    Returns
    -------
    list of dict
        Rows ``key``, ``value``, ``err``: ``alpha_<strain>_<p_t>`` (the power law of the mean
        energy above p_crit, as in Fig. 2:
        :func:`~tensegrity_rigidity.paper.studies.energy_exponent`) and
        ``taut_cables_transition`` (mean over p_t = 0.1, 0.2, 0.3 under compression of the taut
        fraction of rigid samples with certified tensions at the grid p_r nearest p_crit,
        :func:`~.energy.taut_with_error`). Both errors are
        bootstraps over samples that re-estimate p_crit in every replica.
    """
    rows, _ = mask_uncertified_tensions(rows)
    out, th = [], []
    empty = pd.DataFrame({"sample": pd.Series(dtype=int), "threshold_p_r": pd.Series(dtype=float)})
    for phi in (math.pi, 0.0):
        strain = strain_name(phi)
        for p_t in PT4:
            t = thresholds.get((strain, p_t), empty)
            th.append(t[["sample", "threshold_p_r"]].assign(phi=phi, p_t=p_t))
            sub = rows[np.isclose(rows.phi, phi) & np.isclose(rows.p_t, p_t)]
            fit = energy_exponent(sub, t, scale.bootstrap, rng=scale.rng("energy_exponent"))
            out.append({"key": f"alpha_{strain}_{p_t}", "value": fit.alpha, "err": fit.alpha_err})
    th_all = pd.concat(th, ignore_index=True)
    tr = taut_with_error(rows, th_all, scale.bootstrap, rng=scale.rng("taut"))
    if tr is not None:
        out.append({"key": "taut_cables_transition", "value": tr[0], "err": tr[1]})
    return out


def headline(rows: Rows, n: int, delta: float, scale: Scale, *, samples: int, energy: int):
    """The headline claims at one (n, delta) from the rows of :func:`headline_sweeps`
    (``samples`` per point) and the energy claims from those of :func:`energy_sweeps`
    (``energy`` per point; :func:`energy_claims`).

    Parameters
    ----------
    rows : Rows
        Sweep name -> (rows, excluded) of a study that ran both (:func:`.rows.load_sweeps`,
        the energy sweeps loaded with ``energy``).
    n, delta : int, float
        The size and node disorder.
    scale : Scale
        Its bootstrap replicas and generators.
    samples, energy : int
        Samples per point of the threshold and of the energy sweeps.

    Returns
    -------
    frame : DataFrame
        Columns ``key``, ``value``, ``err``.
    excluded : dict
        Sweep name -> undecided rows.
    bracketed : dict
        Energy sweep name -> of those, the rows that still enter the energy analyses
        (:func:`~.rows.energy_bracketed`).
    """
    frames, excluded, bracketed = {}, {}, {}
    for name in headline_sweeps(n, delta, samples):
        part = name.rsplit("_", 1)[1]
        frames[part], excluded[name] = rows[name]
    rods, mixed, pcrit = frames["rods"], frames["mixed"], frames["pcrit"]
    out = []
    # rods-only thresholds do not depend on the strain: a sample is one unit, not three
    pc, pc_err = an.critical_point(
        rods.threshold_p_r.to_numpy(),
        groups=rods["sample"].to_numpy(),
        rng=scale.rng("critical_point"),
    )
    out.append({"key": "rods_only_pc", "value": pc, "err": pc_err})
    for key, f_c, strain in LAMBDA_CLAIMS:
        phi = next(p for p in STRAINS3 if strain_name(p) == strain)
        sub = pd.concat(
            [
                rods[np.isclose(rods.phi, phi)].assign(f_c=f_c),
                mixed[np.isclose(mixed.phi, phi) & np.isclose(mixed.f_c, f_c)],
            ]
        )
        t, lo, hi = threshold_bounds(sub, [0.0, COLLAPSE_PT])
        fit = an.fit_collapse_thresholds(t, np.array([0.0, COLLAPSE_PT]), lo, hi,
                                         n_boot=scale.bootstrap,
                                         rng=scale.rng("collapse"))  # fmt: skip
        out.append({"key": key, "value": fit.lam, "err": fit.lam_err})
    cables = pd.concat([pcrit, mixed[np.isclose(mixed.f_c, 1.0)]], ignore_index=True)
    crit = {}
    for phi in (math.pi, 0.0):
        strain = strain_name(phi)
        for p_t in PT4:
            src = rods if p_t == 0 else cables
            crit[strain, p_t] = src[np.isclose(src.phi, phi) & np.isclose(src.p_t, p_t)]
            v, e = an.critical_point(
                crit[strain, p_t].threshold_p_r.to_numpy(), rng=scale.rng("critical_point")
            )
            out.append({"key": f"p_crit_{strain}_{p_t}", "value": v, "err": e})
    grids = []
    for name in energy_sweeps(n, delta, count=energy):
        grid, excluded[name] = rows[name]
        bracketed[name] = int((~grid.decided.astype(bool)).sum())
        grids.append(grid)
    out += energy_claims(pd.concat(grids, ignore_index=True), crit, scale)
    return pd.DataFrame(out), excluded, bracketed


def first_positive_pcrit(grid: pd.DataFrame, scale: Scale) -> pd.DataFrame:
    """p_crit of rods + cables per (strain, p_t) by the paper's estimator: the first p_r of the
    energy grid at which the mean energy is positive
    (:func:`~tensegrity_rigidity.analysis.scaling.first_positive`), as Fig. 2's study applies it.

    Parameters
    ----------
    grid : DataFrame
        Grid rows of :func:`energy_sweeps` (``phi``, ``p_t``, ``p_r``, ``sample``, ``energy``,
        ``decided``); only decided rows enter, since a bracketed energy could make a mean
        positive.
    scale : Scale
        Bootstrap replicas and the generator of the errors.

    Returns
    -------
    DataFrame
        Columns ``key`` (``p_crit_<strain>_<p_t>``, the claims :func:`headline` measures by the
        median threshold), ``value`` (NaN when no mean is positive), ``err``, ``samples`` and
        ``censored`` (the mean energy is positive at the grid's first p_r already: the value is
        a bound, p_crit <= value, not an estimate); one row per (strain, p_t) of
        :data:`~.rows.PT4` with rows in ``grid``.
    """
    rows = grid[grid.decided.astype(bool)]
    out = []
    for phi in (math.pi, 0.0):
        for p_t in PT4:
            sub = rows[np.isclose(rows.phi, phi) & np.isclose(rows.p_t, p_t)]
            if not len(sub):
                continue
            e, x = per_sample(sub, "energy")
            first = an.first_positive(e, x, n_boot=scale.bootstrap,
                                      rng=scale.rng("first_positive"))  # fmt: skip
            out.append({"key": f"p_crit_{strain_name(phi)}_{p_t}", "value": first.value,
                        "err": first.err, "samples": e.shape[0],
                        "censored": bool(first.value == x[0])})  # fmt: skip
    return pd.DataFrame(out, columns=["key", "value", "err", "samples", "censored"])


def paper_pcrit(rows: Rows, n: int, delta: float, scale: Scale, *, energy: int) -> pd.DataFrame:
    """:func:`first_positive_pcrit` on the energy grids of :func:`energy_sweeps` at one
    (n, delta) with ``energy`` samples per point (rows as :func:`headline` reads them)."""
    grids = [rows[name][0] for name in energy_sweeps(n, delta, count=energy)]
    return first_positive_pcrit(pd.concat(grids, ignore_index=True), scale)


def energy_names(sweeps: dict[str, dict]) -> tuple[str, ...]:
    """The sweeps of ``sweeps`` made by :func:`energy_sweeps` (loaded for the energy analyses)."""
    return tuple(name for name in sweeps if name.startswith("energy_"))


def z_paper(key: str, value: float, err: float) -> float:
    """The comparison's agreement statistic of one value against the paper's claim."""
    return z_score(CLAIMS[key], Measurement.scalar(key, value, err, ""))


def judged(key: str, value: float, err: float) -> tuple[float, str]:
    """The comparison's z and verdict on one value of a claim ("agree", "disagree",
    "inconclusive", "n/a"; :func:`~tensegrity_rigidity.paper.comparison.verdict`)."""
    return verdict(CLAIMS[key], Measurement.scalar(key, value, err, ""))


# --------------------------------------------------------------------------- finite size


#: a finite-size fit whose chi-square is less probable than this does not describe its sizes
MISFIT_P = 0.01


def misfit(chi2: float, dof: int) -> str:
    """A clause for an extrapolation whose chi-square is above its 99th percentile (the values
    do not follow the form, and y_inf says little); "" when it fits."""
    if not (dof > 0 and np.isfinite(chi2)) or stats.chi2.sf(chi2, dof) >= MISFIT_P:
        return ""
    return " " + T.label("misfit", chi2=chi2, dof=dof)
