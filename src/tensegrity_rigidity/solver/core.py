"""Exact relaxation of the linear tensegrity energy and a certified rigid/floppy verdict.

:func:`decide` returns the verdict and the certificate behind it; :func:`solve` adds the
relaxed state: the minimum energy ``E*``, the unique tensions ``t*`` and the minimum-norm
minimising displacements.

Verdict. By Farkas' lemma an instance is rigid iff an admissible self-stress does positive work
on the strain, floppy iff a displacement puts every element in its admissible set. The search
(:mod:`.stages`) runs fast specialised stages that propose displacements and tensions;
:mod:`.certificates` accepts a candidate only under one resolution model that makes the two
certificates exclude each other (a floppy displacement within a stated bound, a self-stress
whose work exceeds what its force residual could explain). The verdict does not depend on the
stiffnesses or on the strain magnitude, so the search runs on unit stiffnesses and unit strain
scale. An instance with no accepted certificate is reported undecided, with both best
candidates, never guessed.

Relaxed state. On a floppy verdict ``E* = 0`` and ``t* = 0``. On a rigid one (or an undecided
one) the energy with the given stiffnesses is minimised from the search's lowest-energy point
by semismooth Newton, the interior point and a crossover (:mod:`.newton`, :mod:`.ipm`), and the
report includes a lower bound on ``E*`` from the purified tensions (weak duality), so the
accuracy of ``E*`` is stated, not assumed.

Displacements. Minimisers are not unique on floppy networks; :func:`solve` returns the
minimum-norm minimiser (the limit of a vanishing background stiffness), with the mean
translation removed (see :mod:`.displacements`).
"""

from __future__ import annotations

import os
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, UndecidedWarning
from ..model.mechanics import affine_extensions, energy_from_extensions, rigidity_matrix
from ..model.network import Instance
from .certificates import FloppyCertificate, RigidCertificate
from .displacements import project
from .ipm import IpmState, interior_point
from .linalg import one_blas_thread
from .newton import crossover, newton
from .options import SolverOptions
from .problem import Problem
from .selfstress import kept, optimal_on_support, purify
from .stages import search
from .tolerances import Tolerances


@dataclass(frozen=True)
class Verdict:
    """A certified verdict (the result of :func:`decide`).

    Attributes
    ----------
    status : str
        "rigid", "floppy" or "undecided".
    rigid : RigidCertificate or None
        The accepted self-stress (rigid), else the best candidate found.
    floppy : FloppyCertificate or None
        The accepted displacement (floppy), else the best candidate found. Displacements are
        in units of ``scale``.
    stage : str
        The stage whose candidate was accepted ("" when undecided).
    scale : float
        ``max |e0|`` over the non-empty sites (physical units).
    factorizations, iterations : int
        Work spent: numeric factorisations, Newton iterations.
    message : str
        Why the sample is undecided ("" otherwise).
    """

    status: str
    rigid: RigidCertificate | None
    floppy: FloppyCertificate | None
    stage: str
    scale: float
    factorizations: int
    iterations: int
    message: str = ""

    @property
    def decided(self) -> bool:
        """Whether a certificate was accepted.

        Returns
        -------
        bool
            False when the instance is within resolution of the boundary (or no stage found
            a certificate).
        """
        return self.status != "undecided"


