"""Minimum-norm minimising displacements, with their optimality certificate.

Minimisers are not unique on floppy networks. Given the unique tensions ``t*`` they form a
polyhedron ``U*`` (equalities on rods and stressed one-sided elements, inequalities on the
others), and the reported displacements are the projection of the origin onto it: the limit of
a vanishing background stiffness. :func:`active_set` tries the projection first where ``t*`` is
not zero (a rigid sample's equalities leave few inequalities to guess); the primal-dual
interior point :func:`min_norm_minimizer` does the rest. Both solve reduced ``2N x 2N`` systems
in the pattern of the verdict's Newton matrix (:class:`_ReducedKKT`), whose identity block
keeps them regular however near-floppy the network is. The result is reported as minimum-norm
only when its KKT residuals (feasibility, stationarity with the duality gap, dual) are below
their tolerances. docs/model.md ("The minimum-norm projection") gives the derivation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from .certificates import EPS
from .ipm import step_to_boundary
from .linalg import PatternFactor
from .problem import Problem

if TYPE_CHECKING:
    from .relaxation import Relaxation


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
        The larger of the stationarity residual ``|u + R^T lam|_inf / |u|_inf`` and the
        complementarity as a relative duality gap, ``sum |lam_b v_b| / |u|^2`` over the
        inequalities: ``|u|^2`` is within twice this fraction of its minimum when the point is
        feasible.
    dual : float
        Largest wrong-signed multiplier of an inequality, relative to ``max |lam|``.
    rounds : int
        Iterations (each one numeric factorisation).
    ok : bool
        All three residuals below their tolerances.
    multipliers : (m,) float or longdouble, optional
        The multipliers ``lam`` of the residuals (``u = -R^T lam`` at the projection,
        ``sigma lam >= 0`` on the inequalities), where the method has them.
    norm_lower : float
        A certified lower bound on ``|u*|^2``, the squared norm of the projection itself
        (units of ``max |e0|`` squared), from the multipliers by weak duality
        (:func:`norm_lower_bound`): computed by :func:`min_norm_minimizer` where it ends
        uncertified, NaN elsewhere.
    """

    u: np.ndarray
    feasibility: float
    stationarity: float
    dual: float
    rounds: int
    ok: bool
    multipliers: np.ndarray | None = None
    norm_lower: float = float("nan")


@dataclass(frozen=True)
class MinimumNorm:
    """The displacements :func:`~tensegrity_rigidity.solver.core.solve` reports.

    Attributes
    ----------
    status : str
        "certified" (the minimum-norm minimiser, by its KKT residuals), "uncertified" (a
        minimiser), "not computed" (the relaxed energy is not certified) or "not asked".
    message : str
        Why the displacements are not certified minimum-norm ("" when they are).
    u : (2N,) float
        The displacements (units of ``max |e0|``).
    residuals : tuple of 3 float
        Feasibility, stationarity and dual KKT residuals (NaN where no projection ran).
    norm_lower : float
        Where the projection ran uncertified, a lower bound on ``|u*|^2``; NaN elsewhere.
    """

    status: str
    message: str
    u: np.ndarray
    residuals: tuple[float, float, float] = (np.nan, np.nan, np.nan)
    norm_lower: float = np.nan

    @property
    def ok(self) -> bool:
        """Whether ``u`` is the certified minimum-norm minimiser."""
        return self.status == "certified"


