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
    support_tol: float = 1e-9,
    rounds: int = 8,
    refine: int = 6,
    hopeless: float = 1e-3,
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

    Returns
    -------
    (m,) float
        Tensions with admissible signs; ``R^T t`` is at round-off when the support of the
        input carries a self-stress near it, otherwise larger (the certificate test decides).
    """
    t = np.array(t, dtype=float)
    t_max = float(np.abs(t).max(initial=0.0))
    if t_max == 0.0 or not np.isfinite(t_max):
        return np.zeros_like(t)
    t[np.abs(t) < support_tol * t_max] = 0.0
    t[p.sigma * t < 0] = 0.0
    w = t * t
    w[p.rod] += 1e-6 * t_max**2  # rods may also take up stress they did not carry
    for _ in range(rounds):
        solver = p.factor_values(p.values(w, 1e-14 * t_max**2))
        r_prev = np.inf
        for _ in range(refine):
            r = p.RT @ t
            r_norm = float(np.abs(r).sum())
            if r_norm >= 0.5 * r_prev or r_norm <= 1e-16 * float(np.abs(t).sum()):
                break  # converged, or stagnating at round-off
            r_prev = r_norm
            t = t - w * (p.R @ solver.solve(r))
        if float(np.abs(p.RT @ t).sum()) > hopeless * float(np.abs(t).sum()):
            break  # far from any self-stress on this support: more rounds will not help
        flipped = p.sigma * t < 0
        if not flipped.any():
            break
        t[flipped] = 0.0
        w[flipped] = 0.0
    return t
