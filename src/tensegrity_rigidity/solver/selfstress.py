"""Exact admissible self-stresses near approximate ones (the rigid side of a verdict).

An interior point, a Newton iterate or an LP returns tensions ``t`` that balance the nodes only
approximately. Near the transition the optimal tensions are tiny (``|t*|^2 = 2 E*``), and
computing them from displacements as ``k (e0 + R u)`` cancels most digits. :func:`purify`
works on the self-stress side instead: it moves ``t`` onto the null space of ``R^T`` by the
weighted least-squares correction

    t <- t - W R y,    (R^T W R + delta I) y = R^T t,    W = diag(t^2)

(each element moves in proportion to its own size, so signs survive a small correction),
refined a few times on one factorisation. One-sided elements whose sign flips are set to zero
and the projection is repeated without them. The result is offered to
:meth:`~.certificates.ExactGeometry.rigid`, which decides whether it is a certificate.
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
    hopeless: float = 1e-3,
    extended: int = 4,
    rod_weight: float = 1e-6,
    shift: float = 1e-14,
    stall: int = 2,
    work_floor: float = 1e-9,
) -> np.ndarray:
    """An admissible self-stress near ``t`` (shape (m,), non-empty sites), up to round-off.

    Parameters
    ----------
    p : Problem
        The problem (its pattern factorisation is reused).
    t : (m,) float
        Approximate tensions; entries below ``support_tol * max |t|`` and one-sided entries of
        the wrong sign are dropped first.
    rounds : int
        Projections, each after dropping the one-sided elements whose sign flipped.
    refine : int
        Corrections per projection on its factorisation (iterative refinement); they stop
        once the residual no longer halves.
    hopeless : float
        Stop after a projection whose relative residual stayed above this (no self-stress
        near ``t`` on its support).
    extended : int
        Final refinement steps with residuals in extended precision (the result is then a
        ``longdouble`` array whose residual can go below double-precision round-off).
    rod_weight : float
        Weight of every rod in the projection, relative to ``max t^2``: rods may take up
        stress they did not carry in ``t`` (a one-sided element may not: its sign is not free).
    shift : float
        Regularisation of the projection's matrix ``R^T W R``, relative to ``max t^2``: keeps it
        factorisable where the support has mechanisms, small enough not to limit the residual,
        which the refinement steps reduce to round-off.
    stall : int
        Stop after this many consecutive rounds whose tensions, balanced but with one-sided
        elements of the wrong sign left, do no positive work on the strain (see
        ``work_floor``); the result then keeps those signs and is no certificate. 0 never
        stops early. Such rounds almost never end in a certificate. Once a round is
        hopeless, the extended-precision steps are skipped too: they
        cannot bring a residual above ``hopeless`` near the certificates' margin.
    work_floor : float
        A round counts toward ``stall`` when its tensions' work is at most ``work_floor`` of
        their size, ``t . e0 <= work_floor |t|_1``: work no rigid certificate accepts (it
        needs ``t . e0 / |t|_1`` above the resolution's ``violation``, whose default this
        is). Rounds that balance a self-stress of the rods alone do work at round-off,
        ``1e-18`` to ``1e-16`` of their size, of either sign; counting only ``t . e0 <= 0``
        let those of positive sign go on for up to 8 rounds.

    Returns
    -------
    (m,) float or longdouble
        Tensions with admissible signs; ``R^T t`` is at round-off when the support of the
        input carries a self-stress near it, otherwise larger (the certificate test decides).
    """
    t = np.array(t, dtype=float)
    t_max = float(np.abs(t).max(initial=0.0))
    if t_max == 0.0 or not np.isfinite(t_max):
        return np.zeros_like(t)
    t[~kept(t, p.tol.support_tol if support_tol is None else support_tol)] = 0.0
    t[p.sigma * t < 0] = 0.0
    w = t * t
    w[p.rod] += rod_weight * t_max**2
    nonpositive = 0  # consecutive rounds doing no positive work (see ``stall``)
    for _ in range(rounds):
        solver = p.factor_values(p.values(w, shift * t_max**2))
        r_prev = np.inf
        for _ in range(refine):
            r = p.RT @ t
            r_norm = float(np.abs(r).sum())
            if r_norm >= 0.5 * r_prev or r_norm <= p.tol.purify_roundoff * float(np.abs(t).sum()):
                break  # converged, or stagnating at round-off
            r_prev = r_norm
            t = t - w * (p.R @ solver.solve(r))
        if float(np.abs(p.RT @ t).sum()) > hopeless * float(np.abs(t).sum()):
            # far from any self-stress on this support: more rounds will not help, nor will
            # the extended-precision steps
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


def optimal_on_support(
    p: Problem,
    t: np.ndarray,
    rounds: int = 8,
    steps: int = 30,
    shift: float = 1e-14,
) -> np.ndarray | None:
    """The best self-stress for the energy's dual on the support of a minimiser's tensions.

    Every admissible self-stress bounds ``E* >= D(t) = t . e0 - 1/2 t . K^-1 t``, with equality
    at ``t*``. The stiffness-weighted correction ``t <- t - K_S R y``, ``(R^T K_S R) y = R^T t``
    on the support ``S`` of ``t`` (residuals in extended precision) converges to the maximiser of
    ``D`` over the self-stresses on ``S``, which is ``t*`` when ``S`` is the optimal engaged set;
    :func:`purify` weighs by ``t^2`` instead, which keeps signs but not that optimality. One-sided
    elements whose sign flips leave ``S`` and the projection is repeated (docs/model.md).

    Parameters
    ----------
    p : Problem
        The problem.
    t : (m,) float
        Tensions ``K (e0 + R u)`` of the engaged elements at some ``u`` (zero elsewhere).
    rounds : int
        Most projections (each one numeric factorisation), each after dropping the flipped
        one-sided elements.
    steps : int
        Most corrections per projection (they stop once one does not cut the residual by 0.7).
    shift : float
        Regularisation of ``R^T K_S R`` relative to the mean stiffness.

    Returns
    -------
    (m,) longdouble or None
        Admissible tensions on ``S`` (their force residual is for the certificate test to
        judge), or None when the support empties or nothing factorises.
    """
    x = np.asarray(t, dtype=np.longdouble)
    support = np.asarray(t, dtype=float) != 0
    for _ in range(rounds):
        if not support.any():
            return None
        w = np.where(support, p.k, 0.0)
        solver = p.factor_shifted(w, [shift, 1e2 * shift, 1e4 * shift])
        if solver is None:
            return None
        x = np.where(support, x, 0)
        r = p.exact.forces(x)
        r_norm = float(np.abs(r).sum())
        for _ in range(steps):
            # the net force is zero in exact arithmetic (see :func:`rebalance`)
            f = np.asarray(r, dtype=float).reshape(-1, p.dim)
            f = (f - f.mean(axis=0)).ravel()
            trial = x - w * (p.R @ solver.solve(f))
            r_trial = p.exact.forces(trial)
            r_trial_norm = float(np.abs(r_trial).sum())
            if not r_trial_norm < 0.7 * r_norm:
                break
            x, r, r_norm = trial, r_trial, r_trial_norm
        flipped = p.sigma * np.asarray(x, dtype=float) < 0
        if not flipped.any():
            return x
        support &= ~flipped
    return None


def kept(t: np.ndarray, support_tol: float) -> np.ndarray:
    """The entries of ``t`` ((m,) float) that :func:`purify` keeps at ``support_tol`` (before it
    drops wrong signs, which does not depend on the tolerance): ``|t_b| >= support_tol max |t|``.
    Two tolerances with the same mask give :func:`purify` the same input, hence the same
    result."""
    t = np.asarray(t, dtype=float)  # as purify sees it
    return ~(np.abs(t) < support_tol * float(np.abs(t).max(initial=0.0)))


def _refine_extended(p: Problem, t: np.ndarray, w: np.ndarray, solver, steps: int):
    """Mixed-precision refinement: residuals ``R^T t`` in extended precision (the problem's
    exact geometry), corrections from the double-precision factorisation, the tensions kept in
    extended precision. Each step removes most of the residual the last one left, down to the
    extended round-off (~1e-19 relative) where double precision stalls at ~1e-16. Stops when
    the residual no longer shrinks, or when a correction would flip a sign."""
    exact = p.exact
    t_ld = np.asarray(t, dtype=np.longdouble)
    r = exact.forces(t_ld)
    r_norm = float(np.abs(r).sum())
    for _ in range(steps):
        step = w * (p.R @ solver.solve(np.asarray(r, dtype=float)))
        trial = t_ld - step
        if np.any(p.sigma * trial < 0):
            break
        r_trial = exact.forces(trial)
        r_trial_norm = float(np.abs(r_trial).sum())
        if not r_trial_norm < 0.5 * r_norm:
            break
        t_ld, r, r_norm = trial, r_trial, r_trial_norm
    return t_ld


def rebalance(
    p: Problem,
    t: np.ndarray,
    steps: int = 20,
    shifts: tuple[float, ...] = (1e-18, 1e-16, 1e-14),
    rod_weight: float = 1e-6,
) -> np.ndarray | None:
    """Balance nearly balanced admissible tensions to extended round-off, keeping their signs.

    Purification stalls where the support of ``t`` has near-mechanisms: the residual lies
    along directions in which ``R^T W R`` is of the order of its regularisation, and the
    correction that would remove it flips the signs of a few small one-sided tensions, so the
    refinement stops. This continues with a smaller regularisation (the first of ``shifts``,
    relative to ``max t^2``, that factorises) and an active set: each correction
    ``-W R (R^T W R)^{-1} R^T t`` (residual in extended precision) is cut at the first
    one-sided element it would take through zero (a ratio test), that element is fixed at zero
    and leaves the weights, and the matrix is factorised again. A full correction that does
    not halve the residual ends it, unless it was the first on its factorisation: then the
    shift was too small for the solve to be accurate, and the next one is tried. At most
    ``steps`` corrections (and as many factorisations).

    Parameters
    ----------
    p : Problem
        The problem.
    t : (m,) float or longdouble
        Admissible tensions on the non-empty sites (a purified candidate).
    steps : int
        Most corrections.
    shifts : tuple of float
        Regularisations tried in turn, relative to ``max t^2``.
    rod_weight : float
        Weight of rods, relative to ``max t^2``, added to ``t^2``: rods may take up stress
        they did not carry (one-sided elements at zero may not: their sign is not known).

    Returns
    -------
    (m,) longdouble or None
        The tensions with the least relative residual met (admissible signs; ``t`` itself
        when nothing reduced it), or None when ``t`` is zero or not admissible.
    """
    exact = p.exact
    x = np.array(t, dtype=np.longdouble)
    tf = np.asarray(x, dtype=float)
    t_max = float(np.abs(tf).max(initial=0.0))
    if t_max == 0.0 or not np.isfinite(t_max) or np.any(p.sigma * tf < 0):
        return None
    w = tf * tf
    w[p.rod] += rod_weight * t_max**2
    r = exact.forces(x)
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
        # the net force is zero in exact arithmetic; its round-off would be amplified along
        # the translations, which the small shift barely regularises
        f = np.asarray(r, dtype=float).reshape(-1, p.dim)
        f = (f - f.mean(axis=0)).ravel()
        step = -(w * (p.R @ solver.solve(f)))
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
        r_trial = exact.forces(trial)
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