def minimum_norm(relaxed: Relaxation, asked: bool = True) -> MinimumNorm:
    """The minimum-norm minimiser of a relaxed state, projected from its displacements.

    Parameters
    ----------
    relaxed : Relaxation
        The relaxed state (its problem, displacements and tensions).
    asked : bool
        Whether to compute it (``SolverOptions.min_norm``).

    Returns
    -------
    MinimumNorm
        The displacements, their status and KKT residuals.

    Notes
    -----
    The polyhedron of minimisers is built from the relaxed tensions: it is ``U*`` only when they
    are ``t*``, which the energy's lower bound certifies, so it is not projected onto
    otherwise. The targets are ``t*/k`` as the relaxed minimiser realises them on every
    equality (rods, and one-sided elements where the balanced tensions are not zero), so that
    the equalities are consistent: a rod's target is its extension at ``u`` even where its
    balanced tension is 0.
    """
    p, u = relaxed.problem, relaxed.u
    if not (p.sites.size and np.any(p.e0)):  # nothing strained or no element: u = 0 is exact
        if asked:
            return MinimumNorm("certified", "", np.zeros(p.n2), (0.0, 0.0, 0.0))
        return MinimumNorm("not asked", _NOT_ASKED, u)
    if not asked:
        return MinimumNorm("not asked", _NOT_ASKED, u)
    if not relaxed.certified:
        message = (
            f"minimum-norm displacements not computed: {relaxed.message}, so its tensions "
            "need not be t*; the displacements are the relaxation's lowest point"
        )
        return MinimumNorm("not computed", message, u)
    targets = np.where(p.rod | (relaxed.tensions != 0), relaxed.tensions_relaxed, 0.0)
    mn = project(p, targets, u)
    kkt = (mn.feasibility, mn.stationarity, mn.dual)
    if mn.ok:
        return MinimumNorm("certified", "", mn.u, kkt)
    message = (
        "minimum-norm displacements not certified (KKT residuals: feasibility "
        f"{mn.feasibility:.1e}, stationarity {mn.stationarity:.1e}, dual {mn.dual:.1e}); the "
        "displacements are a minimiser; the minimum norm is at least "
        f"{np.sqrt(mn.norm_lower):.3g} times the largest affine extension"
    )
    return MinimumNorm("uncertified", message, u, kkt, mn.norm_lower)


_NOT_ASKED = "minimum-norm displacements not asked for (SolverOptions.min_norm)"


def project(p: Problem, t: np.ndarray, u_start: np.ndarray | None = None) -> MinNormResult:
    """The minimum-norm minimiser: :func:`active_set` where ``t`` is not zero and a start is
    given, then, unless that is certified, :func:`min_norm_minimizer` (see the module
    docstring).

    Parameters
    ----------
    p : Problem
        The problem.
    t : (m,) float
        The unique tensions ``t*`` on the non-empty sites.
    u_start : (2N,) float, optional
        A minimiser (the verdict's).

    Returns
    -------
    MinNormResult
        The first certified result, else the interior point's.
    """
    if np.any(t) and u_start is not None:
        first = active_set(p, t, u_start)
        if first.ok:
            return first
    return min_norm_minimizer(p, t, u_start)


