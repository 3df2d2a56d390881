"""Every numeric constant of the search and the relaxation, named once with its meaning.

Held by :class:`~.options.SolverOptions` (so it enters the sweep settings digest) and by each
:class:`~.problem.Problem`, through which the routines read it; lengths in units of ``max |e0|``,
stiffnesses relative to the mean. ``tau`` and ``U`` are ``SolverOptions.violation_tol`` and
``displacement_bound``; a strategy's knobs are its own fields (:mod:`.stages`).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from ..errors import InputError
from ..model.network import check_real, show

#: ``mu`` of the Newton matrix ``R^T D R + mu I`` (relative to the mean stiffness) unless given
DEFAULT_REGULARIZATION = 1e-12
#: the least ``mu`` accepted, about 45 times double precision's epsilon: a smaller shift is lost in
#: the rounding of the Newton matrix's diagonal, and the factorisation of a floppy network's
#: singular matrix fails (CHOLMOD at 1e-16)
MIN_REGULARIZATION = 1e-14


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
        Extension beyond which a crossover releases or adds an element.
    crossover_taus : tuple of float
        Engagement tolerances tried in turn by the search's and the relaxation's crossovers.
    hint_crossover_taus : tuple of float
        Engagement tolerances of the crossovers from a starting point given to ``decide``.
    support_tol : float
        Purification's default relative size below which a tension is dropped.
    purify_roundoff : float
        Purification stops refining once ``|R^T t|_1 <= purify_roundoff |t|_1``.
    purify_hopeless : float
        Purification gives up after a projection whose relative residual stays above this.
    purify_shift : float
        Shift of purification's matrix ``R^T W R``, relative to ``max t^2``.
    purify_work_floor : float
        Purification's default ``work_floor`` (the default ``tau``): rounds doing less stall it.
    rod_weight : float
        Weight of every rod in purification and balancing, relative to ``max t^2``.
    rebalance_shifts : tuple of float
        Shifts of balancing's matrix, relative to ``max t^2``, tried in turn.
    rebalance_ratio_slack : float
        Relative slack of balancing's ratio test: elements reaching zero within it are fixed.
    support_optimal_shift : float
        Shift of ``R^T K_S R`` of the best self-stress on a support (times 1, 1e2, 1e4).
    energy_gap : float
        Largest relative gap ``(E - E_lower) / E`` at which the relaxed energy is certified.
    relax_short_ipm : tuple of (int, float)
        (iterations, tolerance) of the relaxation's interior point.
    relax_long_ipm : tuple of (int, float)
        The same for its long run, where the short one leaves the energy uncertified.
    relax_long_shift : float
        Newton-matrix shift of the long run, below the near-mechanisms' curvature (docs/model.md).
    stationary : float
        Relative force residual of Newton's end point at which the relaxation skips its IPM.
    final_crossover_tau : float
        Engagement tolerance of the relaxation's final crossover.
    final_crossover_raise : float
        Largest relative energy increase at which that crossover is kept.
    balanced_residual : float
        Relative force residual below which relaxed tensions count as an exact self-stress.
    bound_residual : float
        Largest relative force residual of a self-stress that gives a weak-duality bound on E*.
    min_norm_tol : float
        Largest feasibility and stationarity KKT residual of a certified minimum-norm minimiser.
    min_norm_dual : float
        Largest relative wrong-signed multiplier of a certified minimum-norm minimiser.
    min_norm_regularization : float
        Regularisation ``d`` of the projection's reduced KKT systems.
    min_norm_held : float
        The active set first holds the inequalities within this (times ``max |u|``) of their bound.
    min_norm_violated : float
        Relative violation at which the projection's active set adds an inequality.
    min_norm_kkt_exact : float
        KKT measure at which the projection's interior point stops as converged.
    min_norm_kkt_stall : float
        KKT measure below which it stops after 8 iterations without a new best.
    min_norm_certify_below : float
        KKT measure below which its iterate is checked for a certificate.
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
    purify_hopeless: float = 1e-3
    purify_shift: float = 1e-14
    purify_work_floor: float = 1e-9
    rod_weight: float = 1e-6
    rebalance_shifts: tuple[float, ...] = (1e-18, 1e-16, 1e-14)
    rebalance_ratio_slack: float = 1e-9
    support_optimal_shift: float = 1e-14
    energy_gap: float = 1e-8
    relax_short_ipm: tuple[int, float] = (60, 1e-10)
    relax_long_ipm: tuple[int, float] = (200, 1e-14)
    relax_long_shift: float = 1e-15
    stationary: float = 1e-10
    final_crossover_tau: float = 1e-9
    final_crossover_raise: float = 1e-12
    balanced_residual: float = 1e-13
    bound_residual: float = 1e-12
    min_norm_tol: float = 1e-8
    min_norm_dual: float = 1e-9
    min_norm_regularization: float = 1e-14
    min_norm_held: float = 1e-9
    min_norm_violated: float = 1e-12
    min_norm_kkt_exact: float = 1e-12
    min_norm_kkt_stall: float = 1e-6
    min_norm_certify_below: float = 1e-4
    min_norm_multiplier_shifts: tuple[float, ...] = (1e-12, 1e-10, 1e-8)

    def __post_init__(self) -> None:
        # every constant is a finite non-negative number (a tuple: each of them; 0 can mean
        # "none", as a work floor of 0); a NaN or a negative one was accepted and silently
        # changed every comparison it enters
        for f in fields(self):
            value = getattr(self, f.name)
            numbers = value if isinstance(value, tuple) else (value,)
            if not all(finite_number(x) and x >= 0 for x in numbers):
                what = "numbers" if isinstance(value, tuple) else "a number"
                raise InputError(
                    f"Tolerances.{f.name} must be {what} finite and non-negative, got {show(value)}"
                )


def finite_number(x) -> bool:
    """Whether ``x`` is a finite real scalar as
    :func:`~tensegrity_rigidity.model.network.check_real` accepts it (a Python or NumPy number,
    not a bool; an int too large for a float is not)."""
    try:
        check_real("value", x)
    except InputError:
        return False
    return True
