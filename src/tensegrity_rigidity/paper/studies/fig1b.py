"""Fig. 1B: P(p_r, p_t) at f_c = 0.5 under shear, and its collapse onto p_r + p_t / 2.

Estimator: per-sample thresholds along p_r at p_t = 0, 0.1, ..., 0.8 give P on any grid; a
binomial-likelihood fit of P = F(p_r + lam p_t) to all of them gives lam = S_t/S_r
(:func:`~tensegrity_rigidity.analysis.fits.fit_collapse`), bootstrap errors over samples.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..claims import Measurement
from .rows import Rows, interval_straddles, load_sweeps
from .scales import Scale

#: p_t of Fig. 1B's threshold sweeps
FIG1B_PT = [round(x, 3) for x in np.arange(0.0, 0.81, 0.1)]
#: p_r grid of P (K = 101 points) and of the collapse fit's outcomes
P_R = np.linspace(0, 1, 101)
FIT_P_R = np.arange(0.0, 1.0001, 0.01)


@dataclass(frozen=True, eq=False)
class Fig1bResult:
    """P(p_r, p_t) at f_c = 0.5 under shear.

    Attributes
    ----------
    p_r : (K,) float
        Grid of p_r.
    p_t : (J,) float
        Values of p_t (one threshold sweep each).
    P : (J, K) float
        Fraction of rigid samples; NaN where p_r + p_t > 1.
    half_x : (H,) float
        p_r + p_t/2 where P crosses 1/2, for each p_t whose P reaches 1/2 (linear
        interpolation on the grid).
    collapse : CollapseFit
        Fit of P = F(p_r + lam p_t) to every p_t: lam = S_t/S_r under shear at f_c = 0.5.
    rows : DataFrame
        The threshold rows analysed.
    excluded : dict
        Sweep name -> samples excluded as undecided.
    straddling : int or None
        Samples whose threshold interval straddles a grid value (see
        :func:`~tensegrity_rigidity.paper.studies.rows.interval_straddles`; None when the rows
        do not record intervals). The other results' ``straddling`` alike.
    measured : tuple of Measurement
        :func:`claims` of this result.
    """

    p_r: np.ndarray
    p_t: np.ndarray
    P: np.ndarray
    half_x: np.ndarray
    collapse: an.CollapseFit
    n: int
    samples: int
    rows: pd.DataFrame
    excluded: dict[str, int]
    straddling: int | None = None
    measured: tuple[Measurement, ...] = ()


def sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of Fig. 1B (the work :mod:`~tensegrity_rigidity.paper.budget` counts)."""
    return {
        "fig1b": {
            "n": scale.n_threshold,
            "p_t": FIG1B_PT,
            "f_c": 0.5,
            "phi": "shear",
            "samples": scale.fig1b_samples,
            "seed": 11,
            "threshold": {"path": "p_r"},
        }
    }


def analyse(rows: Rows, scale: Scale) -> Fig1bResult:
    """P(p_r, p_t) and the collapse fit from the threshold rows of :func:`sweeps`."""
    p_t = FIG1B_PT
    df, excluded = rows["fig1b"]
    P = np.full((len(p_t), P_R.size), np.nan)
    for i, pt in enumerate(p_t):
        t = df[np.isclose(df.p_t, pt)].threshold_p_r.to_numpy()
        ok = P_R + pt <= 1 + 1e-12
        P[i, ok] = an.probability_from_thresholds(t, P_R[ok])
    halves = []
    for i, pt in enumerate(p_t):
        ok = np.isfinite(P[i])
        if ok.sum() > 2 and P[i, ok].max() >= 0.5:
            halves.append(float(np.interp(0.5, P[i, ok], P_R[ok])) + pt / 2)
    y, pr, pt_ = an.outcomes_from_thresholds(df, FIT_P_R)
    collapse = an.fit_collapse(y, pr, pt_, n_boot=scale.bootstrap, rng=scale.rng("collapse"))
    result = Fig1bResult(
        p_r=P_R,
        p_t=np.array(p_t),
        P=P,
        half_x=np.array(halves),
        collapse=collapse,
        n=scale.n_threshold,
        samples=scale.fig1b_samples,
        rows=df,
        excluded={"fig1b": excluded},
        straddling=interval_straddles(df, P_R),
    )
    return dataclasses.replace(result, measured=claims(result))


def claims(result: Fig1bResult) -> tuple[Measurement, ...]:
    """The collapse under shear at f_c = 0.5 (claim ``collapse_shear_half``)."""
    collapse, half = result.collapse, result.half_x
    system = f"n = {result.n}, {collapse.n_samples} samples x {len(result.p_t)} p_t"
    note = (
        f"collapse fit over p_t = 0 ... 0.8; p_r + p_t/2 at P = 1/2: mean {half.mean():.3f}, "
        f"spread {half.std():.3f} over {half.size} values of p_t"
        if half.size
        else "collapse fit over p_t = 0 ... 0.8"
    )
    return (
        Measurement.scalar(
            "collapse_shear_half",
            collapse.lam,
            collapse.lam_err,
            system,
            note=note,
            size=result.n,
        ),
    )


def study(out, scale: Scale, **kw) -> Fig1bResult:
    """Run (or resume) the sweeps of Fig. 1B into ``out`` and analyse them."""
    return analyse(load_sweeps(out, sweeps(scale), **kw), scale)