def active_set(
    p: Problem,
    t: np.ndarray,
    u_start: np.ndarray,
    tol: float = 1e-8,
    max_iterations: int = 5,
    regularization: float = 1e-14,
    refinement: int = 3,
    corrections: int = 4,
) -> MinNormResult:
    """Projection of the origin onto ``U*`` by a primal-dual active set: each iteration solves
    the projection onto the equalities and the held inequalities, all as equalities.

    The held set starts as the inequalities the start touches; each iteration takes one step of
    :class:`_ReducedKKT` from ``u_start`` (its third block's diagonal zero) and checks the KKT
    residuals of :func:`min_norm_minimizer` with the multipliers of the held rows. Where they are
    not certified, the next held set is the held inequalities whose multiplier has the right sign
    and the others the new point violates; where that leaves it as it was, up to ``corrections``
    further steps on the same factorisation run while each halves the feasibility and
    stationarity residuals. It suits rigid verdicts (:func:`project`), whose equalities fix all
    but a few mechanisms; on floppy ones its stationarity stalls.

    Parameters
    ----------
    p : Problem
        The problem (its stiffnesses define ``t* / k``).
    t : (m,) float
        The unique tensions ``t*`` on the non-empty sites.
    u_start : (2N,) float
        A minimiser (the verdict's): each iteration's step starts there.
    tol : float
        Tolerance of the feasibility and stationarity residuals (units of ``max |e0|``).
    max_iterations : int
        Most iterations (each one numeric factorisation).
    regularization : float
        ``d`` of :class:`_ReducedKKT`.
    refinement : int
        Steps of iterative refinement per solve, against the unregularised system.
    corrections : int
        Most further solves with the same factorisation where the held set did not change but
        the residuals are not certified (the start can lie far from ``U*``'s lowest point along
        the held rows' mechanisms).

    Returns
    -------
    MinNormResult
        The last iterate (``rounds``: the iterations, each one factorisation).
    """
    eq, ineq, c, E, In = _polyhedron(p, t)
    u0 = np.asarray(u_start, dtype=float)
    sig = p.sigma[In]

    def scale(u):
        return max(1.0, float(np.abs(u).max(initial=0.0)))

    v = p.e0 + p.R @ u0
    held = sig * v[In] >= -p.tol.min_norm_held * scale(u0)  # touched by the start
    bE = (c - p.e0)[E]
    u = u0
    residuals: tuple[float, float, float] = (np.inf, np.inf, np.inf)
    it = 0
    for it in range(1, max_iterations + 1):
        H = In[held]
        kkt_system = _ReducedKKT(p, E, H, sig[held], regularization, refinement)
        try:
            kkt_system.factor(np.zeros(H.size))  # the held rows as equalities
        except ArithmeticError:
            break
        h = -(p.sigma * p.e0)[H]
        polyhedron = (E, H, eq, ineq, c)
        start = (u0, np.zeros(E.size), np.zeros(H.size))
        u, y, z, residuals = _equality_step(p, kkt_system, bE, h, start, polyhedron)
        if _certified(*residuals, tol, p.tol.min_norm_dual):
            return MinNormResult(u, *residuals, it, True)
        v = p.e0 + p.R @ u
        z_all = np.zeros(In.size)
        z_all[held] = z
        new = (sig * v[In] > p.tol.min_norm_violated * scale(u)) | (
            held & (z_all >= 0)
        )  # violated, or right sign
        if not np.array_equal(new, held):
            held = new
            continue
        # the held set stands, the residuals do not: correct on the same factorisation while
        # that halves the feasibility and stationarity residuals
        for _ in range(corrections):
            previous = max(residuals[:2])
            u, y, z, residuals = _equality_step(p, kkt_system, bE, h, (u, y, z), polyhedron)
            if _certified(*residuals, tol, p.tol.min_norm_dual):
                return MinNormResult(u, *residuals, it, True)
            if max(residuals[:2]) >= 0.5 * previous:
                break
        break
    return MinNormResult(u, *residuals, it, False)


def _equality_step(
    p: Problem, kkt_system: _ReducedKKT, bE, h, point, polyhedron
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[float, float, float]]:
    """The Newton step of :func:`active_set`'s equality-constrained projection from ``point =
    (u, y, z)`` (a step from a point it reached is a correction: the same linear system), and
    the KKT residuals where it ends; ``polyhedron`` is ``(E, H, eq, ineq, c)``."""
    u, y, z = point
    du, dy, dz = kkt_system.solve(
        -(u + kkt_system.REt @ y + kkt_system.Gt @ z), bE - kkt_system.RE @ u, h - kkt_system.G @ u
    )
    u, y, z = u + du, y + dy, z + dz
    E, H, eq, ineq, c = polyhedron
    return u, y, z, _certificate(p, u, y, z, E, H, eq, ineq, c)


