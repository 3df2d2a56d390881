"""Exact admissible self-stresses near approximate ones (the rigid side of a verdict).

Tensions from interior points, Newton iterates and LPs balance the nodes only approximately:
:func:`purify` moves them onto the null space of ``R^T`` keeping signs, :func:`rebalance` goes on
where that stalls on near-mechanisms, :func:`optimal_on_support` finds the best self-stress of a
support for the energy's dual (docs/solver.md). Only the certificates judge the results.
"""

from __future__ import annotations

import numpy as np

from .problem import Problem


def purify(
    p: Problem,
    t: np.ndarray,
    support_tol: float | None = None,
    rounds: int = 8,
    refine: int = 6,
    extended: int = 4,
    stall: int = 2,
    work_floor: float | None = None,
) -> np.ndarray:
    """An admissible self-stress near ``t`` ((m,), non-empty sites), up to round-off.

    Entries below ``support_tol max |t|`` and wrong-signed ones are dropped; then up to ``rounds``
    projections ``t <- t - W R y``, ``(R^T W R + delta I) y = R^T t``, ``W = diag(t^2)`` plus
    ``Tolerances.rod_weight`` on rods (``delta``: ``purify_shift``), each refined ``refine`` times,
    dropping the one-sided elements whose sign flipped; ``extended`` final steps in extended
    precision. It stops after a projection left above ``Tolerances.purify_hopeless`` relative
    residual, or after ``stall`` rounds in a row with work at most ``work_floor |t|_1``. Defaults
    from ``p.tol``. Returns (m,) float or longdouble tensions with admissible signs.
    """
    tol = p.tol
    support_tol = tol.support_tol if support_tol is None else support_tol
    work_floor = tol.purify_work_floor if work_floor is None else work_floor
    t = np.array(t, dtype=float)
    t_max = float(np.abs(t).max(initial=0.0))
    if t_max == 0.0 or not np.isfinite(t_max):
        return np.zeros_like(t)
    t[~kept(t, support_tol)] = 0.0
    t[p.sigma * t < 0] = 0.0
    w = t * t
    w[p.rod] += tol.rod_weight * t_max**2
    nonpositive = 0  # consecutive rounds doing no positive work (see ``stall``)
    for _ in range(rounds):
        solver = p.factor_values(p.values(w, tol.purify_shift * t_max**2))
        r_prev = np.inf
        for _ in range(refine):
            r = p.RT @ t
            r_norm = float(np.abs(r).sum())
            if r_norm >= 0.5 * r_prev or r_norm <= p.tol.purify_roundoff * float(np.abs(t).sum()):
                break  # converged, or stagnating at round-off
            r_prev = r_norm
            t = t - w * (p.R @ solver.solve(r))
        if float(np.abs(p.RT @ t).sum()) > tol.purify_hopeless * float(np.abs(t).sum()):
            # far from any self-stress on this support: no further round or step will help
            return t
        flipped = p.sigma * t < 0
        if not flipped.any():
            break
        no_work = float(t @ p.e0) <= work_floor * float(np.abs(t).sum())
        nonpositive = nonpositive + 1 if no_work else 0
        if stall and nonpositive >= stall:
            break
        t[flipped] = 0.0
        w[flipped] = 0.0
    if extended and not np.any(p.sigma * t < 0):
        t = _refine_extended(p, t, w, solver, extended)
    return t


def optimal_on_support(p: Problem, t: np.ndarray, rounds: int = 8, steps: int = 30):
    """The best self-stress for the energy's dual on the support ``S`` of tensions ``t`` (m,).

    Stiffness-weighted corrections ``t <- t - K_S R y``, ``(R^T K_S R) y = R^T t`` (at most
    ``steps`` per projection) converge to the maximiser of ``t . e0 - 1/2 t . K^-1 t`` over the
    self-stresses on ``S``; one-sided elements whose sign flips leave ``S``, for at most ``rounds``
    projections. Returns (m,) longdouble tensions, or None when the support empties or nothing
    factorises (``Tolerances.support_optimal_shift``, then 1e2 and 1e4 times it).
    """
    shift = p.tol.support_optimal_shift
    x = np.asarray(t, dtype=np.longdouble)
    support = np.asarray(t, dtype=float) != 0
    for _ in range(rounds):
        if not support.any():
            return None
        w = np.where(support, p.k, 0.0)
        solver = p.factor_shifted(w, [shift, 1e2 * shift, 1e4 * shift])
        if solver is None:
            return None
        x = _refine_extended(p, np.where(support, x, 0), w, solver, steps, 0.7, dual=True)
        flipped = p.sigma * np.asarray(x, dtype=float) < 0
        if not flipped.any():
            return x
        support &= ~flipped
    return None


