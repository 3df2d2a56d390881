"""Independent, general-purpose formulations: the oracle of the tests and the benchmarks.

* :func:`lp_verdict` decides rigidity by the linear program of docs/model.md (Farkas): maximise the
  work ``t . e0`` over admissible self-stresses ``R^T t = 0``, ``t_cable >= 0``, ``t_strut <= 0``,
  solved by HiGHS, and compares the largest work per unit ``|t|_1`` (the quantity the
  resolution model's rigid certificate bounds) with ``tau max |e0|``: the verdict that both
  certificates imply (up to the rigid certificate's residual margin). A zero optimum means
  floppy, and the LP's dual (the multipliers of ``R^T t = 0``) is a displacement ``u`` with
  ``e0 + R u`` admissible.
* :func:`qp_solve` computes the exact energy from a generic QP over displacements and elastic
  extensions, solved by the interior-point solver Clarabel.
* :func:`min_norm_minimizer` projects the origin onto the polyhedron of minimisers (Clarabel).

Both work on the non-empty sites only and return full-length arrays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from tensegrity_rigidity.model.mechanics import (
    affine_extensions,
    rigidity_matrix,
    tensions_from_extensions,
)
from tensegrity_rigidity.model.network import Element, Instance


@dataclass(frozen=True)
class ReferenceResult:
    """Result of a reference solve.

    Attributes
    ----------
    value : float
        LP: optimal normalised work (>= 0). QP: energy E*.
    rigid : bool
        Verdict of the formulation (LP: value above tolerance; QP: E* above tolerance).
    tensions : (m,) float
        LP: the maximising admissible self-stress. QP: the optimal tensions t*.
    displacements : (N, d) float
        Displacements from the dual multipliers of force balance.
    status : str
        The solver's status string.
    """

    value: float
    rigid: bool
    tensions: np.ndarray
    displacements: np.ndarray
    status: str


def _nonempty(instance: Instance):
    net = instance.network
    sites = np.flatnonzero(net.kinds != Element.EMPTY)
    kinds = net.kinds[sites]
    R = rigidity_matrix(net, sites)
    e0 = affine_extensions(net, instance.strain)[sites]
    k = net.stiffness_or_ones()[sites]
    return net, sites, kinds, R, e0, k


def lp_verdict(
    instance: Instance, tol: float = 1e-9, time_limit: float | None = None
) -> ReferenceResult:
    """Rigidity verdict from the Farkas linear program, solved by HiGHS.

    The verdict is whether the largest work ``t . e0 / |t|_1`` of an admissible self-stress
    exceeds ``tol * max |e0|``, the units of the resolution model's rigid certificate
    (:mod:`.certificates`). With ``tol`` its ``tau`` (``SolverOptions.violation_tol``), a
    certified floppy verdict implies not rigid: for every exact self-stress ``t . e0 =
    t . (e0 + R u) <= tau |t|_1 max |e0|``. A certified rigid verdict (work above ``tau + U r``
    per unit ``|t|_1`` for a self-stress balanced to ``r``) implies ``rigid`` unless
    balancing its self-stress exactly costs more than ``U r`` of work (docs/model.md).

    It is computed in two steps. First the box LP, ``max t . e0`` over admissible
    self-stresses with ``|t_b| <= 1`` (fast for HiGHS's simplex). Two upper bounds on the
    largest work per unit ``|t|_1``: the box optimum (``t / |t|_inf`` lies in the box and
    ``|t|_inf <= |t|_1``), and the largest violation of ``e0 + R u`` for the box LP's dual
    ``u`` (for every admissible exact self-stress ``t . e0 = t . (e0 + R u) <= |t|_1 max_b
    viol_b``; plus a bound on its round-off). One lower bound: the vertex's own work per unit
    ``|t|_1``. Where they lie on one side of ``tol * max |e0|`` that decides. Between them,
    the same LP with ``|t|_1 <= 1`` (each rod's tension split as ``p - q``, ``p, q >= 0``)
    computes the largest itself; the simplex is much slower on it (more than 12 minutes on
    an n = 64 configuration whose box LP takes 11 s). At n = 64 the box optimum alone left
    a certified floppy configuration between the bounds (optimum 1.2e-8, vertex 1.8e-11,
    against 1.5e-9). The box LP's optimum against ``tol * sum |e0|``, the rule until
    2026-11-28, called a certified rigid n = 64 configuration floppy: its vertex does work
    6.8e-9 per unit ``|t|_1``, against ``tau = 1e-9``.

    Parameters
    ----------
    instance : Instance
        Network, elements and strain.
    tol : float
        ``rigid`` is True when the largest work per unit ``|t|_1`` exceeds
        ``tol * max |e0|``.
    time_limit : float, optional
        Seconds HiGHS may spend on each LP (no limit by default).

    Returns
    -------
    ReferenceResult
        ``value`` the work per unit ``|t|_1`` that decided (physical units): where floppy
        by the box LP, the upper bound below the tolerance (its optimum or its dual's
        largest violation), else the work of ``tensions`` (m,), the deciding maximiser;
        ``displacements`` (N, d) the LP's dual (admissible extensions when the optimum is
        0); ``status`` names the step that decided. ``value`` NaN and status "time limit"
        when an LP reached the limit.

    Raises
    ------
    RuntimeError
        When HiGHS fails for another reason (after its dual simplex, its interior point).
    """
    net, sites, kinds, R, e0, _ = _nonempty(instance)
    t_full = np.zeros(net.n_sites)
    no_u = np.zeros((net.n_nodes, net.dim))
    if R.shape[0] == 0 or not np.any(e0):
        return ReferenceResult(0.0, False, t_full, no_u, "trivial")
    limit = tol * float(np.abs(e0).max())
    box = _farkas_lp(R, e0, kinds, False, time_limit)
    if box is None:
        return ReferenceResult(np.nan, False, t_full, no_u, "time limit")
    optimum, t, u = box
    u = u.reshape(-1, net.dim)
    t_full[sites] = t
    if optimum <= limit:
        return ReferenceResult(optimum, False, t_full, u, "box LP: optimum below")
    violation = _largest_violation(R, e0, kinds, u.ravel())
    if violation <= limit:
        return ReferenceResult(violation, False, t_full, u, "box LP: dual below")
    work = float(t @ e0) / max(float(np.abs(t).sum()), 1e-300)
    if work > limit:
        return ReferenceResult(work, True, t_full, u, "box LP: vertex above")
    l1 = _farkas_lp(R, e0, kinds, True, time_limit)  # between the bounds
    if l1 is None:
        return ReferenceResult(np.nan, False, t_full, no_u, "time limit")
    optimum, t, u = l1
    t_full[sites] = t
    return ReferenceResult(optimum, optimum > limit, t_full, u.reshape(-1, net.dim), "l1 LP")


def _largest_violation(R, e0, kinds, u) -> float:
    """Largest violation of ``e0 + R u`` ((m,) from (2N,) ``u``) over the elements (rods
    ``|v|``, cables ``v``, struts ``-v``, where positive), plus a bound on the round-off of
    evaluating it in double precision."""
    v = e0 + R @ u
    sigma = np.where(kinds == Element.CABLE, 1.0, -1.0)
    viol = np.where(kinds == Element.ROD, np.abs(v), np.maximum(sigma * v, 0.0))
    terms = np.abs(e0) + abs(R) @ np.abs(u)  # every product and sum of v_b is below this
    nnz_row = int(np.diff(sp.csr_matrix(R).indptr).max(initial=0))
    return float(viol.max()) + (nnz_row + 2) * np.finfo(float).eps * float(terms.max())


def _farkas_lp(R, e0, kinds, l1: bool, time_limit: float | None):
    """``max t . e0`` over admissible self-stresses with ``|t_b| <= 1`` (``l1`` False) or
    ``|t|_1 <= 1``: (optimum, t (m,), u (N, d) from the multipliers of ``R^T t = 0``), or
    None where HiGHS reached ``time_limit``."""
    from scipy.optimize import linprog

    m, n2 = R.shape
    lo = np.where(kinds == Element.CABLE, 0.0, -1.0)
    hi = np.where(kinds == Element.STRUT, 0.0, 1.0)
    RT = sp.csr_matrix(R.T)
    extra: dict = {}
    rod = np.flatnonzero(kinds == Element.ROD)
    if l1:  # rods' own columns fixed at 0; their tensions are p - q, two more columns
        lo[rod] = hi[rod] = 0.0
        RT = sp.hstack([RT, RT[:, rod], -RT[:, rod]], format="csr")
        sigma = np.where(kinds == Element.CABLE, 1.0, -1.0)  # |t| = sigma t, one-sided
        norm = np.r_[np.where(kinds == Element.ROD, 0.0, sigma), np.ones(2 * rod.size)]
        extra = {"A_ub": norm[None, :], "b_ub": [1.0]}
        e0 = np.r_[e0, e0[rod], -e0[rod]]
        lo, hi = np.r_[lo, np.zeros(2 * rod.size)], np.r_[hi, np.ones(2 * rod.size)]
    options = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
    if time_limit is not None:
        options["time_limit"] = float(time_limit)
    # HiGHS's default (dual simplex) occasionally ends with status "Not Set" on near-degenerate
    # instances at a threshold; its interior point with crossover is then asked instead
    for method in ("highs", "highs-ipm"):
        res = linprog(
            -e0,
            A_eq=RT,
            b_eq=np.zeros(n2),
            bounds=np.c_[lo, hi],
            method=method,
            options=options,
            **extra,
        )
        if res.status in (0, 1):
            break
    if res.status == 1 and time_limit is not None:  # iteration or time limit reached
        return None
    if res.status != 0:
        raise RuntimeError(f"HiGHS failed on the verdict LP: {res.message}")
    x = np.asarray(res.x, dtype=float)
    t = x[:m].copy()
    if l1:
        t[rod] = x[m : m + rod.size] - x[m + rod.size :]
    # scipy's marginals satisfy  c = A_eq^T y (+ A_ub^T s) + bound duals, with s = 0 where the
    # optimum is 0 (its dual value is s); on each column c = -e0 then reads e0 + R y =
    # -(bound duals), so u = y makes e0 + R u admissible when the optimum is 0.
    u = np.asarray(res.eqlin.marginals, dtype=float)
    return float(-res.fun), t, u


def qp_solve(instance: Instance, tol: float = 1e-10) -> ReferenceResult:
    """Exact energy, tensions and a minimiser from a generic QP, solved by Clarabel.

    The primal formulation over displacements ``u`` (2N) and elastic extensions ``y`` (m)::

        min 1/2 sum_b k_b y_b^2   subject to
        rods:    y = e0 + R u
        cables:  y >= e0 + R u,  y >= 0
        struts:  y <= e0 + R u,  y <= 0

    (a cable's energy ``1/2 k max(e, 0)^2`` is ``min 1/2 k y^2`` over ``y >= max(e, 0)``). Its
    equality rows contain an identity block, so they have full rank whatever the network; the
    dual form ``min 1/2 t K^-1 t - e0 . t`` over ``R^T t = 0`` does not, and interior-point
    solvers stall on it. The problem is solved for the unit-norm strain and rescaled.

    Parameters
    ----------
    instance : Instance
        Network, elements, stiffness and strain.
    tol : float
        Clarabel's gap and feasibility tolerances.

    Returns
    -------
    ReferenceResult
        ``value`` the energy E*, ``rigid`` whether ``E* > 1e-14 E(u = 0)``, ``tensions``
        (m,) t*, ``displacements`` (N, d) a minimiser.
    """
    import clarabel

    net, sites, kinds, R, e0, k = _nonempty(instance)
    m, n2 = R.shape
    t_full = np.zeros(net.n_sites)
    if m == 0 or not np.any(e0):
        return ReferenceResult(0.0, False, t_full, np.zeros((net.n_nodes, net.dim)), "trivial")
    scale = float(np.linalg.norm(e0))
    e0 = e0 / scale
    rod = np.flatnonzero(kinds == Element.ROD)
    cab = np.flatnonzero(kinds == Element.CABLE)
    stru = np.flatnonzero(kinds == Element.STRUT)
    eye = sp.identity(m, format="csr")

    def rows(sel, sr, sy):
        # rows  sr * R u + sy * y  for the selected sites
        return sp.hstack([sr * R[sel], sy * eye[sel]]) if sel.size else None

    blocks_eq = [rows(rod, -1.0, 1.0)]
    b_eq = [e0[rod]]
    blocks_in = [
        rows(cab, 1.0, -1.0),
        rows(cab, 0.0, -1.0),
        rows(stru, -1.0, 1.0),
        rows(stru, 0.0, 1.0),
    ]
    b_in = [-e0[cab], np.zeros(cab.size), e0[stru], np.zeros(stru.size)]
    A_parts, b_parts, cones = [], [], []
    if rod.size:
        A_parts.append(blocks_eq[0])
        b_parts.append(b_eq[0])
        cones.append(clarabel.ZeroConeT(rod.size))
    ins = [(blk, bb) for blk, bb in zip(blocks_in, b_in, strict=False) if blk is not None]
    if ins:
        A_parts += [blk for blk, _ in ins]
        b_parts += [bb for _, bb in ins]
        cones.append(clarabel.NonnegativeConeT(sum(bb.size for _, bb in ins)))
    A = sp.vstack(A_parts).tocsc()
    b = np.concatenate(b_parts)
    P = sp.block_diag([sp.csc_matrix((n2, n2)), sp.diags(k)], format="csc")
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = tol
    settings.tol_gap_rel = tol
    settings.tol_feas = tol
    settings.max_iter = 500
    sol = clarabel.DefaultSolver(P, np.zeros(n2 + m), A, b, cones, settings).solve()
    x = np.asarray(sol.x)
    u = x[:n2] * scale
    # Report the exact energy and tensions at the QP's displacements rather than its objective
    # value: an interior-point objective carries the solver's tolerance, E(u) is exact for u.
    e = scale * e0 + R @ u
    t = tensions_from_extensions(kinds, k, e)
    t_full[sites] = t
    energy = 0.5 * float(np.dot(t, e))
    e_ref = 0.5 * float(np.dot(k, (scale * e0) ** 2))
    u = u.reshape(-1, net.dim)
    return ReferenceResult(energy, energy > 1e-14 * e_ref, t_full, u, str(sol.status))


def min_norm_minimizer(instance: Instance, tensions: np.ndarray) -> tuple[np.ndarray, str]:
    """Minimum-norm displacement among all minimisers of the energy, by Clarabel.

    Parameters
    ----------
    instance : Instance
        Network, elements, stiffness and strain.
    tensions : (m,) float
        The unique optimal tensions ``t*`` (from :func:`qp_solve` or
        :func:`~tensegrity_rigidity.solve`).

    Returns
    -------
    u : (N, 2) float
        ``argmin |u|`` over the minimisers.
    status : str
        Clarabel's status ("Solved" on success; "trivial" without elements).

    Notes
    -----
    Given ``t*``, the minimisers form the polyhedron ``U* = {u : e_b = t*_b / k_b on rods and
    stressed one-sided elements, and the sign constraint on unstressed one-sided elements}``.
    Its minimum-norm point is the limit of the minimiser of ``E(u) + mu/2 |u|^2`` as
    ``mu -> 0`` (a vanishing background stiffness).
    """
    import clarabel

    net, sites, kinds, R, e0, k = _nonempty(instance)
    n2 = R.shape[1]
    if R.shape[0] == 0:
        return np.zeros((net.n_nodes, net.dim)), "trivial"
    t = np.asarray(tensions, dtype=float)[sites]
    eq = (kinds == Element.ROD) | (t != 0)
    ineq = ~eq
    sigma = np.where(kinds == Element.CABLE, 1.0, -1.0)
    scale = max(float(np.linalg.norm(e0)), 1e-300)
    # equalities R u = t/k - e0 ; inequalities sigma (e0 + R u) <= 0
    A = sp.vstack([R[eq], sp.diags(sigma[ineq]) @ R[ineq]]).tocsc()
    b = np.r_[(t[eq] / k[eq] - e0[eq]), -sigma[ineq] * e0[ineq]] / scale
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = 1e-11
    settings.max_iter = 500
    cones = [clarabel.ZeroConeT(int(eq.sum()))]
    if ineq.any():
        cones.append(clarabel.NonnegativeConeT(int(ineq.sum())))
    sol = clarabel.DefaultSolver(
        sp.eye(n2, format="csc"), np.zeros(n2), A, b, cones, settings
    ).solve()
    return np.asarray(sol.x).reshape(-1, net.dim) * scale, str(sol.status)