def min_norm_minimizer(
    p: Problem,
    t: np.ndarray,
    u_start: np.ndarray | None = None,
    tol: float = 1e-8,
    max_iterations: int = 150,
    regularization: float = 1e-14,
    refinement: int = 3,
    predictor_refinement: int = 0,
    refine_multipliers: bool = True,
) -> MinNormResult:
    """Projection of the origin onto the minimisers ``U*`` of problem ``p``.

    Parameters
    ----------
    p : Problem
        The problem (its stiffnesses define ``t* / k``).
    t : (m,) float
        The unique tensions ``t*`` on the non-empty sites (zero on a floppy verdict).
    u_start : (2N,) float, optional
        A minimiser (the verdict's): the iteration starts there (else at ``u = 0``).
    tol : float
        Tolerance of the feasibility and stationarity residuals (units of ``max |e0|``).
    max_iterations : int
        Most interior-point iterations (each one numeric factorisation).
    regularization : float
        ``d``, the diagonal regularisation of the interior-point system (:class:`_ReducedKKT`).
    refinement : int
        Steps of iterative refinement of the corrector's solve (the step taken), against the
        unregularised system.
    predictor_refinement : int
        Steps of iterative refinement of the predictor's solve. The predictor only sets the
        centring and the corrector's second-order term, and the corrector's own solve is
        refined: unrefined, an iteration costs 5 triangular solves instead of 8.
    refine_multipliers : bool
        Where the iteration ends at a feasible point it has not certified, refine its
        multipliers in extended precision and check again (:func:`_refined_certificate`):
        near a sample's own threshold their size can stall the stationarity residual at the
        round-off of ``R^T lam``.

    Returns
    -------
    MinNormResult
        The displacements and their KKT residuals: the first iterate certified with a
        margin (``min_norm_certify_below``), else the iterate with the smallest KKT residual.
    """
    eq, ineq, c, E, In = _polyhedron(p, t)
    kkt_system = _ReducedKKT(p, E, In, p.sigma[In], regularization, refinement)
    RE, G, REt, Gt = kkt_system.RE, kkt_system.G, kkt_system.REt, kkt_system.Gt
    bE = (c - p.e0)[E]
    h = -(p.sigma * p.e0)[In]
    mI = In.size
    u = np.zeros(p.n2) if u_start is None else np.array(u_start, float)
    # multipliers on the scale of the start: u = -R^T lam needs |lam| of order |u| (z = 1
    # instead took about twice the iterations near the threshold, where |u| is 1e3 to 1e7)
    y, z = np.zeros(E.size), np.full(mI, max(1.0, float(np.abs(u).max(initial=0.0))))
    s = np.maximum(h - G @ u, 1.0)
    best: tuple | None = None
    it = 0
    for it in range(1, max_iterations + 1):
        rd = u + REt @ y + Gt @ z
        re = RE @ u - bE
        ri = G @ u + s - h
        mu = float(z @ s) / max(mI, 1)
        size = max(1.0, float(np.abs(u).max(initial=0.0)))
        kkt = max(
            float(np.abs(re).max(initial=0.0)),
            float(np.abs(ri).max(initial=0.0)),
            float(np.abs(rd).max(initial=0.0)) / size,
            mI * mu / size**2,
        )
        if best is None or kkt < best[0]:
            best = (kkt, u.copy(), y.copy(), z.copy(), it)
        if kkt <= p.tol.min_norm_kkt_exact or (kkt < p.tol.min_norm_kkt_stall and it - best[4] > 8):
            break
        if kkt <= p.tol.min_norm_certify_below:
            residuals = _certificate(p, u, y, z, E, In, eq, ineq, c)
            if _certified_with_margin(*residuals, tol, p.tol.min_norm_dual):
                return MinNormResult(u, *residuals, it, True, _multipliers(p, y, z, E, In))
        try:
            kkt_system.factor(s / z)
        except ArithmeticError:  # numerically singular: keep the best iterate
            break
        residuals = (rd, re, ri)
        du, dy, dz, ds = kkt_system.newton(  # predictor (affine scaling)
            residuals, z * s, z, s, predictor_refinement
        )
        a = min(step_to_boundary(z, dz), step_to_boundary(s, ds))
        mu_aff = float((z + a * dz) @ (s + a * ds)) / max(mI, 1)
        centring = (mu_aff / mu) ** 3 if mu > 0 else 0.0
        du, dy, dz, ds = kkt_system.newton(  # corrector
            residuals, z * s + dz * ds - centring * mu, z, s
        )
        a = 0.99 * min(step_to_boundary(z, dz), step_to_boundary(s, ds))
        u += a * du
        y += a * dy
        z += a * dz
        s += a * ds
    assert best is not None
    _, u, y, z, _ = best
    lam = _multipliers(p, y, z, E, In)
    feas, stat, dual = _residuals(p, u, p.e0 + p.R @ u, lam, eq, ineq, c)
    ok = _certified(feas, stat, dual, tol, p.tol.min_norm_dual)
    if refine_multipliers and not ok and feas <= tol:  # see refine_multipliers
        refined = _refined_certificate(p, u, lam, eq, ineq, c)
        if refined is not None and _certified(*refined[0], tol, p.tol.min_norm_dual):
            (feas, stat, dual), lam = refined
            ok = True
    lower = np.nan if ok else norm_lower_bound(p, lam, eq, ineq, c)
    return MinNormResult(u, feas, stat, dual, it, ok, lam, lower)


