"""Minimum-norm minimising displacements, with their optimality certificate.

Given the unique tensions ``t*`` the minimisers form a polyhedron ``U*`` (equalities on rods and
stressed one-sided elements, inequalities on the others); the reported displacements are the
projection of the origin onto it, the limit of a vanishing background stiffness: a primal-dual
active set (:func:`active_set`) first where ``t*`` is not zero, else a primal-dual interior point
(:func:`min_norm_minimizer`), both on reduced systems in the Newton matrix's pattern, certified only
by their KKT residuals (docs/model.md, "The relaxed state"; docs/solver.md).
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


@dataclass(frozen=True, eq=False)
class MinNormResult:
    """The projection of the origin onto the minimisers and its KKT residuals."""

    #: Displacements (units of ``max |e0|``).
    u: np.ndarray
    #: Largest violation of the constraints of ``U*``.
    feasibility: float
    #: The larger of ``|u + R^T lam|_inf / |u|_inf`` and the relative duality gap ``sum |lam_b v_b|
    #: / |u|^2`` over the inequalities.
    stationarity: float
    #: Largest wrong-signed multiplier of an inequality, relative to ``max |lam|``.
    dual: float
    #: Iterations (each one numeric factorisation).
    rounds: int
    #: All three residuals below their tolerances.
    ok: bool
    #: ``lam`` (``u = -R^T lam`` at the projection, ``sigma lam >= 0`` on the inequalities).
    multipliers: np.ndarray | None = None
    #: Where uncertified, a certified lower bound on ``|u*|^2`` (:func:`norm_lower_bound`), or NaN.
    norm_lower: float = float("nan")


@dataclass(frozen=True, eq=False)
class MinimumNorm:
    """The displacements :func:`~tensegrity_rigidity.solver.core.solve` reports."""

    #: "certified" (the minimum-norm minimiser, by its KKT residuals), "uncertified" (a minimiser),
    #: "not computed" (the relaxed energy is not certified) or "not asked".
    status: str
    #: Why the displacements are not certified minimum-norm ("" when they are).
    message: str
    #: The displacements (units of ``max |e0|``).
    u: np.ndarray
    #: Feasibility, stationarity and dual KKT residuals (NaN where no projection ran).
    residuals: tuple[float, float, float] = (np.nan, np.nan, np.nan)
    #: Where the projection ran uncertified, a lower bound on ``|u*|^2``; NaN elsewhere.
    norm_lower: float = np.nan

    @property
    def ok(self) -> bool:
        """Whether ``u`` is the certified minimum-norm minimiser."""
        return self.status == "certified"


def minimum_norm(relaxed: Relaxation, asked: bool = True) -> MinimumNorm:
    """The minimum-norm minimiser of a relaxed state (if ``asked``: ``SolverOptions.min_norm``).

    ``U*`` is built from the relaxed tensions, so nothing is projected unless the energy's lower
    bound certifies them; the equalities' targets are the extensions the relaxed minimiser realises.
    """
    p, u = relaxed.problem, relaxed.u
    if not asked:
        return MinimumNorm(
            "not asked", "minimum-norm displacements not asked for (SolverOptions.min_norm)", u
        )
    if not (p.sites.size and np.any(p.e0)):  # nothing strained or no element: u = 0 is exact
        return MinimumNorm("certified", "", np.zeros(p.n2), (0.0, 0.0, 0.0))
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


def project(p: Problem, t: np.ndarray, u_start: np.ndarray | None = None) -> MinNormResult:
    """The minimum-norm minimiser for the tensions ``t*`` ``t`` (m,) from the minimiser ``u_start``
    (2N,): :func:`active_set` where ``t`` is not zero and a start is given, else (or where that is
    not certified) :func:`min_norm_minimizer`."""
    if np.any(t) and u_start is not None:
        first = active_set(p, t, u_start)
        if first.ok:
            return first
    return min_norm_minimizer(p, t, u_start)


def active_set(
    p: Problem,
    t: np.ndarray,
    u_start: np.ndarray,
    tol: float | None = None,
    max_iterations: int = 5,
    refinement: int = 3,
    corrections: int = 4,
) -> MinNormResult:
    """Projection of the origin onto ``U*`` by a primal-dual active set.

    Each iteration projects from the minimiser ``u_start`` (2N,) for the tensions ``t`` (m,) onto
    the equalities and the held inequalities as equalities (one :class:`_ReducedKKT` step,
    ``refinement`` refinement steps per solve). The held set starts as the inequalities the start
    touches, keeps those with right-signed multipliers and adds those violated; once it stands, up
    to ``corrections`` more steps on the same factorisation while each halves the residuals.
    ``tol``: default ``Tolerances.min_norm_tol``. Suits rigid verdicts. Returns the last iterate.
    """
    tol = p.tol.min_norm_tol if tol is None else tol
    eq, ineq, c, E, In = _polyhedron(p, t)
    u0 = np.asarray(u_start, dtype=float)
    sig = p.sigma[In]

    def step(u, y, z):
        """One step from ``(u, y, z)`` on the equalities and held rows, with its KKT residuals."""
        du, dy, dz = K.solve(-(u + K.REt @ y + K.Gt @ z), bE - K.RE @ u, h - K.G @ u)
        u, y, z = u + du, y + dy, z + dz
        return u, y, z, _certificate(p, u, y, z, E, H, eq, ineq, c)

    v = p.e0 + p.R @ u0
    held = sig * v[In] >= -p.tol.min_norm_held * max(1.0, _inf(u0))  # touched by the start
    bE = (c - p.e0)[E]
    u, it = u0, 0
    residuals: tuple[float, float, float] = (np.inf, np.inf, np.inf)
    for it in range(1, max_iterations + 1):
        H = In[held]
        K = _ReducedKKT(p, E, H, sig[held], p.tol.min_norm_regularization, refinement)
        try:
            K.factor(np.zeros(H.size))  # the held rows as equalities
        except ArithmeticError:
            break
        h = -(p.sigma * p.e0)[H]
        u, y, z, residuals = step(u0, np.zeros(E.size), np.zeros(H.size))
        if _certified(*residuals, tol, p.tol.min_norm_dual):
            return MinNormResult(u, *residuals, it, True)
        v = p.e0 + p.R @ u
        z_all = np.zeros(In.size)
        z_all[held] = z
        violated = sig * v[In] > p.tol.min_norm_violated * max(1.0, _inf(u))
        new = violated | (held & (z_all >= 0))  # violated, or right-signed
        if not np.array_equal(new, held):
            held = new
            continue
        # the held set stands, the residuals do not: correct while that halves them
        for _ in range(corrections):
            previous = max(residuals[:2])
            u, y, z, residuals = step(u, y, z)
            if _certified(*residuals, tol, p.tol.min_norm_dual):
                return MinNormResult(u, *residuals, it, True)
            if max(residuals[:2]) >= 0.5 * previous:
                break
        break
    return MinNormResult(u, *residuals, it, False)


def min_norm_minimizer(
    p: Problem,
    t: np.ndarray,
    u_start: np.ndarray | None = None,
    tol: float | None = None,
    max_iterations: int = 150,
    refinement: int = 3,
    predictor_refinement: int = 0,
    refine_multipliers: bool = True,
) -> MinNormResult:
    """Projection of the origin onto the minimisers ``U*`` by a primal-dual interior point.

    From the minimiser ``u_start`` (2N,) (default the origin) for the tensions ``t*`` ``t`` (m,), at
    most ``max_iterations`` Mehrotra iterations, one factorisation each; ``tol`` as in
    :func:`active_set`, ``refinement`` and ``predictor_refinement`` the refinement steps of the
    corrector's and the predictor's solves. With ``refine_multipliers`` a feasible uncertified end
    point is checked again with multipliers refined in extended precision
    (:func:`_refined_certificate`). Returns the first iterate certified with a margin, else the one
    of least KKT measure.
    """
    tol = p.tol.min_norm_tol if tol is None else tol
    eq, ineq, c, E, In = _polyhedron(p, t)
    K = _ReducedKKT(p, E, In, p.sigma[In], p.tol.min_norm_regularization, refinement)
    RE, G, REt, Gt = K.RE, K.G, K.REt, K.Gt
    bE = (c - p.e0)[E]
    h = -(p.sigma * p.e0)[In]
    mI = In.size
    u = np.zeros(p.n2) if u_start is None else np.array(u_start, float)
    # multipliers on the scale of the start: u = -R^T lam needs |lam| of order |u|
    y, z = np.zeros(E.size), np.full(mI, max(1.0, _inf(u)))
    s = np.maximum(h - G @ u, 1.0)
    best: tuple | None = None
    it = 0
    for it in range(1, max_iterations + 1):
        rd, re, ri = u + REt @ y + Gt @ z, RE @ u - bE, G @ u + s - h
        mu = float(z @ s) / max(mI, 1)
        size = max(1.0, _inf(u))
        kkt = max(_inf(re), _inf(ri), _inf(rd) / size, mI * mu / size**2)
        if best is None or kkt < best[0]:
            best = (kkt, u.copy(), y.copy(), z.copy(), it)
        if kkt <= p.tol.min_norm_kkt_exact or (kkt < p.tol.min_norm_kkt_stall and it - best[4] > 8):
            break
        if kkt <= p.tol.min_norm_certify_below:
            residuals = _certificate(p, u, y, z, E, In, eq, ineq, c)
            if _certified_with_margin(*residuals, tol, p.tol.min_norm_dual):
                return MinNormResult(u, *residuals, it, True, _multipliers(p, y, z, E, In))
        try:
            K.factor(s / z)
        except ArithmeticError:  # numerically singular: keep the best iterate
            break
        # the predictor (affine scaling), then the corrector on the same factorisation
        du, dy, dz, ds = K.newton((rd, re, ri), z * s, z, s, predictor_refinement)
        a = min(step_to_boundary(z, dz), step_to_boundary(s, ds))
        mu_aff = float((z + a * dz) @ (s + a * ds)) / max(mI, 1)
        centring = (mu_aff / mu) ** 3 if mu > 0 else 0.0
        du, dy, dz, ds = K.newton((rd, re, ri), z * s + dz * ds - centring * mu, z, s)
        a = 0.99 * min(step_to_boundary(z, dz), step_to_boundary(s, ds))
        u, y, z, s = u + a * du, y + a * dy, z + a * dz, s + a * ds
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
    """A certified lower bound on ``|u*|^2`` by weak duality from any multipliers ``lam`` (m,).

    Wrong-signed multipliers are set to 0; the dual function ``-1/2 |R^T lam|^2 + lam . (e0 - c)``
    is evaluated on the certificates' geometry less bounds on its round-off (docs/solver.md).
    ``eq``, ``ineq``, ``c``: the polyhedron (:func:`_polyhedron`). Returns twice it, or 0.
    """
    lam_x = np.where(eq | (ineq & (p.sigma * np.asarray(lam, dtype=float) >= 0)), lam, 0)
    lam_x = np.asarray(lam_x, dtype=np.longdouble)
    # |R^T lam| of the exact geometry is at most |forces| + their round-off, per component
    upper = np.abs(p.exact.forces(lam_x)) + _force_roundoff(p, lam_x)
    # the two sums (pairwise, unlike a longdouble dot product) less bounds on their errors
    sums = float(np.ceil(np.log2(max(lam_x.size, 2)))) + 2.0
    square = np.sum(upper * upper) * (1 + 2 * sums * EPS)
    target = np.asarray(p.e0, dtype=np.longdouble) - np.asarray(c, dtype=np.longdouble)
    terms = lam_x * target
    linear = terms.sum() - sums * EPS * np.abs(terms).sum()
    bound = float(2 * linear - square)
    # the last subtraction and the rounding to double, each within 2^-52 relative
    return max(0.0, bound - abs(bound) * 2.0**-51)


def _polyhedron(p: Problem, t: np.ndarray):
    """``U*`` of the tensions ``t`` (m,): masks (m,) of its equalities (rods and stressed one-sided
    elements) and inequalities, targets ``c`` (m,) (``v = c`` on the equalities, ``sigma v <= 0`` on
    the inequalities) and the indices of both."""
    stressed = p.one_sided & (t != 0)
    eq, ineq = p.rod | stressed, p.one_sided & ~stressed
    c = np.where(eq, t / p.k, 0.0)
    return eq, ineq, c, np.flatnonzero(eq), np.flatnonzero(ineq)


def _certified(feasibility, stationarity, dual, tol: float, dual_tol: float) -> bool:
    """The KKT residuals (floats) within their tolerances (``tol``; ``dual_tol`` for ``dual``)."""
    return feasibility <= tol and stationarity <= tol and dual <= dual_tol


def _certified_with_margin(feasibility, stationarity, dual, tol: float, dual_tol: float) -> bool:
    """Certified (:func:`_certified`) with feasibility ``100`` and the others ``10`` times below
    ``tol``: where :func:`min_norm_minimizer` stops."""
    return _certified(feasibility, stationarity, dual, tol, dual_tol) and (
        feasibility <= 1e-2 * tol and max(stationarity, dual) <= 0.1 * tol
    )


def _multipliers(p, y, z, E, In) -> np.ndarray:
    """The multipliers ``lam`` (m,) of the equalities ``y`` and inequalities ``z``: ``u = -R^T lam``
    at the projection, ``sigma lam >= 0`` on the inequalities."""
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
    precision by ``steps`` least-squares corrections ``R^T dlam = -(u + R^T lam)`` (stationarity
    with the forces' round-off bound), and those ((m,) longdouble); None if the factor fails."""
    f = p.factor_shifted(np.ones(p.sites.size), p.tol.min_norm_multiplier_shifts)
    if f is None:
        return None
    U, lam_x = np.asarray(u, dtype=np.longdouble), np.asarray(lam, dtype=np.longdouble)
    for _ in range(steps):
        r = U + p.exact.forces(lam_x)
        lam_x = lam_x - p.R @ f.solve(np.asarray(r, dtype=float))
    lam_f = np.asarray(lam_x, dtype=float)
    roundoff = float(_force_roundoff(p, lam_f).max(initial=0.0))
    stat = (_inf(U + p.exact.forces(lam_x)) + roundoff) / max(_inf(u), 1e-300)
    return _residuals(p, u, p.e0 + p.R @ u, lam_f, eq, ineq, c, stationarity=stat), lam_x


