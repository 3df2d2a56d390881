"""Independent, general-purpose formulations: the robust fallback and the test oracle.

* :func:`lp_verdict` decides rigidity by the linear program of MODEL.md (Farkas): maximise the
  work ``t . e0`` over admissible self-stresses ``R^T t = 0``, ``t_cable >= 0``, ``t_strut <= 0``,
  ``|t| <= 1``, solved by HiGHS. A positive optimum means rigid, with ``t`` as certificate; a zero
  optimum means floppy, and the LP's dual (the multipliers of ``R^T t = 0``) is a displacement
  ``u`` with ``e0 + R u`` admissible (the dual is the l1 distance of ``e0 + R u`` to the
  admissible set).
* :func:`qp_solve` computes the exact energy as the projection of ``e0`` onto the cone of
  admissible self-stresses, ``min 1/2 t K^-1 t - e0 . t`` over that cone, by the interior-point
  solver Clarabel. Its optimum is ``-E*``, its minimiser the unique tensions ``t*``, and the
  multipliers of ``R^T t = 0`` give a minimising displacement.

Both work on the non-empty sites only and return full-length arrays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .mechanics import affine_extensions, rigidity_matrix
from .network import Element, Instance


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
    displacements : (N, 2) float
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


def lp_verdict(instance: Instance, tol: float = 1e-9) -> ReferenceResult:
    """Rigidity verdict from the Farkas linear program, solved by HiGHS.

    ``rigid`` is True when the maximal work of an admissible self-stress with ``|t_b| <= 1``
    exceeds ``tol * sum |e0|``.
    """
    from scipy.optimize import linprog

    net, sites, kinds, R, e0, _ = _nonempty(instance)
    m, n2 = R.shape
    t_full = np.zeros(net.n_sites)
    if m == 0 or not np.any(e0):
        return ReferenceResult(0.0, False, t_full, np.zeros((net.n_nodes, 2)), "trivial")
    lo = np.where(kinds == Element.CABLE, 0.0, -1.0)
    hi = np.where(kinds == Element.STRUT, 0.0, 1.0)
    res = linprog(
        -e0,
        A_eq=sp.csr_matrix(R.T),
        b_eq=np.zeros(n2),
        bounds=np.c_[lo, hi],
        method="highs",
        options={"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10},
    )
    if res.status != 0:
        raise RuntimeError(f"HiGHS failed on the verdict LP: {res.message}")
    value = float(-res.fun)
    t_full[sites] = res.x
    # scipy's marginals y satisfy  c = A_eq^T y + bound duals;  with c = -e0 this reads
    # e0 + R y = -(bound duals), so u = y makes e0 + R u admissible when the optimum is 0.
    u = np.asarray(res.eqlin.marginals, dtype=float).reshape(-1, 2)
    scale = float(np.abs(e0).sum())
    return ReferenceResult(value, value > tol * scale, t_full, u, res.message)


def qp_solve(instance: Instance, tol: float = 1e-10) -> ReferenceResult:
    """Exact energy and tensions from the dual QP, solved by Clarabel (interior point)."""
    import clarabel

    net, sites, kinds, R, e0, k = _nonempty(instance)
    m, n2 = R.shape
    t_full = np.zeros(net.n_sites)
    if m == 0 or not np.any(e0):
        return ReferenceResult(0.0, False, t_full, np.zeros((net.n_nodes, 2)), "trivial")
    cable = np.flatnonzero(kinds == Element.CABLE)
    strut = np.flatnonzero(kinds == Element.STRUT)
    # rows: R^T t = 0 (zero cone), -t_cable <= 0 and t_strut <= 0 (nonnegative slacks)
    sign_rows = sp.csr_matrix(
        (
            np.r_[-np.ones(len(cable)), np.ones(len(strut))],
            (np.arange(len(cable) + len(strut)), np.r_[cable, strut]),
        ),
        shape=(len(cable) + len(strut), m),
    )
    A = sp.vstack([R.T, sign_rows]).tocsc()
    b = np.zeros(A.shape[0])
    P = sp.diags(1.0 / k).tocsc()
    # Solve for the unit-norm strain and rescale: E* scales as |e0|^2 and t* as |e0|, so the
    # interior-point tolerances act on a problem of unit size whatever the strain magnitude.
    scale = float(np.linalg.norm(e0))
    e0 = e0 / scale
    cones = [clarabel.ZeroConeT(n2)]
    if sign_rows.shape[0]:
        cones.append(clarabel.NonnegativeConeT(sign_rows.shape[0]))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = tol
    settings.tol_gap_rel = tol
    settings.tol_feas = tol
    settings.max_iter = 500
    solver = clarabel.DefaultSolver(P, -e0, A, b, cones, settings)
    sol = solver.solve()
    status = str(sol.status)
    t = np.asarray(sol.x) * scale
    t_full[sites] = t
    energy = float(0.5 * np.dot(t, t / k))
    # KKT of the rod rows: t / k - e0 + R z = 0, so e = e0 + R u with u = -z_eq.
    u = -np.asarray(sol.z)[:n2].reshape(-1, 2) * scale
    e_ref = 0.5 * float(np.dot(k, (scale * e0) ** 2))
    return ReferenceResult(energy, energy > 1e-14 * e_ref, t_full, u, status)