def norm_lower_bound(p: Problem, lam: np.ndarray, eq, ineq, c) -> float:
    """A certified lower bound on ``|u*|^2`` from any multipliers, by weak duality.

    For multipliers ``lam`` with ``sigma lam >= 0`` on the inequalities the dual function of the
    projection, ``g(lam) = -1/2 |R^T lam|^2 + lam . (e0 - c)``, bounds ``1/2 |u*|^2`` from below
    whether or not ``lam`` is optimal (wrong-signed multipliers are set to 0 first). It is evaluated
    on the certificates' geometry, less bounds on its round-off: where the interior point stalls
    near a threshold, this is what is known of the minimum norm.

    Parameters
    ----------
    p : Problem
        The problem.
    lam : (m,) float or longdouble
        Multipliers (``u = -R^T lam`` at the projection).
    eq, ineq : (m,) bool
        The polyhedron's equalities and inequalities (:func:`_polyhedron`).
    c : (m,) float
        Its targets.

    Returns
    -------
    float
        ``2 g(lam)`` less its round-off bound, or 0 where that is negative.
    """
    lam_x = np.where(eq | (ineq & (p.sigma * np.asarray(lam, dtype=float) >= 0)), lam, 0)
    lam_x = np.asarray(lam_x, dtype=np.longdouble)
    forces = p.exact.forces(lam_x)
    # |R^T lam| of the exact geometry is at most |forces| + their round-off, per component
    upper = np.abs(forces) + _force_roundoff(p, lam_x)
    # the two sums (NumPy's pairwise summation, in extended precision; a longdouble dot
    # product would add in turn) less bounds on their summation errors
    sums = float(np.ceil(np.log2(max(lam_x.size, 2)))) + 2.0
    square = np.sum(upper * upper) * (1 + 2 * sums * EPS)
    target = np.asarray(p.e0, dtype=np.longdouble) - np.asarray(c, dtype=np.longdouble)
    terms = lam_x * target
    linear = terms.sum() - sums * EPS * np.abs(terms).sum()
    bound = float(2 * linear - square)
    # the last subtraction and the rounding to double, each within 2^-52 relative
    return max(0.0, bound - abs(bound) * 2.0**-51)


def _polyhedron(p: Problem, t: np.ndarray):
    """``U*`` of the tensions ``t`` ((m,)): masks of its equalities (rods and stressed
    one-sided elements) and inequalities (the other one-sided elements), each (m,) bool; the
    targets ``c`` ((m,), ``v_b = c_b`` on the equalities, ``sigma_b v_b <= 0`` on the
    inequalities); the indices of both."""
    stressed = p.one_sided & (t != 0)
    eq = p.rod | stressed
    ineq = p.one_sided & ~stressed
    c = np.where(eq, t / p.k, 0.0)
    return eq, ineq, c, np.flatnonzero(eq), np.flatnonzero(ineq)


def _certified(
    feasibility: float, stationarity: float, dual: float, tol: float, dual_tol: float
) -> bool:
    """The KKT residuals within their tolerances (``tol``; ``dual_tol`` for ``dual``)."""
    return feasibility <= tol and stationarity <= tol and dual <= dual_tol


def _certified_with_margin(
    feasibility: float, stationarity: float, dual: float, tol: float, dual_tol: float
):
    """Certified (:func:`_certified`) with feasibility ``100`` times and the other residuals
    ``10`` times below ``tol``: where :func:`min_norm_minimizer` stops."""
    return (
        _certified(feasibility, stationarity, dual, tol, dual_tol)
        and feasibility <= 1e-2 * tol
        and max(stationarity, dual) <= 0.1 * tol
    )


