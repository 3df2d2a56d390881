"""Fig. 1B: P(p_r, p_t) at f_c = 0.5 under shear, and its collapse onto p_r + p_t / 2.

Per-sample thresholds along p_r at p_t = 0, 0.1, ..., 0.8 give P on any grid; a
maximum-likelihood fit of P = F(p_r + lam p_t) to all of them gives lam = S_t/S_r
(:func:`~tensegrity_rigidity.analysis.fits.fit_collapse_thresholds`), bootstrap errors over
samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..claims import Measurement
from ..study import Result, Scale, Study
from ..style import COLUMN, WORDS, save
from ..template import load
from .rows import Rows, interval_straddles, threshold_bounds

NAME = "fig1b"
T = load(NAME)
#: p_t of the threshold sweeps
FIG1B_PT = [round(x, 3) for x in np.arange(0.0, 0.81, 0.1)]
#: p_r grid of P (101 points)
P_R = np.linspace(0, 1, 101)


@dataclass(frozen=True, kw_only=True)
class Params:
    n: int = 32  # lattice size
    samples: int = 0  # thresholds per p_t


PARAMS = {"tiny": Params(n=5, samples=6), "quick": Params(n=12, samples=48),
          "paper": Params(n=32, samples=24)}  # fmt: skip


@dataclass(frozen=True, eq=False)
class Fig1bResult(Result):
    """P(p_r, p_t): ``P`` (J, K) over ``p_t`` (J,) and ``p_r`` (K,), NaN where p_r + p_t > 1;
    ``half_x`` (H,): p_r + p_t/2 where P crosses 1/2, per p_t that reaches it; ``collapse``:
    the fit of P = F(p_r + lam p_t) to every p_t; ``rows``: the threshold rows analysed."""

    p_r: np.ndarray
    p_t: np.ndarray
    P: np.ndarray
    half_x: np.ndarray
    collapse: an.CollapseFit
    n: int
    samples: int
    rows: pd.DataFrame


def sweeps(scale: Scale) -> dict[str, dict]:
    p = scale[NAME]
    spec = {"n": p.n, "p_t": FIG1B_PT, "f_c": 0.5, "phi": "shear", "samples": p.samples}
    return {NAME: spec | {"seed": 11, "threshold": {"path": "p_r"}}}


def analyse(rows: Rows, scale: Scale) -> Fig1bResult:
    """P(p_r, p_t) and the collapse fit from the threshold rows of :func:`sweeps`."""
    df, excluded = rows[NAME]
    P = np.full((len(FIG1B_PT), P_R.size), np.nan)
    halves = []
    for i, pt in enumerate(FIG1B_PT):
        t = df[np.isclose(df.p_t, pt)].threshold_p_r.to_numpy()
        ok = P_R + pt <= 1 + 1e-12
        P[i, ok] = an.probability_from_thresholds(t, P_R[ok])
        ok = np.isfinite(P[i])
        if ok.sum() > 2 and P[i, ok].max() >= 0.5:
            halves.append(float(np.interp(0.5, P[i, ok], P_R[ok])) + pt / 2)
    t, lo, hi = threshold_bounds(df, FIG1B_PT)
    collapse = an.fit_collapse_thresholds(t, np.array(FIG1B_PT), lo, hi, n_boot=scale.bootstrap,
                                          rng=scale.rng("collapse"))  # fmt: skip
    return Fig1bResult(
        p_r=P_R, p_t=np.array(FIG1B_PT), P=P, half_x=np.array(halves), collapse=collapse,
        n=scale[NAME].n, samples=scale[NAME].samples, rows=df, excluded={NAME: excluded},
        straddling=interval_straddles(df, P_R),
    )  # fmt: skip


def numbers(r: Fig1bResult) -> dict:
    half = r.half_x
    return {
        "n": r.n, "samples": r.samples, "p_t": len(r.p_t), "lam": r.collapse.lam,
        "lam_err": r.collapse.lam_err, "units": r.collapse.n_samples,
        "half_mean": half.mean() if half.size else None,
        "half_spread": half.std() if half.size else None,
        "halves": half.size,
    }  # fmt: skip


def claims(r: Fig1bResult) -> tuple[Measurement, ...]:
    """The collapse under shear at f_c = 0.5 (claim ``collapse_shear_half``)."""
    v = numbers(r)
    system, note = T.label("system", **v), T.label("note", **v)
    return (Measurement.scalar("collapse_shear_half", v["lam"], v["lam_err"], system, note=note,
                               size=r.n),)  # fmt: skip


def figures(r: Fig1bResult, figdir) -> dict:
    fig, ax = plt.subplots(figsize=(COLUMN, 2.8))
    P = np.ma.masked_invalid(r.P)
    mesh = ax.pcolormesh(r.p_r, r.p_t, P, shading="nearest", cmap="viridis", vmin=0, vmax=1)
    fig.colorbar(mesh, ax=ax, label=T.label("colorbar"))
    ax.contour(r.p_r, r.p_t, P, levels=[0.5], colors="white", linewidths=1)
    # the mean-field line p_r + p_t / 2 = const through P = 1/2 at p_t = 0
    x0 = float(np.interp(0.5, np.nan_to_num(r.P[0]), r.p_r))
    pt = np.linspace(0, r.p_t.max(), 50)
    ax.plot(x0 - pt / 2, pt, color="orange", lw=2, label=T.label("line"))
    ax.set(xlim=(0, 1), xlabel=WORDS.label("p_r"), ylabel=WORDS.label("p_t"))
    ax.set_title(WORDS.label("samples", n=r.n, samples=r.samples))
    ax.legend(loc="upper right")
    return {"1B": save(fig, figdir, "1B")}


def cost(scale: Scale, costs) -> float:
    return costs.analysis(NAME) * scale.bootstrap / 100


def errors(scale: Scale) -> list[tuple]:
    p = scale[NAME]
    return [("collapse_shear_half", NAME, "st_sr", p.n, p.samples)]


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse, claims=claims,
    cost=cost, numbers=numbers, figures=figures, errors=errors,
)  # fmt: skip
