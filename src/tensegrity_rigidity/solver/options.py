"""The options of a verdict and a solve: the resolution model, the strategies, every tolerance.

:class:`SolverOptions` is the one object a verdict depends on besides the instance. It is
frozen plain data throughout, so the sweep settings digest is derived from it as a whole
(:meth:`~tensegrity_rigidity.ensemble.spec.Spec.settings`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

from ..errors import InputError
from ..model.network import show
from .certificates import Resolution, violation_roundoff
from .stages import DEFAULT_STRATEGIES, STRATEGIES, Refiner
from .tolerances import DEFAULT_REGULARIZATION, MIN_REGULARIZATION, Tolerances, finite_number


def strategy_named(name: str):
    """The strategy of :data:`~.stages.STRATEGIES` named ``name`` ("lp", say)."""
    if name not in STRATEGIES:
        raise InputError(f"unknown solver stage {show(name)}; choose from {', '.join(STRATEGIES)}")
    return STRATEGIES[name]


@dataclass(frozen=True)
class SolverOptions:
    """Tolerances, strategies, limits and switches of :func:`solve` and :func:`decide`.

    Attributes
    ----------
    violation_tol : float
        ``tau`` of the resolution model: the largest violation of a floppy certificate and the
        smallest normalised work of a rigid one, in units of ``max |e0|``.
    displacement_bound : float
        ``U`` of the resolution model: the largest displacement of a floppy certificate, in units
        of ``max |e0|``; a rigid certificate's force residual is weighed against it.
    stages : tuple of strategies
        The strategies of the verdict search in order (default
        :data:`~tensegrity_rigidity.solver.stages.DEFAULT_STRATEGIES`): objects with a ``name``
        and a ``run(search)`` method, or names of default strategies (:func:`strategy_named`).
    polish, balance : bool
        Whether the refiner polishes floppy candidates that narrowly fail, balances rigid ones
        (:class:`~tensegrity_rigidity.solver.stages.Refiner`).
    regularization : float
        ``mu`` of the Newton matrix, relative to the mean stiffness.
    max_iter : int
        Newton iterations when the energy is minimised for the relaxed state.
    min_norm : bool
        Compute the minimum-norm minimiser (needed for the nonaffinity).
    factorization : str
        Sparse factorisation backend: "auto", "cholmod" or "qdldl" (:mod:`.linalg`).
    refiner : Refiner
        How candidates are cleaned before the certificates judge them.
    tolerances : Tolerances
        The numeric constants of the search and the relaxation.
    """

    violation_tol: float = Resolution.violation
    displacement_bound: float = Resolution.displacement
    stages: tuple = DEFAULT_STRATEGIES
    polish: bool = True
    balance: bool = True
    regularization: float = DEFAULT_REGULARIZATION
    max_iter: int = 40
    min_norm: bool = True
    factorization: str = "auto"
    refiner: Refiner = field(default_factory=Refiner)
    tolerances: Tolerances = field(default_factory=Tolerances)

    def __post_init__(self):
        if self.factorization not in ("auto", "cholmod", "qdldl"):
            raise InputError(
                "SolverOptions.factorization must be 'auto', 'cholmod' or 'qdldl', "
                f"got {show(self.factorization)}"
            )
        stages = self.stages
        # a list or tuple only: a table ({lp = 1} in a spec) iterates as its keys, a string
        # as its letters
        if not isinstance(stages, (list, tuple)) or not all(
            isinstance(x, str) or (hasattr(x, "run") and hasattr(x, "name")) for x in stages
        ):
            raise InputError(
                f"SolverOptions.stages must be a list of strategies or names, got {show(stages)}"
            )
        if not stages:
            raise InputError(
                "SolverOptions.stages is empty: no stage would look for a certificate, so every "
                "sample would end undecided; choose from "
                + ", ".join(x.name for x in DEFAULT_STRATEGIES)
            )
        strategies = tuple(strategy_named(x) if isinstance(x, str) else x for x in stages)
        object.__setattr__(self, "stages", strategies)
        for f in fields(self):
            value = getattr(self, f.name)
            kind = {"int": int, "float": (int, float), "bool": bool}.get(str(f.type))
            if kind is None:
                continue
            if not isinstance(value, kind) or isinstance(value, bool) != (kind is bool):
                raise InputError(f"SolverOptions.{f.name} must be {f.type}, got {show(value)}")
            if kind is not bool and not (finite_number(value) and value >= 0):
                raise InputError(
                    f"SolverOptions.{f.name} must be finite and non-negative, got {show(value)}"
                )
        if not self.regularization >= MIN_REGULARIZATION:
            raise InputError(
                f"SolverOptions.regularization must be at least {MIN_REGULARIZATION:g}, got "
                f"{show(self.regularization)}: below it the shift is lost in rounding and the "
                "Newton matrix of a floppy network is singular"
            )
        for name, kind in (("refiner", Refiner), ("tolerances", Tolerances)):
            if not isinstance(getattr(self, name), kind):
                raise InputError(
                    f"SolverOptions.{name} must be a {kind.__name__}, got "
                    f"{show(getattr(self, name))}"
                )
        self._check_resolution()

    def _check_resolution(self) -> None:
        """Refuse tolerances under which one kind of certificate could never or always pass."""
        tau, U = self.violation_tol, self.displacement_bound
        if not 0 < tau < 1:
            raise InputError(
                f"SolverOptions.violation_tol must lie in (0, 1), got {tau!r}: at 1 or more "
                "u = 0 passes as a floppy certificate of every sample"
            )
        if not U > 0 or violation_roundoff(U) >= tau:
            raise InputError(
                f"SolverOptions.displacement_bound = {U!r} leaves no floppy certificate "
                f"possible at violation_tol = {tau!r} (the round-off of a violation at that "
                "size reaches tau, or the bound is not positive)"
            )

    @property
    def resolution(self) -> Resolution:
        """The certificates' ``Resolution(violation_tol, displacement_bound)``."""
        return Resolution(self.violation_tol, self.displacement_bound)