def _multipliers(p, y, z, E, In) -> np.ndarray:
    """The multipliers ``lam`` ((m,)) of the equalities ``y`` and inequalities ``z``, such that
    ``u = -R^T lam`` at the projection and ``sigma lam >= 0`` on the inequalities."""
    lam = np.zeros(p.sites.size)
    lam[E] = y
    lam[In] = p.sigma[In] * z
    return lam


def _certificate(p, u, y, z, E, In, eq, ineq, c) -> tuple[float, float, float]:
    """The KKT residuals (:func:`_residuals`) of displacements ``u`` and multipliers y, z."""
    return _residuals(p, u, p.e0 + p.R @ u, _multipliers(p, y, z, E, In), eq, ineq, c)


def _refined_certificate(
    p: Problem, u: np.ndarray, lam: np.ndarray, eq, ineq, c, steps: int = 2
) -> tuple[tuple[float, float, float], np.ndarray] | None:
    """The KKT residuals of ``u`` (2N,) with its multipliers ``lam`` (m,) refined in extended
    precision, and those multipliers ((m,) longdouble); None when the factorisation fails.

    Near a sample's own threshold the multipliers can grow to ``1e8`` times ``|u|`` along
    near-self-stresses of the constraints, where the stationarity residual ``u + R^T lam`` is the
    round-off of ``R^T lam`` in double precision. Each step corrects ``lam`` by the least-squares
    solution of ``R^T dlam = -(u + R^T lam)``, the residual evaluated in extended precision and
    ``lam`` accumulated in it (one factorisation of ``R^T R + shift I``, one solve per step). The
    stationarity reported includes a bound on the round-off of the extended-precision forces.
    """
    f = p.factor_shifted(np.ones(p.sites.size), p.tol.min_norm_multiplier_shifts)
    if f is None:
        return None
    U = np.asarray(u, dtype=np.longdouble)
    lam_x = np.asarray(lam, dtype=np.longdouble)
    for _ in range(steps):
        r = U + p.exact.forces(lam_x)
        lam_x = lam_x - p.R @ f.solve(np.asarray(r, dtype=float))
    lam_f = np.asarray(lam_x, dtype=float)
    roundoff = float(_force_roundoff(p, lam_f).max(initial=0.0))
    stat = (float(np.abs(U + p.exact.forces(lam_x)).max(initial=0.0)) + roundoff) / max(
        float(np.abs(u).max(initial=0.0)), 1e-300
    )
    return _residuals(p, u, p.e0 + p.R @ u, lam_f, eq, ineq, c, stationarity=stat), lam_x


def _force_roundoff(p: Problem, lam: np.ndarray) -> np.ndarray:
    """Per-component bound (2N,) on the round-off of ``p.exact.forces(lam)``: each force sums
    products of at most the node's degree, ``exact.roundoff`` bounds their relative round-off,
    so the node's sum of ``|lam_b|`` bounds the absolute."""
    return p.exact.roundoff * (abs(p.RT) @ np.abs(lam))


