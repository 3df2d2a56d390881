"""The certified rigid/floppy verdict of an instance and its exact relaxed state.

:func:`decide` runs the verdict search (:mod:`.stages`) on unit stiffnesses and unit strain
scale (the verdict depends on neither): by Farkas' lemma an instance is rigid iff an admissible
self-stress does positive work on the strain, floppy iff a displacement puts every element in
its admissible set, and only a certificate accepted by the resolution model decides; otherwise
it is undecided, never guessed. :func:`solve` = :func:`decide` -> :func:`~.relaxation.relax` ->
:func:`~.displacements.minimum_norm`, in the instance's units.
"""

from __future__ import annotations

import math
import os
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, UndecidedWarning
from ..model.limits import check_energy_scale, check_memory, stage_bytes
from ..model.mechanics import affine_extensions, energy_from_extensions, rigidity_matrix
from ..model.network import Instance, PeriodicNetwork, short_repr, show
from .certificates import FloppyCertificate, Resolution, RigidCertificate, undecided_reason
from .displacements import MinimumNorm, minimum_norm
from .linalg import one_blas_thread
from .options import SolverOptions
from .problem import Problem
from .relaxation import Relaxation, energy_certified, relax
from .stages import search

__all__ = ["SolveResult", "SolverOptions", "Verdict", "decide", "energy_certified", "solve"]