def _force_roundoff(p: Problem, lam: np.ndarray) -> np.ndarray:
    """Per-component bound (2N,) on the round-off of ``p.exact.forces(lam)`` (``lam`` (m,))."""
    return p.exact.roundoff * (abs(p.RT) @ np.abs(lam))


class _ReducedKKT:
    """The interior-point system of the projection, reduced to ``2N x 2N`` (docs/solver.md).

    The steps of :func:`min_norm_minimizer` (and, with ``D = 0``, of :func:`active_set`) solve
    ``[[I, R_E^T, G^T], [R_E, 0, 0], [G, 0, -D]] (du, dy, dz) = (r1, r2, r3)``, ``G = diag(sigma)
    R_I``, ``D = S / Z``, regularised by ``d`` and refined against the unregularised system.
    """

    def __init__(self, p: Problem, E, In, sigma_in, d: float, refinement: int):
        R = p.R.tocsr()
        self.p, self.In, self.mE = p, In, E.size
        self.d, self.refinement = d, refinement
        self.RE = R[E]
        self.G = (sp.diags(sigma_in) @ R[In]).tocsr()
        # the transposes once (``.T`` builds a new matrix object on every call)
        self.REt, self.Gt = self.RE.T.tocsr(), self.G.T.tocsr()
        # both constraint blocks stacked, so that each product is one sparse product
        self.B = sp.vstack([self.RE, self.G], format="csr")
        self.Bt = self.B.T.tocsr()
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
        """(du, dy, dz, ds) of the interior-point step for the residuals ``(rd, re, ri)``, ``rc``
        of the complementarity, multipliers ``z``, slacks ``s`` (``refinement``: as in solve)."""
        rd, re, ri = residuals
        du, dy, dz = self.solve(-rd, -re, -ri + rc / z, refinement)
        return du, dy, dz, -(rc + s * dz) / z

    def _regularised(self, r1, r2):
        """(du, dw) of the regularised system for ``(r1, r2)`` (``r2``, ``dw``: y and z stacked)."""
        assert self._factor is not None
        du = self._factor.solve(self.d * (r1 + self.Bt @ (self._inverse * r2)))
        return du, (self.B @ du - r2) * self._inverse

    def solve(self, r1, r2, r3, refinement: int | None = None):
        """(du, dy, dz) of the unregularised system for (r1, r2, r3), refined ``refinement`` times
        (default: the system's own count)."""
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
    lam_max = max(_inf(lam), 1e-300)
    # complementarity as the relative duality gap: sum |lam_b v_b| over the inequalities is
    # the gap between 1/2 |u|^2 and the dual value, so 1/2 |u|^2 is within it of its minimum
    comp = float(np.sum((np.abs(lam) * np.abs(v))[ineq])) / max(float(u @ u), 1e-300)
    if stationarity is None:
        stationarity = _inf(u + p.RT @ lam) / max(_inf(u), 1e-300)
    dual = float(np.maximum(-p.sigma * lam, 0.0)[ineq].max(initial=0.0)) / lam_max
    return float(max(feas_eq, feas_in)), max(comp, stationarity), dual


def _inf(x: np.ndarray) -> float:
    """``max |x|`` (0 for an empty ``x``) as a float."""
    return float(np.abs(x).max(initial=0.0))