@dataclass(frozen=True)
class SolveResult:
    """The relaxed state of an instance and the certificate behind its verdict.

    Attributes
    ----------
    energy : float
        Minimum energy E* = min_u 1/2 sum_b k_b h_b(e_b) e_b^2 (docs/model.md) in the instance's
        units (stiffness x length^2); exactly 0 on a floppy verdict. On a rigid or undecided
        verdict it is the relaxation's lowest energy, E* to within :data:`ENERGY_GAP` where
        :func:`energy_certified` holds for it and ``energy_lower``.
    energy_lower : float
        A certified lower bound on E* (weak duality from the relaxed tensions purified onto a
        self-stress, or from the rigid certificate's self-stress, whichever is larger; E*
        itself on a floppy verdict). ``energy - energy_lower`` bounds the error of ``energy``.
    affine_energy : float
        Energy of the affine deformation, E(u = 0).
    rigid : bool
        Verdict (False also when undecided; check ``decided``).
    decided : bool
        True when a certificate was accepted.
    tensions : (m,) float
        Tensions t* at the minimum (zero on empty sites, >= 0 on cables, <= 0 on struts).
    displacements : (N, 2) float
        Minimising displacements, mean translation removed (minimum-norm when ``min_norm_ok``).
    extensions : (m,) float
        Total extensions e0 + R u at the reported displacements.
    work : float
        Normalised work ``t . e0 / (|t|_1 max |e0|)`` of the best self-stress (the rigid
        certificate on a rigid verdict).
    force_residual : float
        ``|R^T t|_1 / |t|_1`` of that self-stress (``inf`` when the search met no self-stress,
        as on most floppy verdicts, with ``work`` 0).
    violation : float
        Largest violation of the best floppy candidate, in units of ``max |e0|`` (``inf``
        when the search met none). On a rigid verdict this is a rejected candidate, often
        ``u = 0`` (violation 1 when the largest affine extension is on a rod, size 0).
    displacement_size : float
        ``max |u| / max |e0|`` of that candidate (``inf`` when there is none).
    iterations : int
        Newton iterations.
    factorizations : int
        Numeric factorisations of the solver's ``2N x 2N`` matrix: the verdict's, the
        relaxation's and the minimum-norm projection's.
    method : str
        The stage whose certificate decided ("newton", "ipm", ...), or "undecided".
    min_norm_ok : bool
        Whether the displacements are the minimum-norm minimiser, certified by its KKT
        residuals (:mod:`.displacements`) on the polyhedron of minimisers, itself certified by
        the energy's lower bound on a rigid or undecided verdict (:data:`ENERGY_GAP`).
    min_norm_residuals : tuple of 3 float
        Those residuals: feasibility (the largest violation of the polyhedron of minimisers,
        units of ``max |e0|``); stationarity (the larger of ``|u + R^T lam|_inf / |u|_inf``
        and the relative duality gap, both dimensionless); dual (the largest wrong-signed
        multiplier relative to ``|lam|_inf``). All NaN when the displacements were not asked
        for (``SolverOptions.min_norm`` False) or not computed (relaxed energy not certified);
        all 0 when nothing is strained or there is no element (``u = 0`` is exact).
    min_norm_lower : float
        A certified lower bound on ``sum_i |u*_i|^2`` of the minimum-norm minimiser (length^2):
        that sum itself where ``min_norm_ok``; where the projection ran but was not certified,
        the bound weak duality gives from its multipliers
        (:func:`~tensegrity_rigidity.solver.displacements.norm_lower_bound`); NaN where no
        projection ran.
    message : str
        Why the sample is undecided, and why the displacements are not certified minimum-norm
        (not asked for, relaxed energy not certified, or the projection's residuals); empty
        when there is nothing to say.
    seconds : float
        Wall time of the solve (reported only; nothing depends on it).

    See Also
    --------
    status : "rigid", "floppy" or "undecided" (a property).
    """

    energy: float
    energy_lower: float
    affine_energy: float
    rigid: bool
    decided: bool
    tensions: np.ndarray
    displacements: np.ndarray
    extensions: np.ndarray
    work: float
    force_residual: float
    violation: float
    displacement_size: float
    iterations: int
    factorizations: int
    method: str
    min_norm_ok: bool
    min_norm_residuals: tuple[float, float, float] = (np.nan, np.nan, np.nan)
    min_norm_lower: float = np.nan
    message: str = ""
    seconds: float = field(default=0.0)

    @property
    def status(self) -> str:
        """ "rigid", "floppy" or "undecided"."""
        if not self.decided:
            return "undecided"
        return "rigid" if self.rigid else "floppy"

    def summary(self) -> dict:
        """Scalars of the result as a JSON-ready dict.

        Returns
        -------
        dict
            Status, verdict, energies, certificate residuals, work counts, method and
            message; non-finite numbers as None (so that ``json.dumps`` writes valid JSON).
        """

        def num(x):
            x = float(x)
            return x if np.isfinite(x) else None

        return {
            "status": self.status,
            "rigid": bool(self.rigid),
            "decided": bool(self.decided),
            "energy": num(self.energy),
            "energy_lower": num(self.energy_lower),
            "affine_energy": num(self.affine_energy),
            "work": num(self.work),
            "force_residual": num(self.force_residual),
            "violation": num(self.violation),
            "displacement_size": num(self.displacement_size),
            "iterations": int(self.iterations),
            "factorizations": int(self.factorizations),
            "method": self.method,
            "min_norm_ok": bool(self.min_norm_ok),
            "message": self.message,
            "seconds": float(self.seconds),
        }