@dataclass(frozen=True, eq=False)
class Verdict:
    """A certified verdict (the result of :func:`decide`).

    Attributes
    ----------
    status : str
        "rigid", "floppy" or "undecided".
    rigid : RigidCertificate or None
        The accepted self-stress, else the best candidate found.
    floppy : FloppyCertificate or None
        The accepted displacement, else the best candidate found (units of ``scale``).
    stage : str
        The strategy whose candidate was accepted ("" when undecided).
    scale : float
        ``max |e0|`` over all bond sites, empty ones included (physical units).
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
        """Whether a certificate was accepted (False within resolution of the boundary)."""
        return self.status != "undecided"

    def __repr__(self) -> str:
        """Status, stage, the two certificates (arrays by shape), work spent; a few lines."""
        head = short_repr(self, [(k, getattr(self, k)) for k in ("status", "stage", "reason")])
        rest = [f"    rigid={self.rigid!r}", f"    floppy={self.floppy!r}"]
        rest.append(
            f"    scale={self.scale:.6g}, factorizations={self.factorizations}, "
            f"iterations={self.iterations}, message={self.message!r}"
        )
        return head[:-1] + ",\n" + ",\n".join(rest) + ")"


@dataclass(frozen=True, eq=False)
class SolveResult:
    """The relaxed state of an instance and the certificate behind its verdict.

    Attributes
    ----------
    energy : float
        Minimum energy E* (docs/model.md) in the instance's units; exactly 0 on a floppy verdict,
        else the relaxation's lowest energy (E* to within ``Tolerances.energy_gap`` where
        :func:`energy_certified` holds for it and ``energy_lower``).
    energy_lower : float
        A certified lower bound on E* (weak duality from a self-stress); ``energy - energy_lower``
        bounds the error of ``energy``.
    affine_energy : float
        Energy of the affine deformation, E(u = 0).
    rigid, decided : bool
        The verdict (False also when undecided) and whether a certificate was accepted.
    tensions : (m,) float
        Tensions t* (zero on empty sites, >= 0 on cables, <= 0 on struts).
    displacements : (N, d) float
        Minimising displacements, mean translation removed (minimum-norm when ``min_norm_ok``).
    extensions : (m,) float
        Total extensions e0 + R u at those displacements.
    work, force_residual : float
        Normalised work ``t . e0 / (|t|_1 max |e0|)`` and ``|R^T t|_1 / |t|_1`` of the best
        self-stress (0 and ``inf`` when the search met none).
    violation, displacement_size : float
        Largest violation (units of ``max |e0|``) and ``max |u| / max |e0|`` of the best floppy
        candidate (``inf`` when there is none; on a rigid verdict a rejected one).
    iterations, factorizations : int
        Newton iterations; numeric factorisations of the verdict, relaxation and projection.
    method : str
        The strategy whose certificate decided ("newton", "ipm", ...), or "undecided".
    min_norm_ok : bool
        Whether the displacements are the minimum-norm minimiser, certified by their KKT
        residuals on the polyhedron of minimisers (itself certified by ``energy_lower``).
    min_norm_residuals : tuple of 3 float
        Feasibility (units of ``max |e0|``), stationarity and dual KKT residuals; NaN when not
        computed, 0 when nothing is strained.
    min_norm_lower : float
        A certified lower bound on ``sum_i |u*_i|^2`` (length^2): the sum itself where
        ``min_norm_ok``, else the projection's weak-duality bound; NaN where no projection ran.
    message : str
        Why the sample is undecided and why the displacements are not certified minimum-norm.
    seconds : float
        Wall time of the solve (reported only).
    reason : str
        "" when decided, else ``"within resolution"`` or ``"not resolved"`` (:class:`Verdict`).
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
        return "undecided" if not self.decided else ("rigid" if self.rigid else "floppy")

    def __repr__(self) -> str:
        """Verdict, energies, certificate residuals, work spent and the arrays' shapes (the
        arrays themselves are attributes); a few lines instead of every tension."""
        groups = [
            ("status", "method", "reason"),
            ("energy", "energy_lower", "affine_energy"),
            ("work", "force_residual", "violation", "displacement_size"),
            ("min_norm_ok", "iterations", "factorizations", "seconds"),
            ("tensions", "displacements", "extensions"),
        ]
        lines = [short_repr(self, [(k, getattr(self, k)) for k in g])[:-1] for g in groups]
        name = type(self).__name__ + "("
        body = [lines[0]] + ["    " + line[len(name) :] for line in lines[1:]]
        if self.message:
            body.append(f"    message={self.message!r}")
        return ",\n".join(body) + ")"

    def summary(self) -> dict:
        """Scalars of the result as a JSON-ready dict.

        Returns
        -------
        dict
            Status, verdict, energies, certificate residuals, work counts, method and message;
            non-finite numbers as None (so that ``json.dumps`` writes valid JSON).
        """

        floats = ("energy", "energy_lower", "affine_energy", "work", "force_residual")
        out = {"status": self.status, "rigid": bool(self.rigid), "decided": bool(self.decided)}
        for name in (*floats, "violation", "displacement_size"):
            x = float(getattr(self, name))
            out[name] = x if np.isfinite(x) else None
        out |= {"iterations": int(self.iterations), "factorizations": int(self.factorizations)}
        out |= {"method": self.method, "min_norm_ok": bool(self.min_norm_ok)}
        return out | {
            "message": self.message,
            "reason": self.reason,
            "seconds": float(self.seconds),
        }


def _undecided_message(s, reason: str, evidence: str) -> str:
    parts = [f"{reason}: {evidence}"]
    if s.rigid is not None:
        parts.append(f"best self-stress: work {s.rigid.work:.2e}, residual {s.rigid.residual:.2e}")
    if (f := s.floppy) is not None:
        parts.append(f"best displacement: violation {f.violation:.2e}, size {f.size:.2e}")
    if s.ends:
        parts.append("solvers ended: " + ", ".join(s.ends))
    return "; ".join(parts)