class _ReducedKKT:
    """The interior-point system of the projection, reduced to ``2N x 2N``.

    The step of :func:`min_norm_minimizer` (and, with ``D = 0``, of :func:`active_set`) solves

        [ I    R_E^T   G^T  ] [du]   [r1]
        [ R_E  0       0    ] [dy] = [r2],    G = diag(sigma) R_I,  D = S / Z.
        [ G    0       -D   ] [dz]   [r3]

    Regularised by ``d`` in its last two blocks, ``dy`` and ``dz`` are eliminated, leaving
    ``(d I + R_E^T R_E + G^T diag(d / (D + d)) G) du = d r1 + R_E^T r2 + G^T (d r3 / (D + d))``:
    a matrix in the pattern of the verdict's Newton matrix, factorised by the problem's sparse
    Cholesky. A solve can be refined against the unregularised system, which removes the errors
    the elimination leaves along the mechanisms of ``R_E`` (order ``eps / d``).
    """

    def __init__(self, p: Problem, E, In, sigma_in, d: float, refinement: int):
        R = p.R.tocsr()
        self.p, self.In = p, In
        self.RE = R[E]
        self.G = (sp.diags(sigma_in) @ R[In]).tocsr()
        # the transposes once (``.T`` builds a new matrix object on every call)
        self.REt, self.Gt = self.RE.T.tocsr(), self.G.T.tocsr()
        # both constraint blocks stacked, so that each product is one sparse product
        self.B = sp.vstack([self.RE, self.G], format="csr")
        self.Bt = self.B.T.tocsr()
        self.mE = E.size
        self.d, self.refinement = d, refinement
        self._lower = np.zeros(E.size + In.size)  # the lower diagonal blocks: 0 and -D
        self._inverse = np.full(E.size + In.size, 1.0 / d)  # 1 / (regularised blocks)
        self._factor: PatternFactor | None = None
        self._weights = np.zeros(p.sites.size)
        self._weights[E] = 1.0

    def factor(self, D: np.ndarray) -> None:
        """Factorise with the third block's diagonal ``D``; raises ArithmeticError when the
        reduced matrix is numerically singular."""
        self._lower[self.mE :] = D
        self._inverse[self.mE :] = 1.0 / (D + self.d)
        self._weights[self.In] = self.d * self._inverse[self.mE :]
        f = self.p.factor_shifted(self._weights, [self.d])
        if f is None:
            raise ArithmeticError("the projection's reduced system is numerically singular")
        self._factor = f

    def newton(self, residuals, rc, z, s, refinement: int | None = None):
        """(du, dy, dz, ds) of the interior-point step for the residuals ``(rd, re, ri)`` and
        the complementarity residual ``rc``, at multipliers ``z`` and slacks ``s``, with
        ``refinement`` steps of iterative refinement (default: the system's own)."""
        rd, re, ri = residuals
        du, dy, dz = self.solve(-rd, -re, -ri + rc / z, refinement)
        return du, dy, dz, -(rc + s * dz) / z

    def _regularised(self, r1, r2):
        """(du, dw) of the regularised system with right-hand side ``(r1, r2)``, ``r2`` and
        ``dw = (dy, dz)`` stacked."""
        assert self._factor is not None
        du = self._factor.solve(self.d * (r1 + self.Bt @ (self._inverse * r2)))
        return du, (self.B @ du - r2) * self._inverse

    def solve(self, r1, r2, r3, refinement: int | None = None):
        """(du, dy, dz) of the unregularised system with right-hand side (r1, r2, r3), refined
        ``refinement`` times (default: the system's own count)."""
        r23 = np.concatenate([r2, r3])
        du, dw = self._regularised(r1, r23)
        for _ in range(self.refinement if refinement is None else refinement):
            c, cw = self._regularised(
                r1 - (du + self.Bt @ dw), r23 - (self.B @ du - self._lower * dw)
            )
            du, dw = du + c, dw + cw
        return du, dw[: self.mE], dw[self.mE :]


def _residuals(p, u, v, lam, eq, ineq, target, stationarity: float | None = None):
    """(feasibility, max(complementarity, stationarity), dual) residuals of ``(u, lam)``; the
    stationarity ``|u + R^T lam|_inf / |u|_inf`` in double precision unless given."""
    feas_eq = np.abs(v - target)[eq].max(initial=0.0)
    feas_in = np.maximum(p.sigma * v, 0.0)[ineq].max(initial=0.0)
    lam_max = max(float(np.abs(lam).max(initial=0.0)), 1e-300)
    # complementarity as the relative duality gap: sum |lam_b v_b| over the inequalities is
    # the gap between 1/2 |u|^2 and the dual value, so 1/2 |u|^2 is within it of its minimum
    comp = float(np.sum((np.abs(lam) * np.abs(v))[ineq])) / max(float(u @ u), 1e-300)
    if stationarity is None:
        stationarity = float(np.abs(u + p.RT @ lam).max(initial=0.0)) / max(
            float(np.abs(u).max(initial=0.0)), 1e-300
        )
    dual = float(np.maximum(-p.sigma * lam, 0.0)[ineq].max(initial=0.0)) / lam_max
    return float(max(feas_eq, feas_in)), max(comp, stationarity), dual
