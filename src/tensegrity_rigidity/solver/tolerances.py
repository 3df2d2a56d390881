"""Every numeric constant of the search and the relaxation, named once with its meaning.

A :class:`Tolerances` is held by :class:`~.options.SolverOptions` (and so enters the sweep
settings digest) and by each :class:`~.problem.Problem`, through which the numerical routines
read it. Lengths are in units of ``max |e0|``, stiffnesses relative to the mean stiffness;
"relative" means relative to the quantity named. The resolution model's ``tau`` and ``U`` are
``SolverOptions.violation_tol`` and ``SolverOptions.displacement_bound``; the knobs of one
strategy are the fields of that strategy (:mod:`.stages`).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tolerances:
    """Numeric constants of the verdict search and the relaxation (dimensionless).

    Attributes
    ----------
    newton_gradient_stop : float
        Newton stops once ``|R^T t| <= newton_gradient_stop |t|`` (round-off).
    newton_progress : float
        Relative energy decrease that counts as progress of a Newton step.
    newton_full_step : float
        A Newton step is truncated when ``|alpha - 1|`` exceeds this.
    prox_gradient_stop : float
        Proximal iterations stop once the gradient fell by this factor from its start.
    crossover_sign_tol : float
        Extension (relative to ``max |e0|``) beyond which a crossover releases or adds an element.
    crossover_taus : tuple of float
        Engagement tolerances tried in turn by the search's and the relaxation's crossovers.
    hint_crossover_taus : tuple of float
        Engagement tolerances of the crossovers from a starting point given to ``decide``.
    support_tol : float
        Purification's default relative size below which a tension is dropped (round-off
        tensions of elements only touched by a minimiser belong to no self-stress).
    purify_roundoff : float
        Purification stops refining once ``|R^T t|_1 <= purify_roundoff |t|_1``.
    rebalance_ratio_slack : float
        Relative slack of balancing's ratio test: elements reaching zero within it are fixed.
    energy_gap : float
        Largest relative gap ``(E - E_lower) / E`` at which the relaxed energy is certified and
        its tensions are taken as ``t*`` for the minimum-norm projection.
    relax_short_ipm : tuple of (int, float)
        (iterations, tolerance) of the relaxation's interior point.
    relax_long_ipm : tuple of (int, float)
        The same for its long run, where the short one leaves the energy uncertified.
    relax_long_shift : float
        Newton-matrix shift of the long run (in place of ``SolverOptions.regularization``):
        near a threshold the energy falls along near-mechanisms of curvature below ``1e-12``.
    stationary : float
        Relative force residual of Newton's end point below which the relaxation's interior
        point is not run.
    final_crossover_tau : float
        Engagement tolerance of the relaxation's final crossover.
    final_crossover_raise : float
        Largest relative energy increase at which that crossover is kept (it must also lower
        the force residual).
    balanced_residual : float
        Relative force residual below which the relaxed tensions count as an exact self-stress
        (kept as they are, or as purified).
    bound_residual : float
        Largest relative force residual of a self-stress that gives a weak-duality bound on E*.
    min_norm_held : float
        The projection's held set starts with the inequalities within this (relative to
        ``max |u|``) of their bound at the start.
    min_norm_violated : float
        Relative violation at which the projection's active set adds an inequality.
    min_norm_kkt_exact : float
        KKT measure at which the projection stops as converged.
    min_norm_kkt_stall : float
        KKT measure below which the projection stops after 8 iterations without a new best.
    min_norm_dual : float
        Largest relative wrong-signed multiplier of a certified minimum-norm minimiser.
    min_norm_certify_below : float
        KKT measure below which the projection's iterate is refined and certified.
    min_norm_multiplier_shifts : tuple of float
        Shifts tried in turn when the projection's multipliers are refined.
    """

    newton_gradient_stop: float = 1e-14
    newton_progress: float = 1e-13
    newton_full_step: float = 1e-6
    prox_gradient_stop: float = 1e-14
    crossover_sign_tol: float = 1e-12
    crossover_taus: tuple[float, ...] = (1e-7, 1e-5, 1e-3)
    hint_crossover_taus: tuple[float, ...] = (1e-9, 1e-7)
    support_tol: float = 1e-9
    purify_roundoff: float = 1e-16
    rebalance_ratio_slack: float = 1e-9
    energy_gap: float = 1e-8
    relax_short_ipm: tuple[int, float] = (60, 1e-10)
    relax_long_ipm: tuple[int, float] = (200, 1e-14)
    relax_long_shift: float = 1e-15
    stationary: float = 1e-10
    final_crossover_tau: float = 1e-9
    final_crossover_raise: float = 1e-12
    balanced_residual: float = 1e-13
    bound_residual: float = 1e-12
    min_norm_held: float = 1e-9
    min_norm_violated: float = 1e-12
    min_norm_kkt_exact: float = 1e-12
    min_norm_kkt_stall: float = 1e-6
    min_norm_dual: float = 1e-9
    min_norm_certify_below: float = 1e-4
    min_norm_multiplier_shifts: tuple[float, ...] = (1e-12, 1e-10, 1e-8)
