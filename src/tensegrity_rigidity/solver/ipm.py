"""A primal-dual interior-point method specialised to the tensegrity energy.

With one slack per one-sided element the energy is a convex QP with bounds only, whose Newton
system's Schur complement ``R^T diag(k~) R`` has the Newton matrix's pattern: each Mehrotra
iteration is one refactorisation, and the iteration count hardly depends on the combinatorics that
slow active sets near the transition. ``anchored=True`` adds ``mu/2 |u|^2`` (docs/solver.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .problem import Problem


@dataclass(frozen=True, eq=False)
class IpmState:
    """Where a run of :func:`interior_point` ended, in the run's own units.

    The iteration is a function of its iterate alone, so a later run that would pass through this
    state may start there and end where it would have from the cold start.
    """

    #: The problem it ran on.
    problem: Problem
    #: Its ``anchored`` setting.
    anchored: bool
    #: Its tolerance.
    tol: float
    #: Newton steps taken from the cold start.
    steps: int
    #: Displacements.
    u: np.ndarray
    #: Slacks and multipliers of the ``k`` one-sided sites.
    w: np.ndarray
    lam: np.ndarray

    def resumes(self, p: Problem, max_iter: int, tol: float, anchored: bool) -> bool:
        """Whether a run on ``p`` with these settings passes through this state (the same problem
        object and objective, a tolerance at most this run's, at least ``steps`` iterations)."""
        same = self.problem is p and self.anchored == anchored
        return same and self.steps <= max_iter and tol <= self.tol


def interior_point(
    p: Problem,
    max_iter: int = 60,
    tol: float | None = None,
    checkpoints: tuple[float, ...] = (),
    callback=None,
    anchored: bool = False,
    start: IpmState | None = None,
    record: list[IpmState] | None = None,
):
    """Approximately minimise the energy of problem ``p``.

    Returns (u, w, lam, iterations): displacements (2N,), slacks and multipliers on the one-sided
    sites. Stops at scaled residuals and duality measure below ``tol`` (default
    ``Tolerances.relax_short_ipm``'s), when ``callback(u, lam)`` (called as the larger measure
    passes each of the decreasing ``checkpoints``) returns True, or at the last finite iterate when
    a slack underflows. ``start``: an earlier run's end through which this one passes
    (:meth:`IpmState.resumes`, no checkpoint pending); ``record``: a list this run's end is appended
    to.
    """
    tol = p.tol.relax_short_ipm[1] if tol is None else tol
    pending = sorted((c for c in checkpoints if c > tol), reverse=True)
    os_, k_all = p.one_sided, p.k
    sig, k = p.sigma[os_], k_all[os_]
    scale = max(float(np.abs(p.e0).max()), 1e-300)
    e0 = p.e0 / scale  # solve the unit-scale problem; displacements scale back linearly
    m_os = max(int(os_.sum()), 1)
    anchor = p.mu if anchored else 0.0
    warm = start if callback is None or not pending else None  # not with checkpoints pending
    if warm is not None and warm.resumes(p, max_iter, tol, anchored):
        steps, u, w, lam = warm.steps, warm.u, warm.w, warm.lam
        e = e0 + p.R @ u
    else:  # cold start: slacks that make every one-sided element slightly slack, unit multipliers
        steps, u = 0, np.zeros(p.n2)
        e = e0 + p.R @ u
        w = np.maximum(-sig * e[os_], 0.0) + 1.0
        lam = np.ones_like(w)

    def direction(tau):
        """Newton direction (du, dw, dlam) of the perturbed KKT system (complementarity target
        ``tau``), eliminated down to the Schur complement factorised in ``solver``."""
        q = -r_w - lam + tau / w
        rhs_full = np.zeros(p.k.size)
        rhs_full[os_] = k * sig * q / D
        du = solver.solve(-r_u - p.RT @ rhs_full)
        s = p.R @ du
        dw = (q - sig * k * s[os_]) / D
        dlam = -lam + tau / w - ratio * dw
        return du, dw, dlam

    it = steps
    for it in range(steps + 1, max_iter + 1):  # noqa: B007 (reported)
        eps_el = e.copy()
        eps_el[os_] += sig * w  # elastic extensions
        t = k_all * eps_el
        r_u = p.RT @ t + anchor * u
        r_w = sig * t[os_] - lam
        mu = float(w @ lam) / m_os if w.size else 0.0
        res = max(float(np.abs(r_u).max(initial=0.0)), float(np.abs(r_w).max(initial=0.0)))
        if res <= tol and mu <= tol:
            break
        if pending and max(res, mu) <= pending[0]:
            while pending and max(res, mu) <= pending[0]:
                pending.pop(0)
            if callback is not None and callback(u * scale, lam * scale):
                break
        with np.errstate(over="ignore"):
            ratio = lam / w
        if not np.all(np.isfinite(ratio)):  # a slack underflowed: stop before a NaN step
            break
        D = k + ratio
        ktil = k_all.copy()
        ktil[os_] = k * ratio / D
        solver = p.factor(ktil)

        # predictor (affine scaling), then the corrector with the same factorisation
        du, dw, dlam = direction(0.0)
        a_p, a_d = step_to_boundary(w, dw), step_to_boundary(lam, dlam)
        mu_aff = float((w + a_p * dw) @ (lam + a_d * dlam)) / m_os if w.size else 0.0
        sigma_c = (mu_aff / mu) ** 3 if mu > 0 else 0.0
        du, dw, dlam = direction(sigma_c * mu - dw * dlam)
        a_p = min(1.0, 0.99 * step_to_boundary(w, dw))
        a_d = min(1.0, 0.99 * step_to_boundary(lam, dlam))
        # u and w move together (primal), lambda separately (dual)
        u, w, lam = u + a_p * du, w + a_p * dw, lam + a_d * dlam
        e = e0 + p.R @ u
        steps += 1
    if record is not None:
        record.append(IpmState(p, anchored, tol, steps, u, w, lam))
    return u * scale, w * scale, lam * scale, it


def step_to_boundary(x: np.ndarray, dx: np.ndarray) -> float:
    """The largest step in (0, 1] that keeps ``x + a dx >= 0`` (``x`` > 0, both (k,))."""
    neg = dx < 0
    if not neg.any():
        return 1.0
    with np.errstate(over="ignore"):  # a tiny dx: the boundary is out of reach, inf is right
        return min(1.0, float(np.min(-x[neg] / dx[neg])))
