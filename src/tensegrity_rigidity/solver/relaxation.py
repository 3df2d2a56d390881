"""The relaxed state after a verdict: the minimum energy, its tensions and a certified bound.

On a floppy verdict ``E* = 0`` and ``t* = 0``. Otherwise the energy with the instance's stiffnesses
is minimised from the search's lowest-energy point, and a weak-duality lower bound from a
self-stress states its accuracy; where that leaves it uncertified, a long run on a Newton matrix
shifted far less goes on from it, the better of the two kept (docs/model.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.network import Instance
from .certificates import RigidCertificate
from .ipm import IpmState, interior_point
from .newton import crossover, newton
from .options import SolverOptions
from .problem import Problem
from .selfstress import kept, optimal_on_support, purify
from .stages import Search
from .tolerances import Tolerances


@dataclass(frozen=True, eq=False)
class Relaxation:
    """The relaxed state of an instance in the normalised units of its problem.

    Attributes
    ----------
    status : str
        "floppy" (``E* = 0`` exactly), "certified" (within ``Tolerances.energy_gap`` of its lower
        bound) or "uncertified".
    message : str
        Why the energy is not certified ("" otherwise).
    problem : Problem
        The problem with the instance's stiffnesses (the verdict's where they are uniform).
    k_unit : float
        The stiffness unit of the energies and tensions (physical units).
    u : (2N,) float
        Lowest-energy displacements found (units of ``max |e0|``).
    energy, energy_lower : float
        Their energy and a certified lower bound on E* (units of ``k_unit max |e0|^2``).
    tensions_relaxed : (m,) float
        The tensions ``k (e0 + R u)`` at ``u`` (zero on slack one-sided elements).
    tensions : (m,) float or longdouble
        The same moved onto an exact self-stress where that certifies them.
    iterations, extra_factorizations : int
        Newton iterations (the verdict's included); factorisations of the long run's own problem.
    """

    status: str
    message: str
    problem: Problem
    k_unit: float
    u: np.ndarray
    energy: float
    energy_lower: float
    tensions_relaxed: np.ndarray
    tensions: np.ndarray
    iterations: int
    extra_factorizations: int = 0

    @property
    def certified(self) -> bool:
        """Whether the relaxed tensions are certified to be ``t*``."""
        return self.status != "uncertified"


def relax(
    instance: Instance, p: Problem, s: Search, status: str, opts: SolverOptions
) -> Relaxation:
    """The relaxed state after the verdict search.

    Parameters
    ----------
    instance : Instance
        The instance.
    p : Problem
        The verdict's problem (unit stiffness).
    s : Search
        The verdict search's final state (its lowest-energy point, its rigid certificate).
    status : str
        The verdict: "rigid", "floppy" or "undecided".
    opts : SolverOptions
        The options.

    Returns
    -------
    Relaxation
        The relaxed state and whether its energy is certified.
    """
    tol = opts.tolerances
    k_sites = instance.network.stiffness_or_ones()[p.sites]
    uniform = k_sites.size == 0 or bool(np.all(k_sites == k_sites[0]))
    # with one stiffness the verdict's unit-stiffness problem is the energy's too
    pe = p if uniform else Problem(instance, opts.regularization, opts.factorization, False, tol)
    k_unit = float(k_sites[0]) if uniform and k_sites.size else pe.k_scale
    if status == "floppy":
        zeros = np.zeros(p.sites.size)
        u = np.asarray(s.floppy.u, dtype=float)  # type: ignore[union-attr]
        return Relaxation("floppy", "", pe, k_unit, u, 0.0, 0.0, zeros, zeros, s.iterations)
    u, E, more, t_relaxed, t_n, E_lower = _relaxed(pe, s.u, opts, s.rigid, ipm_start=s.ipm_end)
    extra = 0
    if not energy_certified(E, E_lower, tol.energy_gap):
        # the long run (Tolerances.relax_long_ipm) on a matrix shifted by relax_long_shift only
        pl = Problem(instance, tol.relax_long_shift, opts.factorization, uniform, tol)
        try:
            long: tuple | None = _relaxed(pl, u, opts, s.rigid, tol.relax_long_ipm)
        except ArithmeticError:  # a factorisation failed
            long = None
        extra = pl.factorizations
        if long is not None:
            u_2, E_2, more_2, t_relaxed_2, t_n_2, E_lower_2 = long
            more += more_2
            E_lower = max(E_lower, E_lower_2)  # both bound E* from below
            if E_2 < E:
                u, E, t_relaxed, t_n = u_2, E_2, t_relaxed_2, t_n_2
            E_lower = min(E_lower, E)  # and E bounds it from above
    status, message = "certified", ""
    if not energy_certified(E, E_lower, tol.energy_gap):
        status = "uncertified"
        message = (
            f"the relaxed energy is not certified (its lower bound is {E_lower / E:.1e} of it)"
        )
    it = s.iterations + more
    return Relaxation(status, message, pe, k_unit, u, E, E_lower, t_relaxed, t_n, it, extra)


def energy_certified(energy, energy_lower, gap: float = Tolerances.energy_gap):
    """Whether the relaxed energy is within ``gap`` of its certified lower bound.

    Parameters
    ----------
    energy, energy_lower : float or (k,) float array
        Relaxed energies and their lower bounds (``SolveResult`` fields, sweep-row columns).
    gap : float
        The largest relative gap (``Tolerances.energy_gap``).

    Returns
    -------
    bool or (k,) bool array
        True where the relaxed tensions are certified to be t* (False where either is NaN): by
        the strong convexity of the energy in the tensions ``sum (t_b - t*_b)^2 / k_b <= 2 (E -
        E_lower)``.
    """
    return energy_lower >= (1.0 - gap) * energy


def _relax(
    p: Problem,
    u: np.ndarray,
    opts: SolverOptions,
    ipm: tuple[int, float] | None = None,
    ipm_start: IpmState | None = None,
) -> tuple[np.ndarray, float, int]:
    """Minimise the energy from ``u`` (2N,): Newton, then (if not stationary) the interior point
    with ``ipm`` = (iterations, tolerance), going on from ``ipm_start`` where it passes through it,
    and a crossover; a final crossover if it cuts the force residual. Returns (u, E, iterations)."""

    def residual(x):
        _, _, t = p.state(x)
        return float(np.linalg.norm(p.RT @ t)) / max(float(np.linalg.norm(t)), 1e-300)

    tol = p.tol
    ipm = tol.relax_short_ipm if ipm is None else ipm
    u, E, it = newton(p, u, opts.max_iter)
    if E > 0 and residual(u) > tol.stationary:
        x, _, _, _ = interior_point(p, max_iter=ipm[0], tol=ipm[1], start=ipm_start)
        for tau in tol.crossover_taus:  # the first that does not raise the energy
            y = crossover(p, x, tau=tau)
            if y is not None and p.energy(y) <= p.energy(x):
                x = y
                break
        x, E_x, more = newton(p, x, opts.max_iter)
        it += more
        if E_x < E:
            u, E = x, E_x
    if E > 0:
        y = crossover(p, u, tau=tol.final_crossover_tau)
        if y is not None:
            E_y = p.energy(y)
            if E_y <= E * (1 + tol.final_crossover_raise) and residual(y) < residual(u):
                u, E = y, E_y
    return u, E, it


def _relaxed(
    p: Problem,
    u: np.ndarray,
    opts: SolverOptions,
    certificate: RigidCertificate | None,
    ipm: tuple[int, float] | None = None,
    ipm_start: IpmState | None = None,
) -> tuple[np.ndarray, float, int, np.ndarray, np.ndarray, float]:
    """The relaxation from ``u`` (2N,) (:func:`_relax`) and what certifies it: (u, E, iterations,
    tensions ``k (e0 + R u)`` (m,), the same moved onto an exact self-stress where close to one, a
    certified lower bound on E* at most E)."""
    gap = opts.tolerances.energy_gap
    u, E, more = _relax(p, u, opts, ipm, ipm_start)
    _, _, t_relaxed = p.state(u)
    t_n, tensions_bound = _balanced_tensions(p, t_relaxed)
    E_lower = min(_energy_lower(p, tensions_bound, certificate), E)
    if E > 0 and not energy_certified(E, E_lower, gap):
        x = optimal_on_support(p, t_relaxed)  # the best self-stress of the tensions' support
        if x is not None:
            t_opt = np.asarray(x, dtype=float)
            bound = _self_stress_bound(p, t_opt, _exact_residual(p, x))
            if bound > E_lower:
                E_lower = min(bound, E)
                if energy_certified(E, E_lower, gap):
                    t_n = t_opt
    return u, E, more, t_relaxed, t_n, E_lower


def _balanced_tensions(p: Problem, t: np.ndarray) -> tuple[np.ndarray, float]:
    """The minimiser's tensions ``t`` (m,) moved onto an exact self-stress where purification
    balances them to ``Tolerances.balanced_residual`` (else ``t``; kept as they are, less round-off
    entries, where they balance that well already), and the lower bound on E* it gives."""
    if not np.any(t):
        return t, 0.0
    # purification's own support: the round-off tensions of elements only touched dropped
    t_kept = np.where(kept(t, p.tol.support_tol), t, 0.0)
    exact = _exact_residual(p, t_kept)
    if exact <= p.tol.balanced_residual:  # already balanced: purify could only refine round-off
        return t_kept, _self_stress_bound(p, t_kept, exact)
    try:
        tp = purify(p, t)
    except ArithmeticError:
        return t, 0.0
    bound = _self_stress_bound(p, tp, _exact_residual(p, tp))
    if float(np.abs(p.RT @ tp).sum()) <= p.tol.balanced_residual * float(np.abs(tp).sum()):
        return tp, bound
    return t, bound


def _exact_residual(p: Problem, t: np.ndarray) -> float:
    """``|R^T t|_1 / |t|_1`` of tensions ``t`` (m,), the forces in extended precision (0 for ``t =
    0``; no floor on ``|t|_1``, so underflowed tensions keep their large residual)."""
    size = float(np.abs(t).sum())
    return float(np.abs(p.exact.forces(t)).sum()) / size if size > 0 else 0.0


def _self_stress_bound(p: Problem, t: np.ndarray, residual: float) -> float:
    """Weak-duality bound ``(t . e0)^2 / (2 t . K^-1 t)`` on E* from an admissible self-stress ``t``
    (m,) of relative force residual ``residual`` (0 above ``Tolerances.bound_residual``)."""
    work = float(np.dot(t, p.e0))
    if residual > p.tol.bound_residual or work <= 0 or not np.all(np.isfinite(t)):
        return 0.0
    return work**2 / (2.0 * float(np.dot(t, t / p.k)))


def _energy_lower(
    p: Problem, tensions_bound: float, certificate: RigidCertificate | None = None
) -> float:
    """Lower bound on E*: the larger of ``tensions_bound`` and the rigid certificate's bound."""
    bound = 0.0
    if certificate is not None:
        bound = _self_stress_bound(p, np.asarray(certificate.t, dtype=float), certificate.residual)
    return max(bound, tensions_bound)