def _check_scale(p: Problem) -> None:
    if p.scale and not 1e-150 <= p.scale <= 1e150:
        raise InputError(
            f"the largest affine extension is {p.scale:.1e}: energies (proportional to its "
            "square) are not representable in double precision; rescale the strain "
            "(verdicts do not depend on its magnitude)"
        )


def _undecided_message(s) -> str:
    parts = ["no certificate passed the resolution model"]
    if s.rigid is not None:
        parts.append(f"best self-stress: work {s.rigid.work:.2e}, residual {s.rigid.residual:.2e}")
    if s.floppy is not None:
        parts.append(
            f"best displacement: violation {s.floppy.violation:.2e}, size {s.floppy.size:.2e}"
        )
    return "; ".join(parts)


def _search(
    instance: Instance,
    opts: SolverOptions,
    start: np.ndarray | None,
    start_tensions: np.ndarray | None = None,
):
    if not isinstance(instance, Instance):
        hint = " (load a file with load_instance(path) first)"
        hint = hint if isinstance(instance, (str, os.PathLike)) else ""
        raise InputError(f"expected an Instance, got {type(instance).__name__}{hint}")
    p = Problem(instance, opts.regularization, opts.factorization, True, tolerances=opts.tolerances)
    _check_scale(p)
    u0 = t0 = None
    if start is not None and p.scale > 0:
        u0 = np.asarray(start, dtype=float).ravel() / p.scale
    if start_tensions is not None:
        t0 = np.asarray(start_tensions, dtype=float)[p.sites]
    s = search(p, opts.resolution, opts.stages, u0, t0, opts.refiner, opts.polish, opts.balance)
    return p, s


def _verdict(p: Problem, s) -> Verdict:
    status = "undecided" if not s.decided else ("rigid" if s.rigid_verdict else "floppy")
    return Verdict(
        status=status,
        rigid=s.rigid,
        floppy=s.floppy,
        stage=s.stage,
        scale=p.scale,
        factorizations=p.factorizations,
        iterations=s.iterations,
        message="" if s.decided else _undecided_message(s),
    )


def decide(
    instance: Instance,
    options: SolverOptions | None = None,
    initial_displacements: np.ndarray | None = None,
    initial_tensions: np.ndarray | None = None,
) -> Verdict:
    """The certified verdict of an instance, without the relaxed state.

    Parameters
    ----------
    instance : Instance
        Network, elements and strain.
    options : SolverOptions, optional
        Resolution model, stages and limits.
    initial_displacements : (N, 2) float, optional
        A starting point (offered as a floppy candidate, crossed over, and used by Newton).
    initial_tensions : (m,) float, optional
        Tensions on every site (a neighbouring configuration's self-stress, say), purified
        and offered as a rigid candidate before any stage runs.

    Returns
    -------
    Verdict
        Status, the accepted certificate (or the best candidates) and the work spent.

    Notes
    -----
    Starting points only add candidates: they can decide a sample sooner, never change a
    decided verdict (the certificates exclude each other).
    """
    opts = options or SolverOptions()
    with one_blas_thread():  # the same last bits whatever the thread settings
        p, s = _search(instance, opts, initial_displacements, initial_tensions)
    return _verdict(p, s)


