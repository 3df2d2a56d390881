"""Semismooth Newton on the energy, its exact line search, and the active-set crossover.

All work on a :class:`~.problem.Problem` in its normalised units and decide nothing: the strategies
(:mod:`.stages`) offer their points to the certificates.
"""

from __future__ import annotations

import numpy as np

from .problem import Problem


def line_search(p: Problem, e: np.ndarray, s: np.ndarray) -> float:
    """Exact minimiser ``alpha >= 0`` of the energy along ``e + alpha s`` (extensions ``e`` (m,),
    ``s = R d`` (m,) for the direction ``d``), walking the sorted breakpoints where one-sided
    elements engage or slacken."""
    k, sig = p.k, p.sigma
    ks, kes = k * s * s, k * e * s
    et, st = sig * e, sig * s
    # elements engaged at alpha = 0+ (rods, or one-sided with et > 0, or et == 0 and st > 0)
    on0 = p.rod | (et > 0) | ((et == 0) & (st > 0))
    c, a = float(kes[on0].sum()), float(ks[on0].sum())
    # events: one-sided elements that switch at beta = -et/st > 0
    os = p.one_sided & (st != 0)
    beta = np.full(e.shape, -1.0)
    beta[os] = -et[os] / st[os]
    ev = os & (beta > 0)
    on = ev & (st > 0)  # engage at beta
    off = ev & (st < 0)  # slacken at beta (they are in on0)
    idx = np.flatnonzero(on | off)
    if idx.size == 0:
        return -c / a if a > 0 else 0.0
    order = idx[np.argsort(beta[idx], kind="stable")]
    sign = np.where(on[order], 1.0, -1.0)
    bpts = beta[order]
    seg_c = np.r_[c, c + np.cumsum(sign * kes[order])]  # per segment between breakpoints
    seg_a = np.r_[a, a + np.cumsum(sign * ks[order])]
    left, right = np.r_[0.0, bpts], np.r_[bpts, np.inf]
    with np.errstate(invalid="ignore", over="ignore"):
        slope_right = seg_c + seg_a * right
    slope_right[-1] = np.inf if seg_a[-1] > 0 else seg_c[-1]
    hit = np.flatnonzero(slope_right >= 0)
    if hit.size == 0:
        return float(bpts[-1])
    jj = int(hit[0])
    if seg_a[jj] <= 0:
        return float(left[jj])
    return float(np.clip(-seg_c[jj] / seg_a[jj], left[jj], right[jj]))


def prox_minimize(p: Problem, w: np.ndarray, x: np.ndarray, max_iter: int = 100):
    """Minimise ``1/2 sum_b w_b (e0 + R x)_b^2`` (``w`` (m,)) by at most ``max_iter`` proximal
    iterations from ``x`` (2N,) on one factorisation, stopping when the gradient has not halved for
    three (round-off then grows along floppy modes): the best iterate and its gradient norm."""
    solver = p.factor(w)
    best_x, best_g, g0, since = x, np.inf, None, 0
    for _ in range(max_iter):
        g = p.RT @ (w * (p.e0 + p.R @ x))
        gn = float(np.linalg.norm(g))
        g0 = gn if g0 is None else g0
        since = 0 if gn < 0.5 * best_g else since + 1
        if gn < best_g:
            best_x, best_g = x, gn
        if gn <= p.tol.prox_gradient_stop * max(g0, 1e-300) or gn == 0.0 or since >= 3:
            break
        x = x - solver.solve(g)
    return best_x, best_g


def newton(
    p: Problem,
    u: np.ndarray,
    max_iter: int,
    max_truncated: float = np.inf,
    energy_floor: float = 0.0,
) -> tuple[np.ndarray, float, int]:
    """Semismooth Newton with exact line search from ``u`` (2N,); returns (u, E, iterations).

    Steps solve ``(R^T D_A R + mu I) d = -R^T t`` on the active set. Stops after ``max_iter``, once
    ``E <= energy_floor``, at a round-off gradient, after three steps without progress, or after
    ``max_truncated`` steps in a row cut short at a breakpoint (the active set then crawls).
    """
    e, act, t = p.state(u)
    E = 0.5 * float(np.dot(t, e))
    best_g, stalled, E_prev, it, truncated = np.inf, 0, np.inf, 0, 0
    for it in range(1, max_iter + 1):  # noqa: B007 (it is reported)
        if E <= energy_floor:
            break
        g = p.RT @ t
        gn = float(np.linalg.norm(g))
        if gn <= p.tol.newton_gradient_stop * float(np.linalg.norm(t)):
            break
        # Progress is a lower energy or, once energies stop resolving it, a smaller gradient.
        progress = E < E_prev * (1.0 - p.tol.newton_progress) or gn < best_g
        stalled = 0 if progress else stalled + 1
        best_g, E_prev = min(best_g, gn), min(E_prev, E)
        if stalled >= 3:
            break
        d = -p.factor(p.k * act).solve(g)
        if float(np.dot(g, d)) >= 0:
            break  # no descent direction left at working precision
        alpha = line_search(p, e, p.R @ d)
        if alpha <= 0:
            break
        u = u + alpha * d
        e, act, t = p.state(u)
        E = 0.5 * float(np.dot(t, e))
        truncated = truncated + 1 if abs(alpha - 1.0) > p.tol.newton_full_step else 0
        if truncated >= max_truncated:
            break  # steps keep stopping at breakpoints: the active set crawls
    return u, E, it


def crossover(p: Problem, u: np.ndarray, tau: float | None = None, rounds: int = 12):
    """Exact solve on a guessed active set corrected by KKT signs (primal-dual active set).

    The guess: the rods and the one-sided elements within ``tau max |e0|`` of engaging (default the
    first of ``Tolerances.crossover_taus``), on which :func:`prox_minimize` minimises exactly;
    wrong-signed engaged elements are released and stretched slack ones added, for at most
    ``rounds``. Returns the displacements (2N,), or None when the rounds do not settle or the
    corrections grow (a wrong guess costs time, never a wrong verdict).
    """
    tau = p.tol.crossover_taus[0] if tau is None else tau
    scale = float(np.abs(p.e0).max())
    e = p.e0 + p.R @ u
    A = p.rod | (p.sigma * e > -tau * scale)
    tol, changes = p.tol.crossover_sign_tol * scale, np.inf
    for _ in range(rounds):
        best_x, _ = prox_minimize(p, p.k * A, u.copy())
        e = p.e0 + p.R @ best_x
        release = A & p.one_sided & (p.sigma * e < -tol)
        add = ~A & (p.sigma * e > tol)
        if not (release.any() or add.any()):
            return best_x
        if release.sum() + add.sum() > changes:
            return None  # the corrections grow: the guess was too far off to settle
        changes = release.sum() + add.sum()
        A = (A & ~release) | add
    return None
