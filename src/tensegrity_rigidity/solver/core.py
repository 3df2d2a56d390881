"""The certified rigid/floppy verdict of an instance and its exact relaxed state.

:func:`decide` runs the verdict search (:mod:`.stages`) on unit stiffnesses and unit strain
scale (the verdict depends on neither) and returns a :class:`Verdict`: by Farkas' lemma an
instance is rigid iff an admissible self-stress does positive work on the strain, floppy iff a
displacement puts every element in its admissible set, and only a certificate accepted by the
resolution model of :mod:`.certificates` decides; otherwise the instance is undecided, with both
best candidates, never guessed. :func:`solve` composes the verdict with the relaxation
(:mod:`.relaxation`: ``E*``, ``t*`` and a certified lower bound) and the minimum-norm projection
(:mod:`.displacements`) into a :class:`SolveResult` in the instance's units.
"""

from __future__ import annotations

import os
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, UndecidedWarning
from ..model.limits import check_energy_scale
from ..model.mechanics import affine_extensions, energy_from_extensions, rigidity_matrix
from ..model.network import Instance
from .certificates import FloppyCertificate, RigidCertificate, undecided_reason
from .displacements import MinimumNorm, minimum_norm
from .linalg import one_blas_thread
from .options import SolverOptions
from .problem import Problem
from .relaxation import Relaxation, energy_certified, relax
from .stages import search

__all__ = ["SolveResult", "SolverOptions", "Verdict", "decide", "energy_certified", "solve"]


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
    reason : str
        "" when decided, else ``"within resolution"`` or ``"not resolved"``
        (:func:`~.certificates.undecided_reason`).
    """

    status: str
    rigid: RigidCertificate | None
    floppy: FloppyCertificate | None
    stage: str
    scale: float
    factorizations: int
    iterations: int
    message: str = ""
    reason: str = ""

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
        verdict it is the relaxation's lowest energy, E* to within ``Tolerances.energy_gap`` where
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
    displacements : (N, d) float
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
        the energy's lower bound on a rigid or undecided verdict (``Tolerances.energy_gap``).
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
    reason : str
        "" when decided, else ``"within resolution"`` or ``"not resolved"`` (:class:`Verdict`).

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
    reason: str = ""

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
            "reason": self.reason,
            "seconds": float(self.seconds),
        }


def _check_scale(p: Problem) -> None:
    check_energy_scale(p.scale, p.instance.network.stiffness_or_ones()[p.sites])


def _undecided_message(s, reason: str, evidence: str) -> str:
    parts = [f"{reason}: {evidence}"]
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
    reason = evidence = ""
    if not s.decided:
        reason, evidence = undecided_reason(s.rigid, s.floppy, s.resolution, p.exact.roundoff)
    return Verdict(
        status=status,
        rigid=s.rigid,
        floppy=s.floppy,
        stage=s.stage,
        scale=p.scale,
        factorizations=p.factorizations,
        iterations=s.iterations,
        message="" if s.decided else _undecided_message(s, reason, evidence),
        reason=reason,
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
    initial_displacements : (N, d) float, optional
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
        Resolution model, strategies and limits; the defaults suit any geometry and strain
        magnitude.
    initial_displacements : (N, d) float, optional
        Warm start (for example the solution of a neighbouring sample).

    Returns
    -------
    SolveResult
        Energy, tensions, minimum-norm displacements, verdict and its certificate.

    Notes
    -----
    ``solve`` = the verdict (:func:`decide`) -> the relaxation
    (:func:`~.relaxation.relax`) -> the minimum-norm projection
    (:func:`~.displacements.minimum_norm`). The verdict never rests on an energy threshold:
    rigid needs an admissible self-stress doing positive work beyond its residual, floppy a
    displacement of bounded size whose extensions are admissible to ``violation_tol``.
    """
    opts = options or SolverOptions()
    start = time.perf_counter()
    with one_blas_thread():  # the same last bits whatever the thread settings
        p, s = _search(instance, opts, initial_displacements)
        verdict = _verdict(p, s)
        relaxed = relax(instance, p, s, verdict.status, opts)
        projected = minimum_norm(relaxed, opts.min_norm)
    if not verdict.decided:
        warnings.warn(f"undecided sample: {verdict.message}", UndecidedWarning, stacklevel=2)
    return _result(instance, p, verdict, relaxed, projected, time.perf_counter() - start)


def _result(
    instance: Instance,
    p: Problem,
    verdict: Verdict,
    relaxed: Relaxation,
    projected: MinimumNorm,
    seconds: float,
) -> SolveResult:
    """The three levels' results in the instance's physical units."""
    net, pe, k_unit = instance.network, relaxed.problem, relaxed.k_unit
    e_unit = k_unit * p.scale**2
    disp = (projected.u * p.scale).reshape(-1, p.dim)
    disp = disp - disp.mean(axis=0)
    # the certified sum itself, else the projection's bound (physical units)
    norm_lower = projected.norm_lower * p.scale**2
    min_norm_lower = float(np.sum(disp**2)) if projected.ok else float(norm_lower)
    t_full = np.zeros(net.n_sites)
    t_full[p.sites] = relaxed.tensions * k_unit * p.scale
    affine = affine_extensions(net, instance.strain)
    rc, fc = verdict.rigid, verdict.floppy
    message = verdict.message
    if projected.message:
        message = f"{message}; {projected.message}" if message else projected.message
    factorizations = p.factorizations + (pe.factorizations if pe is not p else 0)
    return SolveResult(
        energy=float(relaxed.energy * e_unit),
        energy_lower=float(relaxed.energy_lower * e_unit),
        affine_energy=energy_from_extensions(net.kinds, net.stiffness_or_ones(), affine),
        rigid=verdict.status == "rigid",
        decided=verdict.decided,
        tensions=t_full,
        displacements=disp,
        extensions=affine + rigidity_matrix(net) @ disp.ravel(),
        work=rc.work if rc is not None else 0.0,
        force_residual=rc.residual if rc is not None else np.inf,
        violation=fc.violation if fc is not None else np.inf,
        displacement_size=fc.size if fc is not None else np.inf,
        iterations=relaxed.iterations,
        factorizations=factorizations + relaxed.extra_factorizations,
        method=verdict.stage or "undecided",
        min_norm_ok=projected.ok,
        min_norm_residuals=projected.residuals,
        min_norm_lower=min_norm_lower,
        message=message,
        seconds=seconds,
        reason=verdict.reason,
    )