def energy_certified(energy, energy_lower, gap: float = Tolerances.energy_gap):
    """Whether the relaxed energy is within :data:`ENERGY_GAP` of its certified lower bound.

    Parameters
    ----------
    energy, energy_lower : float or (k,) float array
        Relaxed energies and their lower bounds (``SolveResult.energy``, ``energy_lower``;
        the sweep rows' columns of the same names).
    gap : float
        The largest relative gap (``Tolerances.energy_gap``).

    Returns
    -------
    bool or (k,) bool array
        True where the relaxed tensions are certified to be t* (False where either is NaN).
    """
    return energy_lower >= (1.0 - gap) * energy


def _relax(
    p: Problem,
    u: np.ndarray,
    opts: SolverOptions,
    ipm: tuple[int, float] | None = None,
    ipm_start: IpmState | None = None,
) -> tuple[np.ndarray, float, int]:
    """Minimise the energy from u: Newton, then (if not stationary) the interior point with
    ``ipm`` = (iterations, tolerance) + crossover, and a final exact solve on the active set (a
    crossover) when it lowers the force residual. The interior point goes on from
    ``ipm_start`` where it passes through it (the verdict search's own run, which the cold
    start would retrace step for step: :class:`~.ipm.IpmState`)."""

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
    """The relaxation from ``u`` (2N,) and what certifies it (``ipm_start``: see
    :func:`_relax`).

    Returns
    -------
    u : (2N,) float
        Lowest-energy displacements found.
    E : float
        Their energy.
    iterations : int
        Newton iterations spent.
    t_relaxed : (m,) float
        Their tensions ``k (e0 + R u)`` (zero on slack one-sided elements).
    t_balanced : (m,) float
        The same moved onto an exact self-stress where they are close to one.
    E_lower : float
        Certified lower bound on E*, at most ``E``.
    """
    u, E, more = _relax(p, u, opts, ipm, ipm_start)
    _, _, t_relaxed = p.state(u)
    t_n, tensions_bound = _balanced_tensions(p, t_relaxed)
    E_lower = min(_energy_lower(p, tensions_bound, certificate), E)
    if E > 0 and not energy_certified(E, E_lower, opts.tolerances.energy_gap):
        t_opt, bound = _support_optimal_tensions(p, t_relaxed)
        if bound > E_lower:
            E_lower = min(bound, E)
            if energy_certified(E, E_lower, opts.tolerances.energy_gap):
                t_n = t_opt
    return u, E, more, t_relaxed, t_n, E_lower


def _long_relaxation(
    instance: Instance,
    opts: SolverOptions,
    unit_stiffness: bool,
    u: np.ndarray,
    certificate: RigidCertificate | None,
) -> tuple[tuple | None, int]:
    """The relaxation's long run (``RELAX_IPM[1]``) from ``u`` (2N,), on a Newton matrix
    shifted by :data:`RELAX_LONG_SHIFT`.

    Returns
    -------
    result : tuple or None
        What :func:`_relaxed` returns, or None where a factorisation failed (the shift is
        below the round-off of a pivot).
    factorizations : int
        Numeric factorisations spent.
    """
    tol = opts.tolerances
    pl = Problem(instance, tol.relax_long_shift, opts.factorization, unit_stiffness, tol)
    try:
        return _relaxed(pl, u, opts, certificate, tol.relax_long_ipm), pl.factorizations
    except ArithmeticError:
        return None, pl.factorizations