def _starting_point(name: str, value, shape: tuple[int, ...]) -> np.ndarray:
    """A starting point as a finite float array of ``shape`` (or the same numbers flat)."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be a numeric array, got {show(value)}") from None
    if arr.size != math.prod(shape):
        raise InputError(f"{name} must have shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} contains NaN or infinite values")
    return arr.reshape(shape)


def _search(instance: Instance, opts: SolverOptions, start, start_tensions=None):
    """The problem of ``instance`` and the verdict search on it, from the given starting points."""
    if not isinstance(instance, Instance):
        hint = " (load a file with load_instance(path) first)"
        hint = hint if isinstance(instance, (str, os.PathLike)) else ""
        raise InputError(f"expected an Instance, got {type(instance).__name__}{hint}")
    if not isinstance(opts, SolverOptions):
        raise InputError(
            f"options must be a SolverOptions, got {type(opts).__name__} (e.g. "
            "SolverOptions(max_iter=100))"
        )
    net = instance.network
    if start is not None:
        start = _starting_point("initial_displacements", start, (net.n_nodes, net.dim))
    if start_tensions is not None:
        start_tensions = _starting_point("initial_tensions", start_tensions, (net.n_sites,))
    need = stage_bytes("solve", net.n_nodes, dim=net.dim)
    check_memory(need, f"solving a {net.dim}D network of {net.n_nodes:,} nodes")
    lengths = net.bond_lengths()  # both checks read them
    check_displacement_bound(net, opts.displacement_bound, lengths)
    check_length_range(net, opts.violation_tol, lengths)
    p = Problem(instance, opts.regularization, opts.factorization, True, tolerances=opts.tolerances)
    if p.scale == 0 and np.any(instance.strain):
        unit = instance.strain / float(np.abs(instance.strain).max())
        if np.any(affine_extensions(net, unit)):  # zero only through underflow
            raise InputError(
                "the strain is not zero but every affine extension underflows to zero in "
                "double precision; rescale the strain (verdicts do not depend on its magnitude)"
            )
    check_energy_scale(p.scale, instance.network.stiffness_or_ones()[p.sites])
    u0 = t0 = None
    if start is not None and p.scale > 0:
        u0 = np.asarray(start, dtype=float).ravel() / p.scale
    if start_tensions is not None:
        t0 = np.asarray(start_tensions, dtype=float)[p.sites]
    s = search(p, opts.resolution, opts.stages, u0, t0, opts.refiner, opts.polish, opts.balance)
    return p, s


def linear_size(network: PeriodicNetwork, lengths: np.ndarray | None = None) -> float:
    """The box's largest width (distance between opposite faces) in median bond lengths.

    A zero-energy displacement that takes up a strain across the box can be that large in units
    of the largest affine extension, so a smaller displacement bound ``U`` would call floppy
    networks rigid (docs/model.md, "The resolution model").

    Parameters
    ----------
    network : PeriodicNetwork
        The network (empty sites count among the bonds).
    lengths : (m,) float, optional
        Its bond lengths, when already at hand.

    Returns
    -------
    float
        ``max_a w_a / median |d_b|`` (0 without bonds).
    """
    lengths = network.bond_lengths() if lengths is None else lengths
    if lengths.size == 0:
        return 0.0
    unit = float(np.abs(network.box).max())  # widths of the box scaled to 1: no overflow
    widths = 1.0 / np.linalg.norm(np.linalg.inv(network.box / unit), axis=0)
    return float(widths.max() * (unit / float(np.median(lengths))))


def check_displacement_bound(
    network: PeriodicNetwork, bound: float, lengths: np.ndarray | None = None
) -> None:
    """Refuse a displacement bound ``U`` below the network's :func:`linear_size`.

    Parameters
    ----------
    network : PeriodicNetwork
        The network to be decided.
    bound : float
        ``SolverOptions.displacement_bound``.
    lengths : (m,) float, optional
        Its bond lengths, when already at hand.

    Raises
    ------
    InputError
        When ``bound < linear_size(network)``.
    """
    size = linear_size(network, lengths)
    if bound < size:
        raise InputError(
            f"SolverOptions.displacement_bound = {bound:g} is below this network's linear size "
            f"({size:.3g} bond lengths): its zero-energy displacements can be that large, so "
            "floppy samples would be called rigid; use at least that (the default is "
            f"{Resolution.displacement:g})"
        )


#: The resolution of the lengths: the shortest bond's affine extension must stay this many
#: violation tolerances above the largest one's, else its constraint is below the resolution.
LENGTH_RESOLUTION = 1e3


def check_length_range(
    network: PeriodicNetwork, violation_tol: float, lengths: np.ndarray | None = None
) -> None:
    """Refuse bond lengths that span more than ``1 / (LENGTH_RESOLUTION tau)`` (1e6 by default).

    Tolerances are relative to the largest affine extension over every site (empty ones too, so
    that a threshold search sees one scale along its path); a bond ``1 / tau`` times shorter than
    the longest is below that resolution, and a rod across a unit box beside an empty site 2e9
    long read floppy with ``u = 0``.

    Parameters
    ----------
    network : PeriodicNetwork
        The network.
    violation_tol : float
        ``tau`` of the resolution model.
    lengths : (m,) float, optional
        Its bond lengths, when already at hand.

    Raises
    ------
    InputError
        When ``max |d_b| / min |d_b|`` (all sites) exceeds the bound.
    """
    lengths = network.bond_lengths() if lengths is None else lengths
    if lengths.size == 0:
        return
    ratio = float(lengths.max()) / float(lengths.min())
    top = 1.0 / (LENGTH_RESOLUTION * violation_tol)
    if ratio > top:
        raise InputError(
            f"bond lengths span a factor {ratio:.3g}, more than {top:.3g}: at violation_tol = "
            f"{violation_tol:g} relative to the largest affine extension the shortest bonds' "
            "constraints fall below the resolution (drop empty sites that are much longer than "
            "the elements, or lower violation_tol)"
        )


def _verdict(p: Problem, s) -> Verdict:
    status = "undecided" if not s.decided else ("rigid" if s.rigid_verdict else "floppy")
    reason = evidence = ""
    if not s.decided:
        reason, evidence = undecided_reason(s.rigid, s.floppy, s.resolution, p.exact.roundoff)
    message = "" if s.decided else _undecided_message(s, reason, evidence)
    return Verdict(
        status, s.rigid, s.floppy, s.stage, p.scale, p.factorizations, s.iterations, message, reason
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
        Resolution model, strategies and tolerances.
    initial_displacements : (N, d) float, optional
        A starting point (offered as a floppy candidate and crossed over).
    initial_tensions : (m,) float, optional
        Tensions on every site (a neighbouring configuration's self-stress, say), purified and
        offered as a rigid candidate first.

    Returns
    -------
    Verdict
        Status, the accepted certificate (or the best candidates) and the work spent. Starting
        points only add candidates: they never change a decided verdict.
    """
    opts = SolverOptions() if options is None else options
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
        Resolution model, strategies and tolerances.
    initial_displacements : (N, d) float, optional
        Warm start (for example the solution of a neighbouring sample).

    Returns
    -------
    SolveResult
        Energy, tensions, minimum-norm displacements, verdict and its certificate: the verdict
        (:func:`decide`), then the relaxation (:func:`~.relaxation.relax`), then the minimum-norm
        projection (:func:`~.displacements.minimum_norm`). No energy threshold decides.
    """
    opts = SolverOptions() if options is None else options
    start = time.perf_counter()
    with one_blas_thread():  # the same last bits whatever the thread settings
        p, s = _search(instance, opts, initial_displacements)
        verdict = _verdict(p, s)
        relaxed = relax(instance, p, s, verdict.status, opts)
        projected = minimum_norm(relaxed, opts.min_norm)
    if not verdict.decided:
        warnings.warn(f"undecided sample: {verdict.message}", UndecidedWarning, stacklevel=2)
    seconds = time.perf_counter() - start
    return _result(instance, p, verdict, relaxed, projected, seconds, opts.displacement_bound)


def _result(
    instance: Instance,
    p: Problem,
    verdict: Verdict,
    relaxed: Relaxation,
    projected: MinimumNorm,
    seconds: float,
    bound: float,
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
    beyond = ""
    size = float(np.abs(relaxed.u).max(initial=0.0))
    if verdict.status == "rigid" and size > bound:
        beyond = (
            f"rigid within the displacement bound U = {bound:g}: the relaxation lowered the "
            f"energy with displacements of size {size:.3g} beyond it (units of the largest "
            "affine extension), where the resolution model does not look (docs/model.md)"
        )
    message = "; ".join(x for x in (verdict.message, projected.message, beyond) if x)
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