def kept(t: np.ndarray, support_tol: float) -> np.ndarray:
    """The entries ((m,) bool) of ``t`` (m,) that :func:`purify` keeps at ``support_tol``,
    ``|t_b| >= support_tol max |t|``: two tolerances with the same mask purify alike."""
    t = np.asarray(t, dtype=float)  # as purify sees it
    return ~(np.abs(t) < support_tol * float(np.abs(t).max(initial=0.0)))


def _refine_extended(p: Problem, t, w, solver, steps: int, gain: float = 0.5, dual=False):
    """Mixed-precision refinement of ``t`` (m,): extended-precision residuals ``R^T t``, corrections
    ``w R y`` from the double ``solver`` of weights ``w`` (m,); at most ``steps``, each cutting the
    residual by ``gain`` and flipping no sign unless ``dual`` (which also drops the net force).
    Returns (m,) longdouble."""
    x = np.asarray(t, dtype=np.longdouble)
    r = p.exact.forces(x)
    r_norm = float(np.abs(r).sum())
    for _ in range(steps):
        rhs = _without_net_force(p, r) if dual else np.asarray(r, dtype=float)
        trial = x - w * (p.R @ solver.solve(rhs))
        if not dual and np.any(p.sigma * trial < 0):
            break
        r_trial = p.exact.forces(trial)
        r_trial_norm = float(np.abs(r_trial).sum())
        if not r_trial_norm < gain * r_norm:
            break
        x, r, r_norm = trial, r_trial, r_trial_norm
    return x


def rebalance(p: Problem, t: np.ndarray, steps: int = 20) -> np.ndarray | None:
    """Balance nearly balanced admissible tensions to extended round-off, keeping their signs.

    Goes on where :func:`purify` stalls, from ``t`` ((m,), a purified candidate): weighted
    corrections with the first of ``Tolerances.rebalance_shifts`` (times ``max t^2``) that
    factorises and gains, each cut at the first one-sided element it would take through zero,
    which is then fixed at zero; at most ``steps``. Returns the (m,) longdouble tensions of least
    relative residual, or None when ``t`` is zero or inadmissible.
    """
    shifts = p.tol.rebalance_shifts
    x = np.array(t, dtype=np.longdouble)
    tf = np.asarray(x, dtype=float)
    t_max = float(np.abs(tf).max(initial=0.0))
    if t_max == 0.0 or not np.isfinite(t_max) or np.any(p.sigma * tf < 0):
        return None
    w = tf * tf
    w[p.rod] += p.tol.rod_weight * t_max**2
    r = p.exact.forces(x)
    r_norm = float(np.abs(r).sum())
    best, best_rel = x, r_norm / float(np.abs(x).sum())
    solver, level, fresh = None, 0, False
    for _ in range(steps):
        if solver is None:
            while level < len(shifts) and solver is None:
                solver = p.factor_shifted(w, [shifts[level] * t_max**2])
                level += solver is None
            if solver is None:
                break
            fresh = True
        step = -(w * (p.R @ solver.solve(_without_net_force(p, r))))
        trial = x + step
        flips = p.sigma * trial < 0
        if flips.any():
            ratios = np.asarray(-x[flips] / step[flips], dtype=float)
            alpha = float(ratios.min())
            trial = x + alpha * step
            hit = np.flatnonzero(flips)[ratios <= alpha * (1 + p.tol.rebalance_ratio_slack)]
            trial[hit] = 0.0
            w[hit] = 0.0
            solver = None  # the weights changed
        r_trial = p.exact.forces(trial)
        r_trial_norm = float(np.abs(r_trial).sum())
        if solver is not None and not r_trial_norm < 0.5 * r_norm:
            if not fresh:
                break  # a full correction that no longer gains: round-off
            solver, level = None, level + 1  # too small a shift for this factorisation
            continue
        fresh = False
        x, r, r_norm = trial, r_trial, r_trial_norm
        rel = r_norm / float(np.abs(x).sum())
        if rel < best_rel:
            best, best_rel = x, rel
    return best


def _without_net_force(p: Problem, r: np.ndarray) -> np.ndarray:
    """Forces ``r`` ((2N,), any precision) as doubles less their mean per axis (docs/solver.md)."""
    f = np.asarray(r, dtype=float).reshape(-1, p.dim)
    return (f - f.mean(axis=0)).ravel()
