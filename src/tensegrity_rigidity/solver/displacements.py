"""Minimum-norm minimising displacements, with their optimality certificate.

Minimisers are not unique on floppy networks. Given the unique tensions ``t*``, the minimisers
form the polyhedron

    U* = {u : v_b = t*_b / k_b  on rods and stressed one-sided elements (equalities),
              sigma_b v_b <= 0   on unstressed one-sided elements (inequalities)},

``v = e0 + R u`` (on a floppy verdict ``t* = 0``: rods unstretched, the zero-energy set). The
reported displacements are the projection of the origin onto ``U*``, the limit of the
minimiser of ``E(u) + mu/2 |u|^2`` as ``mu -> 0`` (a vanishing background stiffness).

Method: a primal active set (see :func:`min_norm_minimizer`). For a working set ``A`` (the
equalities and the inequalities held tight) the projection of the origin onto the affine set
``{R_A u = c_A - e0_A}`` is the minimum-norm solution of the normal equations
``R_A^T R_A u = R_A^T (c_A - e0_A)``. It is computed by conjugate gradients from ``u = 0``,
preconditioned by the factorisation of ``R_A^T R_A + shift I`` in the solver's fixed
pattern: from the origin every iterate lies in the range of ``R_A^T``, so the limit is the
minimum-norm solution, also along near-floppy modes whose stiffness lies below round-off of
the assembled matrix (plain proximal iterations stall there). Its multipliers
``u = -R_A^T lam`` come from the same recurrence (:func:`_min_norm_solve`).

Certificate (KKT of the projection): primal feasibility (largest violation of ``U*``, units of
``max |e0|``), complementarity as the relative duality gap ``sum |lam_b v_b| / |u|^2``, dual
feasibility (largest wrong-signed multiplier of an inequality, relative to ``|lam|_inf``);
stationarity ``u + R^T lam = 0`` holds by construction. The displacements are
reported as minimum-norm (``min_norm_ok``) only when all three are below their tolerances.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .problem import Problem


@dataclass(frozen=True)
class MinNormResult:
    """The projection of the origin onto the minimisers and its KKT residuals.

    Attributes
    ----------
    u : (2N,) float
        Displacements (units of ``max |e0|``).
    feasibility : float
        Largest violation of the constraints of ``U*``.
    stationarity : float
        Complementarity as a relative duality gap, ``sum |lam_b v_b| / |u|^2`` over the
        inequalities (stationarity ``u + R^T lam = 0`` holds by construction): ``|u|^2`` is
        within this fraction of its minimum when the point is feasible.
    dual : float
        Largest wrong-signed multiplier of an inequality, relative to ``max |lam|``.
    rounds : int
        Active-set steps.
    ok : bool
        All three residuals below their tolerances.
    """

    u: np.ndarray
    feasibility: float
    stationarity: float
    dual: float
    rounds: int
    ok: bool


def _min_norm_solve(
    p: Problem, w: np.ndarray, b: np.ndarray, max_iter: int, shift: float
) -> tuple[np.ndarray, np.ndarray]:
    """Minimum-norm solution of ``R_A x = b_A`` (``A``: ``w > 0``) and its multipliers.

    Conjugate gradients on ``R^T W R x = R^T W b`` from ``x = 0``, preconditioned by the
    factorisation of ``M = R^T W R + shift I``. Every preconditioned residual has the form
    ``z = R^T W q`` with ``q = (rho - R z) / shift`` (``rho`` the residual in element space; the
    push-through identity ``M^-1 R^T W = R^T W (R R^T W + shift I)^-1``), so the recurrence is
    run on ``q`` beside ``z``: it gives ``s`` with ``x = R^T W s`` and hence the multipliers
    ``lam = W s`` of the constraints ``R_A x = b_A`` at no extra solve. Returns ``(x, lam)``.
    """
    solver = p.factor_values(p.values(w, shift))
    x = np.zeros(p.n2)
    s = np.zeros(w.size)
    rho = b.copy()  # residual b - R x in element space
    r = p.RT @ (w * rho)
    r0 = float(np.linalg.norm(r))
    if r0 == 0.0:
        return x, s
    z = solver.solve(r)
    q = (rho - p.R @ z) / shift
    d, e = z.copy(), q.copy()
    rz = float(r @ z)
    for _ in range(max_iter):
        Rd = p.R @ d
        Ad = p.RT @ (w * Rd)
        dAd = float(d @ Ad)
        if not dAd > 0:
            break
        alpha = rz / dAd
        x += alpha * d
        s += alpha * e
        rho -= alpha * Rd
        r -= alpha * Ad
        if float(np.linalg.norm(r)) <= 1e-15 * r0:
            break
        z = solver.solve(r)
        q = (rho - p.R @ z) / shift
        rz_new = float(r @ z)
        beta = rz_new / rz
        rz = rz_new
        d = z + beta * d
        e = q + beta * e
    return x, w * s


def min_norm_minimizer(
    p: Problem,
    t: np.ndarray,
    u_start: np.ndarray | None = None,
    tol: float = 1e-8,
    max_steps: int = 100,
    cg_iterations: int = 300,
    shift: float = 1e-4,
    polish_rounds: int = 6,
) -> MinNormResult:
    """Projection of the origin onto the minimisers ``U*`` of problem ``p``.

    Gradient projection with Newton steps on faces (in the manner of More and Toraldo's GPCG)
    on the dual. The dual of the projection is
    ``min f(lam) = 1/2 |R^T lam|^2 - lam . (e0 - c)`` over multipliers with ``sigma lam >= 0``
    on the inequalities (free on the equalities), with ``u = -R^T lam`` and gradient ``c - v``
    (``v = e0 + R u``). Each step first moves along the projected gradient path (a Cauchy
    step: it lowers ``f`` whenever ``lam`` is not optimal, and changes many bounds at once),
    then takes the Newton step on the face it reached: the multipliers at zero whose gradient
    pushes outwards are held, the others solve ``R_F R_F^T d = -grad_F`` (the minimum-norm
    solve of :func:`_min_norm_solve`), searched along the projected path. Once the face is
    the optimal one the Newton step is exact.

    Parameters
    ----------
    p : Problem
        The problem (its stiffnesses define ``t* / k``).
    t : (m,) float
        The unique tensions ``t*`` on the non-empty sites (zero on a floppy verdict).
    u_start : (2N,) float, optional
        Unused by the method (kept for callers that hold a minimiser); the iteration starts
        from ``lam = 0``.
    tol : float
        Tolerance of the feasibility and stationarity residuals (units of ``max |e0|``).
    max_steps : int
        Most steps (a Cauchy and a Newton step each).
    cg_iterations : int
        Most conjugate-gradient iterations per solve.
    shift : float
        Shift of the preconditioning factorisation, relative to unit weights.
    polish_rounds : int
        Exact solves on the working set the dual iterate points at, corrected by the signs
        of the KKT conditions (primal-dual active set), after the Newton steps.

    Returns
    -------
    MinNormResult
        The displacements and their KKT residuals (the best point found).
    """
    stressed = p.one_sided & (t != 0)
    eq = p.rod | stressed
    ineq = p.one_sided & ~stressed
    c = np.where(eq, t / p.k, 0.0)  # v_b = c_b on equalities, sigma v_b <= 0 on inequalities
    b = p.e0 - c
    lam = np.zeros(p.sites.size)
    u = np.zeros(p.n2)
    f = 0.0
    steps = 0
    for steps in range(1, max_steps + 1):  # noqa: B007 (reported)
        v = p.e0 + p.R @ u
        feas, comp, _ = _residuals(p, u, v, lam, eq, ineq, c)
        if feas <= tol and comp <= tol:
            break
        # 1. Cauchy step: the projected gradient path, from the step that would minimise f
        #    along -grad without bounds (it always lowers f unless lam is optimal)
        grad = c - v
        g = np.where(ineq & (p.sigma * lam <= 0) & (p.sigma * grad > 0), 0.0, grad)
        Rg = p.RT @ g
        curv = float(Rg @ Rg)
        if curv > 0:
            moved = _search(p, lam, -g, b, f, ineq, grad, first=float(g @ g) / curv)
            if moved is not None:
                lam, u, f = moved
        # 2. Newton step on the face the Cauchy point lies on (multipliers at zero with the
        #    gradient pushing outwards held there), searched along the projected path
        v = p.e0 + p.R @ u
        grad = c - v
        held = ineq & (p.sigma * lam <= 0)
        _, d = _min_norm_solve(p, (~held).astype(float), -grad, cg_iterations, shift)
        moved = _search(p, lam, d, b, f, ineq, np.where(held, 0.0, grad))
        if moved is not None:
            lam, u, f = moved
    v = p.e0 + p.R @ u
    best = (u, lam, _residuals(p, u, v, lam, eq, ineq, c))
    # Polish: the working set the dual iterate points at (equalities and the inequalities
    # whose multiplier is positive), solved exactly; violated inequalities join it and
    # wrong-signed multipliers leave it (a few primal-dual active-set rounds).
    A = eq | (ineq & (p.sigma * lam > 0))
    for _ in range(polish_rounds):
        steps += 1
        w = A.astype(float)
        x, lam_a = _min_norm_solve(p, w, p.e0 - c, cg_iterations, shift)
        u_a = -x
        v_a = p.e0 + p.R @ u_a
        res = _residuals(p, u_a, v_a, lam_a, eq, ineq, c)
        if max(res[0], res[1]) + res[2] < max(best[2][0], best[2][1]) + best[2][2]:
            best = (u_a, lam_a, res)
        violated = ineq & ~A & (p.sigma * v_a > tol)
        wrong = ineq & A & (p.sigma * lam_a < 0)
        if not (violated.any() or wrong.any()):
            break
        A = (A | violated) & ~wrong
    u, lam, (feas, comp, dual) = best
    ok = feas <= tol and comp <= tol and dual <= 1e-9
    return MinNormResult(u, feas, comp, dual, steps, ok)


def _search(p, lam, d, b, f, ineq, grad, first: float = 1.0, tries: int = 40):
    """Armijo search along the projected path ``P(lam + a d)`` from ``a = first``; None if
    nothing decreases ``f``."""
    alpha = first
    for _ in range(tries):
        trial = lam + alpha * d
        trial[ineq] = p.sigma[ineq] * np.maximum(p.sigma[ineq] * trial[ineq], 0.0)
        u = -(p.RT @ trial)
        f_trial = 0.5 * float(u @ u) - float(trial @ b)
        if f_trial <= f + 1e-4 * float(grad @ (trial - lam)) and f_trial < f:
            return trial, u, f_trial
        alpha *= 0.5
    return None


def _residuals(p, u, v, lam, eq, ineq, target):
    """(feasibility, complementarity, dual) residuals of a dual iterate (``u = -R^T lam``
    exactly, so stationarity holds by construction)."""
    feas_eq = np.abs(v - target)[eq].max(initial=0.0)
    feas_in = np.maximum(p.sigma * v, 0.0)[ineq].max(initial=0.0)
    lam_max = max(float(np.abs(lam).max(initial=0.0)), 1e-300)
    # complementarity as the relative duality gap: sum |lam_b v_b| over the inequalities is
    # the gap between 1/2 |u|^2 and the dual value, so |u|^2 is within it of the optimum
    comp = float(np.sum((np.abs(lam) * np.abs(v))[ineq])) / max(float(u @ u), 1e-300)
    # stationarity (exact for the dual iterates, to solver accuracy for the polished ones)
    stat = float(np.abs(u + p.RT @ lam).max(initial=0.0)) / max(
        float(np.abs(u).max(initial=0.0)), 1e-300
    )
    dual = float(np.maximum(-p.sigma * lam, 0.0)[ineq].max(initial=0.0)) / lam_max
    return float(max(feas_eq, feas_in)), max(comp, stat), dual