def _balanced_tensions(p: Problem, t: np.ndarray) -> tuple[np.ndarray, float]:
    """The minimiser's tensions, moved onto an exact self-stress when they are close to one,
    and the lower bound on E* that self-stress gives.

    Tensions read off displacements as ``k (e0 + R u)`` lose digits to cancellation when they
    are small; purification (:func:`~.selfstress.purify`) balances them to round-off with a
    relative change of the order of their force residual. Kept only if it balances them
    better than 1e-13 relative, else the tensions are returned as they were. Tensions that
    already balance the nodes to 1e-13 (their round-off entries dropped, as purification
    drops them: :data:`~.selfstress.SUPPORT_TOL`), as a converged Newton minimiser's do
    (``3e-16`` to ``8e-16`` on the rigid phase-diagram instances at n = 64), are kept without
    purifying: one factorisation fewer per rigid ``solve()`` (paired on those 9 instances,
    scratch, 2026-11-28: 5.6 ms of 125 ms on average, the same energies, bounds and
    displacements, tensions within 1e-14).

    Returns
    -------
    t_n : (m,) float or longdouble
        The purified tensions where kept, else ``t``.
    bound : float
        :func:`_self_stress_bound` of the purified tensions with their exact force residual
        (0 where purification fails). One purification serves both: the bound used to come
        from purifying ``t_n`` again, about 9 ms of a rigid sample's 127 ms ``solve()`` at
        n = 64 (median of the 9 rigid phase-diagram instances of ``bench_solver.py``,
        scratch, 2026-11-27).
    """
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


def _support_optimal_tensions(p: Problem, t: np.ndarray) -> tuple[np.ndarray, float]:
    """The minimiser's tensions ``t`` ((m,), zero on slack elements) moved onto the best
    self-stress of their support for the energy's dual
    (:func:`~.selfstress.optimal_on_support`), and the lower bound on E* it gives.

    Where the relaxation has converged, :func:`_balanced_tensions` certifies the energy; near
    a sample's own threshold its purification (weighted by ``t^2``) can land on a self-stress
    far from the dual optimum although the engaged set is right. On the 12 at-threshold
    configurations of issue 13's set at n = 32 (``benchmarks/bench_solver.py``), one rigid
    energy was uncertified with a bound of 0.34 of it; this one certifies it to ``4e-12``.
    Where the engaged set is wrong (four at-threshold n = 64 configurations, energies ``1e-12``
    to ``1e-6`` of the affine one) dropping the flipped elements empties the self-stress of
    work and the bound is 0.

    Returns
    -------
    t_opt : (m,) float
        The self-stress (``t`` itself when there is none).
    bound : float
        :func:`_self_stress_bound` of it (0 when there is none).
    """
    x = optimal_on_support(p, t)
    if x is None:
        return t, 0.0
    t_opt = np.asarray(x, dtype=float)
    return t_opt, _self_stress_bound(p, t_opt, _exact_residual(p, x))


def _exact_residual(p: Problem, t: np.ndarray) -> float:
    """Relative force residual ``|R^T t|_1 / |t|_1`` of tensions ``t`` ((m,) float or
    longdouble), the forces in extended precision (0 for ``t = 0``). No floor on ``|t|_1``:
    tensions that underflow to subnormal sizes get the large residual they have, so that
    :func:`_self_stress_bound` rejects them instead of dividing by their underflowed norm."""
    size = float(np.abs(t).sum())
    return float(np.abs(p.exact.forces(t)).sum()) / size if size > 0 else 0.0


def _self_stress_bound(p: Problem, t: np.ndarray, residual: float) -> float:
    """Weak-duality lower bound on E* from an admissible self-stress ``t`` (m,) whose relative
    force residual ``|R^T t|_1 / |t|_1`` is ``residual``.

    Any self-stress gives ``E* >= max_a (a t.e0 - a^2/2 t.K^-1 t) = (t.e0)^2 / (2 t.K^-1 t)``.
    The residual adds at most ``|R^T t|_1 |u*|_inf`` to the work, which we do not know, so the
    bound is 0 unless the residual is at round-off (``<= 1e-12``).
    """
    work = float(np.dot(t, p.e0))
    if residual > p.tol.bound_residual or work <= 0 or not np.all(np.isfinite(t)):
        return 0.0
    return work**2 / (2.0 * float(np.dot(t, t / p.k)))


