"""Estimates of the jamming study: P(jammed) against packing fraction, the fraction strictly
jammed among the collectively jammed, the jamming point per size and its finite-size shift.

* :func:`jamming_table`: per ``(n, phi)`` the decided and undecided samples, P(collectively
  jammed) and P(strictly jammed | collectively jammed) with 95 % Wilson intervals.
* :func:`jamming_points`: per size, ``phi_J(N)`` where a logistic fit of P in ``phi`` crosses
  1/2 (Firth-penalised, :func:`~.fits.fit_logistic`), with the width (the 1/4-to-3/4 distance)
  and bootstrap errors over samples (the generator passed in).
* :func:`finite_size_shift`: ``phi_J(N) = phi_inf + a N^(-b)`` fitted by weighted least squares
  with ``b`` free and with ``b`` fixed at each value of ``exponents``; ``phi_inf`` is reported
  for every form with the spread over the forms the data allow (chi^2 per degree of freedom below
  ``accept``) beside it, never one form alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from ..errors import InputError
from .binomial import wilson
from .bootstrap import Estimate
from .fits import fit_logistic


def jamming_table(rows: pd.DataFrame) -> pd.DataFrame:
    """P(jammed) per ``(n, phi)`` from study rows (one per sample).

    Parameters
    ----------
    rows : pandas.DataFrame
        Columns ``n``, ``phi``, ``collective`` and ``strict`` (statuses).

    Returns
    -------
    pandas.DataFrame
        Per ``(n, phi)``: ``samples``, ``decided``, ``undecided`` (either test), ``jammed``
        (collectively), ``p``, ``p_lo``, ``p_hi`` (Wilson 95 %), ``strict`` (strictly jammed among
        the collectively jammed), ``p_strict``, ``p_strict_lo``, ``p_strict_hi``.
    """
    out = []
    for (n, phi), g in rows.groupby(["n", "phi"], sort=True):
        coll, strict = g["collective"].to_numpy(), g["strict"].to_numpy()
        decided = coll != "undecided"
        jammed = int(np.count_nonzero(coll == "jammed"))
        both = (coll == "jammed") & (strict != "undecided")
        k_strict = int(np.count_nonzero(both & (strict == "jammed")))
        p, lo, hi = wilson(jammed, int(decided.sum()))
        ps, sl, sh = wilson(k_strict, int(both.sum()))
        out.append({
            "n": int(n), "phi": float(phi), "samples": len(g), "decided": int(decided.sum()),
            "undecided": int(np.count_nonzero((coll == "undecided") | (strict == "undecided"))),
            "jammed": jammed, "p": p, "p_lo": lo, "p_hi": hi, "strict": k_strict,
            "strict_tested": int(both.sum()), "p_strict": ps, "p_strict_lo": sl,
            "p_strict_hi": sh,
        })  # fmt: skip
    return pd.DataFrame(out)


@dataclass(frozen=True)
class JammingPoint:
    """The jamming point of one size.

    Attributes
    ----------
    n : int
        Particles.
    phi_j : Estimate
        Packing fraction at P = 1/2 (NaN when the fit does not cross it inside the data).
    width : Estimate
        ``phi(P = 3/4) - phi(P = 1/4)``.
    samples : int
        Decided samples used.
    """

    n: int
    phi_j: Estimate
    width: Estimate
    samples: int


def _logistic_point(phi: np.ndarray, jammed: np.ndarray) -> tuple[float, float]:
    """(phi at P = 1/2, width) of a logistic fit to per-sample outcomes."""
    values = np.unique(phi)
    k = np.array([jammed[phi == v].sum() for v in values], dtype=float)
    m = np.array([(phi == v).sum() for v in values], dtype=float)
    centre, scale = values.mean(), max(values.std(), 1e-12)
    X = np.c_[np.ones_like(values), (values - centre) / scale]
    b0, b1 = fit_logistic(k, m, X)
    if not (np.isfinite(b0) and np.isfinite(b1)) or b1 <= 0:
        return math.nan, math.nan
    mid = centre - scale * b0 / b1
    if not values.min() <= mid <= values.max():
        return math.nan, math.nan
    return float(mid), float(2 * math.log(3) * scale / b1)


def jamming_points(
    rows: pd.DataFrame, rng: np.random.Generator, replicas: int = 200
) -> list[JammingPoint]:
    """``phi_J`` and the transition's width per size, with bootstrap errors.

    Parameters
    ----------
    rows : pandas.DataFrame
        Study rows (``n``, ``phi``, ``sample``, ``collective``); undecided samples are left out of
        the fit (and counted by :func:`jamming_table`).
    rng : numpy.random.Generator
        The bootstrap's stream (samples resampled within each ``phi``).
    replicas : int
        Bootstrap replicas.

    Returns
    -------
    list of JammingPoint
        One per size, in increasing ``n``.
    """
    out = []
    for n, g in rows.groupby("n", sort=True):
        g = g[g["collective"] != "undecided"]
        phi = g["phi"].to_numpy(dtype=float)
        jammed = (g["collective"] == "jammed").to_numpy(dtype=float)
        mid, width = _logistic_point(phi, jammed)
        groups = [np.flatnonzero(phi == v) for v in np.unique(phi)]
        reps = []
        for _ in range(replicas):
            idx = np.concatenate([rng.choice(ix, size=ix.size) for ix in groups])
            reps.append(_logistic_point(phi[idx], jammed[idx]))
        r = np.array(reps)
        ok = np.isfinite(r).all(axis=1)
        err = r[ok].std(axis=0, ddof=1) if ok.sum() >= 0.8 * replicas else (math.nan, math.nan)
        point = JammingPoint(
            int(n), Estimate(mid, float(err[0])), Estimate(width, float(err[1])), int(len(g))
        )
        out.append(point)
    return out


@dataclass(frozen=True)
class ShiftFit:
    """One form of ``phi_J(N) = phi_inf + a N^(-b)``.

    Attributes
    ----------
    exponent : float
        ``b`` (fitted when ``free``).
    free : bool
        Whether ``b`` was fitted.
    phi_inf, amplitude : Estimate
        ``phi_inf`` and ``a`` with their standard errors.
    chi2_dof : float
        Reduced chi^2 (NaN without degrees of freedom).
    """

    exponent: float
    free: bool
    phi_inf: Estimate
    amplitude: Estimate
    chi2_dof: float


@dataclass(frozen=True)
class FiniteSizeShift:
    """The finite-size shift of the jamming point.

    Attributes
    ----------
    fits : tuple of ShiftFit
        Every form tried.
    accepted : tuple of ShiftFit
        Those with ``chi2_dof <= accept`` (or without degrees of freedom).
    phi_inf : float
        Median of the accepted forms' ``phi_inf`` (NaN when none is accepted).
    spread : float
        Half the range of the accepted ``phi_inf`` plus the largest of their errors: the
        uncertainty the choice of form leaves.
    """

    fits: tuple[ShiftFit, ...]
    accepted: tuple[ShiftFit, ...]
    phi_inf: float
    spread: float


def finite_size_shift(
    points: list[JammingPoint],
    exponents: tuple[float, ...] = (0.5, 0.7),
    accept: float = 3.0,
) -> FiniteSizeShift:
    """Fit the shift of ``phi_J(N)`` with the exponent free and fixed at each of ``exponents``.

    Parameters
    ----------
    points : list of JammingPoint
        From :func:`jamming_points`; points with a NaN estimate or error are left out.
    exponents : tuple of float
        Fixed values of ``b`` (O'Hern et al. 2003 report the shift and the width scaling as
        ``N^(-1/(nu d))`` with ``nu d`` near 1.4 in 2D, ``b`` about 0.7; 0.5 is ``1 / d``).
    accept : float
        Largest reduced chi^2 of a form kept for the spread.

    Returns
    -------
    FiniteSizeShift
        Every fit, the accepted ones and their combined ``phi_inf`` with its spread.
    """
    ok = [p for p in points if np.isfinite(p.phi_j.value) and np.isfinite(p.phi_j.err)
          and p.phi_j.err > 0]  # fmt: skip
    if len(ok) < 2:
        raise InputError("the finite-size shift needs jamming points at two sizes at least")
    n = np.array([p.n for p in ok], dtype=float)
    y = np.array([p.phi_j.value for p in ok])
    e = np.array([p.phi_j.err for p in ok])
    fits = []
    forms: list[tuple[float | None, bool]] = [(b, False) for b in exponents]
    if len(ok) >= 4:
        forms.append((None, True))
    for b_fixed, free in forms:

        def resid(params, b_fixed=b_fixed):
            phi_inf, a = params[0], params[1]
            b = params[2] if b_fixed is None else b_fixed
            return (phi_inf + a * n ** (-b) - y) / e

        start = [y[-1], (y[0] - y[-1]) * n[0] ** 0.7] + ([0.7] if free else [])
        res = least_squares(resid, start)
        dof = len(ok) - len(start)
        chi2 = float(np.sum(res.fun**2))
        try:
            cov = np.linalg.inv(res.jac.T @ res.jac)
        except np.linalg.LinAlgError:
            cov = np.full((len(start), len(start)), np.nan)
        scale = max(chi2 / dof, 1.0) if dof > 0 else 1.0
        errs = np.sqrt(np.abs(np.diag(cov)) * scale)
        b = float(res.x[2]) if free else float(b_fixed)  # type: ignore[arg-type]
        fits.append(ShiftFit(b, free, Estimate(float(res.x[0]), float(errs[0])),
                             Estimate(float(res.x[1]), float(errs[1])),
                             chi2 / dof if dof > 0 else math.nan))  # fmt: skip
    accepted = tuple(f for f in fits if not (f.chi2_dof > accept))
    if not accepted:
        return FiniteSizeShift(tuple(fits), (), math.nan, math.nan)
    values = np.array([f.phi_inf.value for f in accepted])
    errors = np.array([f.phi_inf.err for f in accepted])
    spread = 0.5 * float(values.max() - values.min()) + float(np.nanmax(errors))
    return FiniteSizeShift(tuple(fits), accepted, float(np.median(values)), spread)