def _energy_lower(
    p: Problem, tensions_bound: float, certificate: RigidCertificate | None = None
) -> float:
    """Lower bound on E*: the larger of ``tensions_bound`` (the bound from the minimiser's
    tensions purified onto a self-stress, :func:`_balanced_tensions`) and the bound from the
    rigid certificate's self-stress.

    Where the relaxation has converged the first equals E to round-off; where it has not
    (near a sample's own threshold) it is 0 and the certificate's bound is what is left: 0.20
    and 0.26 of the relaxed energy on the two such n = 32 at-threshold configurations, 0.001
    to 0.015 on four at n = 64, 0 on two more whose certificates' force residuals (3e-9, 2e-8)
    are above round-off.
    """
    bound = 0.0
    if certificate is not None:
        tc = np.asarray(certificate.t, dtype=float)
        bound = _self_stress_bound(p, tc, certificate.residual)
    return max(bound, tensions_bound)


def _joined(message: str, more: str) -> str:
    """``message`` and ``more`` joined by "; " (``more`` alone when ``message`` is empty)."""
    return f"{message}; {more}" if message else more


def solve(
    instance: Instance,
    options: SolverOptions | None = None,
    initial_displacements: np.ndarray | None = None,
) -> SolveResult:
    """Relax an instance exactly and decide whether it rigidly resists its strain.

    Parameters
    ----------
    instance : Instance
        Network, elements and strain.
    options : SolverOptions, optional
        Resolution model, stages and limits; the defaults suit any geometry and strain
        magnitude.
    initial_displacements : (N, 2) float, optional
        Warm start (for example the solution of a neighbouring sample).

    Returns
    -------
    SolveResult
        Energy, tensions, minimum-norm displacements, verdict and its certificate.

    Notes
    -----
    See the module docstring. The verdict never rests on an energy threshold: rigid needs an
    admissible self-stress doing positive work beyond its residual, floppy a displacement of
    bounded size whose extensions are admissible to ``violation_tol``.
    """
    opts = options or SolverOptions()
    tol = opts.tolerances
    start = time.perf_counter()
    with one_blas_thread():  # the same last bits whatever the thread settings
        p, s = _search(instance, opts, initial_displacements)
        verdict = _verdict(p, s)
        net = instance.network
        k_sites = net.stiffness_or_ones()[p.sites]
        uniform = k_sites.size == 0 or bool(np.all(k_sites == k_sites[0]))
        # with one stiffness the verdict's unit-stiffness problem is the energy's too
        pe = (
            p
            if uniform
            else Problem(instance, opts.regularization, opts.factorization, tolerances=tol)
        )
        k_unit = float(k_sites[0]) if uniform and k_sites.size else pe.k_scale
        extra_factorizations = 0
        if verdict.status == "floppy":
            u_n = np.asarray(s.floppy.u, dtype=float)
            t_relaxed = np.zeros(p.sites.size)
            E_n = 0.0
            t_n = np.zeros(p.sites.size)
            E_lower = 0.0
            iterations = s.iterations
        else:
            u_n, E_n, more, t_relaxed, t_n, E_lower = _relaxed(
                pe, s.u, opts, verdict.rigid, ipm_start=s.ipm_end
            )
            if not energy_certified(E_n, E_lower, tol.energy_gap):  # near the threshold
                long, extra_factorizations = _long_relaxation(
                    instance, opts, uniform, u_n, verdict.rigid
                )
                if long is not None:
                    u_2, E_2, more_2, t_relaxed_2, t_n_2, E_lower_2 = long
                    more += more_2
                    E_lower = max(E_lower, E_lower_2)  # both bound E* from below
                    if E_2 < E_n:
                        u_n, E_n, t_relaxed, t_n = u_2, E_2, t_relaxed_2, t_n_2
                    E_lower = min(E_lower, E_n)  # and E_n bounds it from above
            iterations = s.iterations + more
        min_norm_ok, message, kkt = False, verdict.message, (np.nan, np.nan, np.nan)
        norm_lower = np.nan  # of |u*|^2, units of scale^2
        # the polyhedron of minimisers is built from the relaxed tensions: it is U* only when
        # they are t*, which the energy's lower bound certifies (see ENERGY_GAP)
        certified = verdict.status == "floppy" or energy_certified(E_n, E_lower, tol.energy_gap)
        if opts.min_norm and p.sites.size and np.any(p.e0):
            if not certified:
                message = _joined(
                    message,
                    "minimum-norm displacements not computed: the relaxed energy is not "
                    f"certified (its lower bound is {E_lower / E_n:.1e} of it), so its tensions "
                    "need not be t*; the displacements are the relaxation's lowest point",
                )
            else:
                # the targets t*/k as the minimiser u_n realises them on every equality (rods,
                # and one-sided elements where the balanced tensions t_n are not zero:
                # purification drops the round-off tensions of elements that are only touched),
                # so that the equalities of U* are consistent: a rod's target is its extension
                # at u_n even where t_n is 0 (zero targets there left the system inconsistent
                # by that extension, and the projection could not reach feasibility)
                mn = project(pe, np.where(pe.rod | (t_n != 0), t_relaxed, 0.0), u_n)
                kkt = (mn.feasibility, mn.stationarity, mn.dual)
                if mn.ok:
                    u_n, min_norm_ok = mn.u, True
                else:
                    norm_lower = mn.norm_lower
                    message = _joined(
                        message,
                        "minimum-norm displacements not certified (KKT residuals: feasibility "
                        f"{mn.feasibility:.1e}, stationarity {mn.stationarity:.1e}, dual "
                        f"{mn.dual:.1e}); the displacements are a minimiser; the minimum "
                        f"norm is at least {np.sqrt(norm_lower):.3g} times the largest affine "
                        "extension",
                    )
        elif opts.min_norm:  # nothing strained or no element: u = 0 is the minimum-norm minimiser
            u_n, min_norm_ok, kkt = np.zeros(p.n2), True, (0.0, 0.0, 0.0)
        else:
            message = _joined(
                message, "minimum-norm displacements not asked for (SolverOptions.min_norm)"
            )
    if not verdict.decided:
        warnings.warn(f"undecided sample: {verdict.message}", UndecidedWarning, stacklevel=2)
    # back to physical units
    e_unit = k_unit * p.scale**2
    disp = (u_n * p.scale).reshape(-1, 2)
    disp = disp - disp.mean(axis=0)
    # the certified sum itself, else the projection's bound (physical units)
    min_norm_lower = float(np.sum(disp**2)) if min_norm_ok else float(norm_lower * p.scale**2)
    t_full = np.zeros(net.n_sites)
    t_full[p.sites] = t_n * k_unit * p.scale
    affine = affine_extensions(net, instance.strain)
    e_full = affine + rigidity_matrix(net) @ disp.ravel()
    k = net.stiffness_or_ones()
    rc, fc = verdict.rigid, verdict.floppy
    return SolveResult(
        energy=float(E_n * e_unit),
        energy_lower=float(E_lower * e_unit),
        affine_energy=energy_from_extensions(net.kinds, k, affine),
        rigid=verdict.status == "rigid",
        decided=verdict.decided,
        tensions=t_full,
        displacements=disp,
        extensions=e_full,
        work=rc.work if rc is not None else 0.0,
        force_residual=rc.residual if rc is not None else np.inf,
        violation=fc.violation if fc is not None else np.inf,
        displacement_size=fc.size if fc is not None else np.inf,
        iterations=iterations,
        factorizations=p.factorizations
        + (pe.factorizations if pe is not p else 0)
        + extra_factorizations,
        method=verdict.stage or "undecided",
        min_norm_ok=min_norm_ok,
        min_norm_residuals=kkt,
        min_norm_lower=min_norm_lower,
        message=message,
        seconds=time.perf_counter() - start,
    )
