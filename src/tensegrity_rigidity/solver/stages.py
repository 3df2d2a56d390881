"""The verdict search: strategies that propose candidates to one search state.

Strategies propose displacements ``u`` (floppy candidates) and tensions ``t`` (rigid ones) to a
:class:`Search`, whose :class:`Refiner` cleans each first; only a certificate accepted by the
resolution model (:mod:`.certificates`) decides. A strategy is a frozen dataclass (its fields its
knobs) with a ``name`` and ``run(search)``; they run in order (:data:`DEFAULT_STRATEGIES`) until a
candidate is accepted. Every limit is a count, never a time (docs/model.md, "How the verdict is
found").
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ..model.network import Instance
from .certificates import FloppyCertificate, Resolution, RigidCertificate
from .highs import run_lp
from .ipm import IpmState, interior_point
from .newton import crossover, newton
from .problem import Problem
from .selfstress import kept, purify, rebalance


@dataclass(eq=False)
class Search:
    """State shared by the strategies of one verdict search (normalised units of the problem)."""

    #: The problem (unit stiffness for the verdict).
    p: Problem
    #: Tolerances of the certificates.
    resolution: Resolution
    #: How candidates are cleaned; ``polish`` and ``balance`` switch its two steps.
    refiner: Refiner = field(default_factory=lambda: Refiner())
    polish: bool = False
    balance: bool = False
    #: The lowest-energy point offered so far and its energy.
    u: np.ndarray = field(default_factory=lambda: np.zeros(0))
    E: float = np.inf
    #: The accepted certificate, else the best candidate: the smallest violation, the largest
    #: margin ``work - U residual``.
    floppy: FloppyCertificate | None = None
    rigid: RigidCertificate | None = None
    #: The strategy whose candidate was accepted ("" while undecided).
    stage: str = ""
    #: Newton iterations spent; candidates polished and balanced so far.
    iterations: int = 0
    polished: int = 0
    balanced: int = 0
    #: Where the interior point strategy ended, for the relaxation to go on from.
    ipm_end: IpmState | None = None
    #: How the strategies' solvers ended ("lp: verdict LP Iteration limit reached", ...): an
    #: undecided verdict names them.
    ends: list[str] = field(default_factory=list)

    def __post_init__(self):
        if self.u.size == 0:  # start at the origin
            self.u = np.zeros(self.p.n2)
            self.E = self.p.energy(self.u)

    @property
    def decided(self) -> bool:
        """Whether a candidate was accepted."""
        return bool(self.stage)

    @property
    def rigid_verdict(self) -> bool:
        """Whether the accepted candidate is a self-stress."""
        return self.rigid is not None and self.rigid.accepted

    def offer_u(self, u: np.ndarray, stage: str, E: float | None = None) -> bool:
        """Offer displacements ``u`` ((2N,) float or longdouble, precision kept) with their energy
        ``E`` if known, as a floppy candidate and as the lowest-energy point; polished when they
        narrowly fail. True once the search is decided."""
        if self.decided:
            return True
        exact = np.asarray(u)
        u = np.asarray(exact, dtype=float)  # no copy when it is already a double array
        if not np.all(np.isfinite(u)):
            return False
        E = self.p.energy(u) if E is None else E
        if E < self.E:
            self.u, self.E = u, E
        cert = self._offer_floppy(self.p.exact.floppy(exact, self.resolution), stage)
        if self.polish and self.refiner.polishes(cert, self.resolution, self.polished):
            self.polished += 1
            x = self.refiner.polished(self, exact)
            if x is not None:
                self._offer_floppy(self.p.exact.floppy(x, self.resolution), stage)
        return self.decided

    def _offer_floppy(self, cert: FloppyCertificate, stage: str) -> FloppyCertificate:
        """Keep ``cert`` if it is the best floppy candidate so far; decide if it is accepted."""
        if self.floppy is None or _floppy_key(cert) < _floppy_key(self.floppy):
            self.floppy = cert
        if cert.accepted:
            self.stage = stage
        return cert

    def offer_t(self, t: np.ndarray, stage: str, as_is: bool = False) -> bool:
        """Offer approximate tensions ``t`` ((m,) on the non-empty sites) as a rigid candidate,
        purified and, where that narrowly fails, balanced. ``as_is``: check ``t`` itself first, in
        its own precision (for tensions purification could only coarsen). True once decided."""
        if self.decided:
            return True
        if as_is and self._offer_rigid(self.p.exact.rigid(t, self.resolution), stage):
            return True
        t = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(t)) or not np.any(t):
            return False
        res, best = self.resolution, None
        for tp in self.refiner.purified(self, t):
            cert = self.p.exact.rigid(tp, res)
            if self._offer_rigid(cert, stage):
                return True
            if best is None or _rigid_key(cert, res) > _rigid_key(best, res):
                best = cert
        if self.balance and best is not None and self.refiner.balances(best, res, self.balanced):
            self.balanced += 1
            x = rebalance(self.p, best.t, steps=self.refiner.balance_steps)
            if x is not None:
                self._offer_rigid(self.p.exact.rigid(x, res), stage)
        return self.decided

    def _offer_rigid(self, cert: RigidCertificate, stage: str) -> bool:
        """Keep ``cert`` if it is the best rigid candidate so far; True if it is accepted."""
        res = self.resolution
        if self.rigid is None or _rigid_key(cert, res) > _rigid_key(self.rigid, res):
            self.rigid = cert
        if cert.accepted:
            self.stage = stage
        return cert.accepted

    def note(self, stage: str, what: str, h) -> None:
        """Record how the solved ``highspy.Highs`` ``h`` of ``stage``'s ``what`` ended."""
        self.ends.append(f"{stage}: {what} {h.modelStatusToString(h.getModelStatus())}")

    def offer_point(self, u: np.ndarray, stage: str) -> bool:
        """Offer displacements ``u`` (2N,) and the tensions of the energy at them; True once
        decided."""
        e, _, t = self.p.state(u)
        E = 0.5 * float(np.dot(t, e))
        return self.offer_u(u, stage, E) or (E > 0 and self.offer_t(t, stage))

    def crossovers(self, u: np.ndarray, stage: str, taus=None) -> bool:
        """Crossovers (:func:`~.newton.crossover`) from ``u`` (2N,) at the widening ``taus``
        (default ``Tolerances.crossover_taus``); True once the search is decided."""
        for tau in self.p.tol.crossover_taus if taus is None else taus:
            x = crossover(self.p, u, tau=tau)
            if x is not None and self.offer_point(x, stage):
                return True
        return False


def _floppy_key(c: FloppyCertificate) -> tuple:
    return (not c.accepted, c.violation)


def _rigid_key(c: RigidCertificate, res: Resolution) -> float:
    return c.work - res.displacement * c.residual


@dataclass(frozen=True)
class Refiner:
    """How the search cleans candidates before the certificates judge them.

    Tensions are purified at each support tolerance; the best rejected purification with work left
    is balanced (:func:`~.selfstress.rebalance`). A floppy candidate within ``U`` failing by at most
    ``polish_below`` is polished onto its tight set by :class:`Refine`'s proximal iteration, in
    extended precision. Both are bounded by counts per search.
    """

    #: Relative sizes below which approximate tensions are dropped before purification.
    support_tols: tuple[float, ...] = (1e-6, 1e-9)
    #: Largest violation of a floppy candidate that is polished (units of ``max |e0|``).
    polish_below: float = 1e-6
    #: Slacks within which one-sided elements are held at their bound, tried in turn.
    polish_slacks: tuple[float, ...] = (1e-6, 1e-9)
    #: Most rounds (tight sets) per slack; most candidates polished per search.
    polish_rounds: int = 3
    polish_attempts: int = 4
    #: Largest relative force residual of a rigid candidate that is balanced.
    balance_below: float = 1e-6
    #: A candidate is balanced only when ``U r <= balance_reduction (w - tau)``.
    balance_reduction: float = 1e5
    #: Most candidates balanced per search; most corrections (factorisations) per candidate.
    balance_attempts: int = 4
    balance_steps: int = 20
    #: The proximal iteration's settings.
    proximal: Refine = field(default_factory=lambda: Refine())

    def purified(self, s: Search, t: np.ndarray):
        """Yield the purifications ((m,) float or longdouble) of tensions ``t`` (m,) at the support
        tolerances (nothing for a failed one)."""
        previous = None
        for support_tol in self.support_tols:
            support = kept(t, support_tol)
            if previous is not None and np.array_equal(support, previous):
                continue  # purify's input, and so its result, as at the last tolerance
            previous = support
            try:
                yield purify(s.p, t, support_tol=support_tol, work_floor=s.resolution.violation)
            except ArithmeticError:
                continue

    def balances(self, cert: RigidCertificate, res: Resolution, done: int = 0) -> bool:
        """Whether a rejected rigid candidate is worth balancing after ``done`` others."""
        margin = float(cert.work) - res.violation
        return (
            done < self.balance_attempts
            and margin > 0
            and cert.residual <= self.balance_below
            and res.displacement * cert.residual <= self.balance_reduction * margin
        )

    def polishes(self, cert: FloppyCertificate, res: Resolution, done: int = 0) -> bool:
        """Whether a floppy candidate is worth polishing after ``done`` others."""
        return (
            not cert.accepted
            and cert.violation <= self.polish_below
            and cert.size <= res.displacement
            and done < self.polish_attempts
        )

    def polished(self, s: Search, u: np.ndarray) -> np.ndarray | None:
        """The polished displacements ((2N,) longdouble) of ``u`` (2N,): the first end point that is
        a floppy certificate, else the first that converged, else None."""
        fallback = None
        for slack in self.polish_slacks:
            x = self._polish(s, u, slack)
            if x is None:
                continue
            if s.p.exact.floppy(x, s.resolution).accepted:
                return x
            fallback = x if fallback is None else fallback
        return fallback

    def _polish(self, s: Search, u: np.ndarray, slack: float) -> np.ndarray | None:
        """Rounds of the proximal iteration from ``u`` holding the elements within ``slack`` of
        their bound; the end point ((2N,) longdouble), or None."""
        p = s.p
        v = np.asarray(p.exact.extensions(u), dtype=float)
        active = p.rod | (p.sigma * v >= -slack)
        x = np.asarray(u, dtype=np.longdouble)
        for _ in range(self.polish_rounds):
            solver = p.factor_shifted(active.astype(float), self.proximal.shifts)
            if solver is None:
                return None
            x, _, converged = self.proximal._round(s, active, solver, start=x)
            if not converged:
                return None
            v = np.asarray(p.exact.extensions(x), dtype=float)
            joined = ~active & (p.sigma * v > 0)
            if not joined.any():
                break
            active = active | joined
        return x


@dataclass(frozen=True)
class Affine:
    """The tensions of the affine deformation: decides deeply rigid samples."""

    name: str = "affine"

    def run(self, s: Search) -> None:
        s.offer_point(np.zeros(s.p.n2), self.name)


@dataclass(frozen=True)
class Newton:
    """Semismooth Newton from the search's point (:func:`~.newton.newton`), stopped once the energy
    alone would allow a violation of a tenth of ``tau``."""

    max_iter: int = 15
    max_truncated: int = 4
    name: str = "newton"

    def run(self, s: Search) -> None:
        floor = 0.5 * (0.1 * s.resolution.violation) ** 2
        u, E, it = newton(s.p, s.u, self.max_iter, self.max_truncated, floor)
        s.iterations += it
        s.offer_point(u, self.name)


@dataclass(frozen=True)
class InteriorPoint:
    """The energy interior point (:func:`~.ipm.interior_point`) to ``tol`` in ``max_iter``
    iterations: its point offered and crossed over at ``checkpoint_taus`` at each of the
    ``checkpoints``, at its end at every crossover tau."""

    checkpoints: tuple[float, ...] = (1e-3, 1e-5, 1e-7)
    checkpoint_taus: tuple[float, ...] = (1e-7,)
    tol: float = 1e-9
    max_iter: int = 60
    name: str = "ipm"

    def run(self, s: Search) -> None:
        def tensions(u, lam):
            t = s.p.k * (s.p.e0 + s.p.R @ u)
            t[s.p.one_sided] = s.p.sigma[s.p.one_sided] * lam
            return t

        def offer(u, lam, taus=None):
            return (
                s.offer_u(u, self.name)
                or s.offer_t(tensions(u, lam), self.name)
                or s.crossovers(u, self.name, taus=taus)
            )

        end: list[IpmState] = []
        at_checkpoint = partial(offer, taus=self.checkpoint_taus)
        u, _, lam, _ = interior_point(
            s.p, self.max_iter, self.tol, self.checkpoints, at_checkpoint, record=end
        )
        s.ipm_end = end[0]
        offer(u, lam)


@dataclass(frozen=True)
class Refine:
    """The minimum-norm zero-violation displacements on the engaged set, in extended precision.

    Proximal steps on one factorisation per round, extrapolated every ``window`` steps, solve
    ``min |u|`` s.t. ``e0_A + R_A u = 0`` on the engaged set ``A`` (docs/solver.md), where the
    energy's huge minimisers near a threshold stall at their round-off; a stalled round offers its
    least-squares self-stress, and elements the end point violates join ``A`` for the next.
    """

    #: ``mu`` relative to the unit stiffness, tried in turn until a factorisation succeeds.
    shifts: tuple[float, ...] = (1e-13, 1e-11, 1e-9)
    #: Steps between extrapolations.
    window: int = 8
    #: Extrapolations in a row that may fail to halve the least violation so far.
    patience: int = 2
    #: Most steps per round (each one back-substitution); most rounds (engaged sets).
    max_iter: int = 200
    rounds: int = 3
    name: str = "refine"

    def run(self, s: Search) -> None:
        p = s.p
        active = p.rod | (p.sigma * (p.e0 + p.R @ s.u) >= 0)
        for _ in range(self.rounds):
            solver = p.factor_shifted(active.astype(float), self.shifts)
            if solver is None:
                return
            u, r, converged = self._round(s, active, solver)
            if s.offer_u(u, self.name):
                return
            if not converged:
                if not np.any(p.sigma * r < 0):  # admissible signs: a self-stress candidate
                    s.offer_t(np.asarray(r, dtype=float), self.name)
                return
            v = np.asarray(p.exact.extensions(u), dtype=float)
            joined = ~active & (p.sigma * v > 0)
            if not joined.any():
                return
            active = active | joined

    def _round(self, s: Search, active: np.ndarray, solver, start=None):
        """Proximal steps with extrapolation on the engaged set ``active`` (m,) bool from ``start``
        ((2N,), default the origin): (u (2N,) longdouble, residual on ``active`` (m,), converged).
        """
        ex, goal = s.p.exact, 0.1 * s.resolution.violation
        R = ex.matrix

        def residual(u):  # e0 + R u on the engaged set (the certificate re-checks the end point)
            r = np.where(active, ex.e0n + R @ u, 0)
            return r, float(np.abs(r).max(initial=0.0))

        u = np.zeros(s.p.n2, dtype=np.longdouble) if start is None else start
        u = np.asarray(u, dtype=np.longdouble)
        r, viol = residual(u)
        us, rs, best, misses = [u], [r], viol, 0
        for _ in range(self.max_iter):
            if viol <= goal:
                return u, r, True
            u = u - solver.solve(np.asarray(ex.forces(r), dtype=float))
            r, viol = residual(u)
            us.append(u)
            rs.append(r)
            if len(us) > self.window:
                u, r, viol = _extrapolate(us, rs, residual)
                us, rs = [u], [r]
                if viol < 0.5 * best:
                    best, misses = viol, 0
                else:
                    misses += 1
                    if misses >= self.patience:
                        break
        return u, r, viol <= goal


def _extrapolate(us, rs, residual):
    """The affine combination of iterates ``us`` (each (2N,)) whose residual (the same combination
    of ``rs``, each (m,)) has the least 2-norm: (u, r, max |r|)."""
    last_u, last_r = us[-1], rs[-1]
    D = np.array([np.asarray(x - last_r, dtype=float) for x in rs[:-1]]).T
    c = np.linalg.lstsq(D, -np.asarray(last_r, dtype=float), rcond=None)[0]
    u = last_u + sum(ci * (ui - last_u) for ci, ui in zip(c, us[:-1], strict=True))
    r, viol = residual(u)
    return u, r, viol


@dataclass(frozen=True)
class Support:
    """The search again on the strongly stressed part of the network.

    Near the threshold the nearly slack elements of the best rigid candidate keep the interior
    point from converging. Without the sites whose tension is below ``keep`` times the largest the
    network is smaller; a self-stress found there, zero elsewhere, is checked on the whole network.
    """

    #: Tensions below this fraction of the largest leave the sub-network.
    keep: float = 1e-5
    #: The strategies of the search on the sub-network.
    stages: tuple = (Affine(), Newton(), Refine(), InteriorPoint())
    name: str = "support"

    def __post_init__(self):
        if not 0 < self.keep < 1:
            raise InputError(f"Support.keep must lie in (0, 1), got {self.keep!r}")

    def run(self, s: Search) -> None:
        p, best = s.p, s.rigid
        if best is None or not best.work > s.resolution.violation:
            return
        t = np.asarray(best.t, dtype=float)
        stressed = p.sites[np.abs(t) >= self.keep * float(np.abs(t).max())]
        net = p.instance.network
        kinds = np.zeros_like(net.kinds)
        kinds[stressed] = net.kinds[stressed]
        sub = Problem(
            Instance(net.with_kinds(kinds), p.instance.strain), p.mu, p.backend, True, p.tol
        )
        inner = search(sub, s.resolution, self.stages, refiner=s.refiner, polish=s.polish,
                       balance=s.balance)  # fmt: skip
        if inner.rigid_verdict and inner.rigid is not None:
            lifted = np.zeros(net.kinds.size, dtype=np.asarray(inner.rigid.t).dtype)
            lifted[sub.sites] = inner.rigid.t
            s.offer_t(lifted[p.sites], self.name, as_is=True)


@dataclass(frozen=True)
class LinearProgram:
    """Linear programs of Farkas' lemma, solved by HiGHS with iteration limits.

    The verdict LP ``max e0 . t`` over self-stresses with ``|t_b| <= 1`` (:meth:`verdict_lp`): its
    tensions, its row duals (displacements, crossed over) and its vertex refined in extended
    precision offered. Then, up to ``feasibility_sites_max`` sites, the feasibility LP: a vertex is
    a floppy candidate, a dual ray a rigid one. A HiGHS failure leaves the search as it was.
    """

    #: Interior-point iterations of the verdict LP.
    max_iter: int = 100
    #: Simplex iterations per non-empty site of the feasibility LP (0: not run).
    simplex_iterations_per_site: float = 2.0
    #: Most simplex iterations of the feasibility LP (an iteration costs about ``n^2``).
    simplex_iterations_max: int = 25_000
    #: Refinement rounds of the verdict LP's vertex (0: no crossover, no refinement).
    refine: int = 1
    #: Simplex iterations per non-empty site of each refinement round and the crossover's clean-up.
    refine_iterations_per_site: float = 0.25
    #: Solve the verdict LP again without the crossover when its clean-up hits its limit.
    interior_fallback: bool = True
    #: Above this many non-empty sites the feasibility LP is not run.
    feasibility_sites_max: int = 24_576
    #: HiGHS's primal feasibility tolerance in the feasibility LP (units of ``max |e0|``).
    feasibility_tolerance: float = 1e-9
    #: HiGHS's interior point of the verdict LP, named, never HiGHS's "ipm", which runs HiPO
    #: instead of IPX whenever the plugin ``highspy-extras`` is installed: :data:`INTERIOR_POINTS`.
    interior: str = "ipx"
    name: str = "lp"

    def __post_init__(self):
        if self.interior not in INTERIOR_POINTS:
            raise InputError(
                f"LinearProgram.interior must be one of {', '.join(INTERIOR_POINTS)}, "
                f"got {self.interior!r}"
            )
        if self.interior == "hipo" and not hipo_available():
            raise InputError(
                "LinearProgram.interior = 'hipo' needs HiGHS's HiPO, which the package "
                "highspy-extras provides: pip install highspy-extras"
            )

    def verdict_lp(self, p: Problem, crossover: bool | None = None):
        """The verdict LP ``max e0 . t`` over self-stresses with admissible ``|t_b| <= 1``, as the
        strategy solves it (``crossover``: default when ``refine`` is set): the solved
        ``highspy.Highs`` (columns the tensions, rows the forces), ``R^T`` (2N, m) CSC and the
        bounds ``lo, hi`` (m,)."""
        A = p.RT.tocsc()
        lo = np.where(p.sigma > 0, 0.0, -1.0)
        hi = np.where(p.sigma < 0, 0.0, 1.0)
        zeros = np.zeros(A.shape[0])
        options = {
            "solver": self.interior,
            "run_crossover": "on" if (self.refine if crossover is None else crossover) else "off",
            "ipm_iteration_limit": self.max_iter,
            "simplex_iteration_limit": self._refine_budget(p),
        }
        return run_lp(A, -p.e0, lo, hi, zeros, zeros, **options), A, lo, hi

    def run(self, s: Search) -> None:
        p = s.p
        h, A, lo, hi = self.verdict_lp(p)
        s.note(self.name, "verdict LP", h)
        sol = h.getSolution()
        if not sol.value_valid and self.refine and self.interior_fallback:
            # the crossover's clean-up hit its limit and HiGHS dropped the interior point with it
            h2 = self.verdict_lp(p, crossover=False)[0]
            s.note(self.name, "verdict LP without crossover", h2)
            sol = h2.getSolution()
        if sol.value_valid and sol.dual_valid:
            t = np.asarray(sol.col_value, dtype=float)
            if s.offer_t(np.clip(t, lo, hi), self.name):
                return
            # HiGHS's row duals y satisfy c - A^T y = reduced costs, i.e. e0 + R y = -(bound
            # duals): y is a displacement whose extensions are admissible at the optimum 0.
            u = np.asarray(sol.row_dual, dtype=float)
            if s.offer_u(u, self.name) or s.crossovers(u, self.name):
                return
        if self.refine and self._refine(s, h, A, lo, hi):
            return
        max_iter = self._feasibility_budget(p)
        if max_iter <= 0:
            return
        vertex, ray, h = _feasibility_lp(p, max_iter, tolerance=self.feasibility_tolerance)
        s.note(self.name, "feasibility LP", h)
        if vertex is not None and not s.offer_u(vertex, self.name):
            s.crossovers(vertex, self.name)
        if ray is not None:
            s.offer_t(ray, self.name)

    def _feasibility_budget(self, p: Problem) -> int:
        """Simplex iterations of the feasibility LP (0 above ``feasibility_sites_max``)."""
        if p.sites.size > self.feasibility_sites_max:
            return 0
        per_site = int(self.simplex_iterations_per_site * p.sites.size)
        return min(per_site, self.simplex_iterations_max)

    def _refine_budget(self, p: Problem) -> int:
        """Simplex iterations of the interior point's clean-up and of each refinement round."""
        return int(self.refine_iterations_per_site * p.sites.size)

    def _refine(self, s: Search, h, A, lo, hi) -> bool:
        """``refine`` rounds of LP iterative refinement from the vertex of the solved verdict LP
        ``h``, each result offered; True once the search is decided."""
        sol, basis = h.getSolution(), h.getBasis()
        if not (sol.value_valid and basis.valid):
            return False
        t = np.asarray(sol.col_value, dtype=np.longdouble)
        budget = self._refine_budget(s.p)
        for _ in range(self.refine):
            step = _refinement(s.p, A, lo, hi, t, basis, budget)
            if step is None:
                return False
            t, u, basis = step
            admissible = np.where(s.p.sigma * t < 0, 0, t)
            if s.offer_t(admissible, self.name, as_is=True) or s.offer_u(u, self.name):
                return True
        return False


#: HiGHS's interior points the verdict LP may name: IPX (built into highspy) and HiPO (the plugin
#: ``highspy-extras``); their crossovers and iterates differ, so the choice enters the options.
INTERIOR_POINTS = ("ipx", "hipo")


def hipo_available() -> bool:
    """Whether HiGHS can run its HiPO interior point here (the plugin ``highspy-extras``)."""
    try:
        import highspy_extras  # noqa: F401
    except ImportError:
        return False
    return True


def _refinement(p: Problem, A, lo, hi, t: np.ndarray, basis, max_iter: int):
    """One round of LP iterative refinement of the verdict LP at tensions ``t`` ((m,) longdouble)
    from ``basis``: (refined tensions (m,) longdouble, the correction LP's row duals (2N,), its
    basis), or None when ``t`` is exact or the primal simplex does not end within ``max_iter``."""
    import highspy

    f = p.exact.forces(t)
    d = float(np.max(np.r_[np.abs(f), lo - t, t - hi], initial=0.0))  # the largest defect
    if not (np.isfinite(d) and d > 0):
        return None
    rows = np.asarray(-f / d, dtype=float)
    lo_d, hi_d = np.asarray((lo - t) / d, dtype=float), np.asarray((hi - t) / d, dtype=float)
    # the primal simplex: the basis stays dual feasible, its values do not
    options = {"solver": "simplex", "simplex_strategy": 4, "simplex_iteration_limit": max_iter}
    h = run_lp(A, -p.e0, lo_d, hi_d, rows, rows, basis, **options)
    if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
        return None
    sol = h.getSolution()
    x = np.asarray(sol.col_value, dtype=np.longdouble)
    return t + d * x, np.asarray(sol.row_dual, dtype=float), h.getBasis()


def _feasibility_lp(
    p: Problem,
    max_iter: int,
    variants=("dual", "primal"),
    tolerance=LinearProgram.feasibility_tolerance,
):
    """The feasibility LP ``{u : e0 + R u admissible}`` by HiGHS's simplex, one thread.

    Rows in site order (rods ``R u = -e0``, cables ``<=``, struts ``>=``), free columns; the simplex
    ``variants`` in turn, the next only after status "Unknown", each at most ``max_iter`` iterations
    at HiGHS's primal feasibility ``tolerance``. Returns ``(vertex, ray)``: a vertex (2N,) when
    feasible; when infeasible, minus the dual ray (m,): by Farkas' lemma admissible tensions doing
    positive work with ``R^T t = 0`` up to round-off (the caller purifies and checks them); and
    the last solved ``highspy.Highs``.
    """
    import highspy

    A, inf = p.R.tocsc(), highspy.kHighsInf
    n = A.shape[1]
    free = (np.zeros(n), np.full(n, -inf), np.full(n, inf))  # cost and bounds of the columns
    rows = (np.where(p.sigma > 0, -inf, -p.e0), np.where(p.sigma < 0, inf, -p.e0))
    options = {"solver": "simplex", "simplex_iteration_limit": max_iter}
    options["primal_feasibility_tolerance"] = tolerance
    for variant in variants:
        h = run_lp(A, *free, *rows, **options, simplex_strategy=4 if variant == "primal" else 1)
        status = h.getModelStatus()
        if status == highspy.HighsModelStatus.kOptimal:
            return np.asarray(h.getSolution().col_value, dtype=float), None, h
        if status == highspy.HighsModelStatus.kInfeasible:
            # (status, has_ray, values); missing from highspy's type stubs
            *_, has_ray, ray = h.getDualRay()  # type: ignore[attr-defined]
            return (None, -np.asarray(ray, dtype=float) if has_ray else None, h)
        if status != highspy.HighsModelStatus.kUnknown:
            break  # the budget is spent (or HiGHS failed otherwise): no second variant
    return None, None, h


@dataclass(frozen=True)
class SmallestDisplacement:
    """The smallest floppy displacement: ``min |u|_inf`` s.t. ``e0 + R u`` admissible, by HiGHS's
    dual simplex.

    The resolution model accepts a floppy certificate only within ``U``, so near the threshold the
    search needs the smallest displacement, not any one: a feasibility LP's vertex there lies
    anywhere up to 1e9. The LP's end point (optimal or not) is offered and, being accurate to
    double precision relative to its size, polished when its violation is within
    ``polish_relative`` of its size; when the LP is infeasible its dual ray, admissible tensions
    doing positive work (Farkas), is offered. Skipped when the search already holds an exact
    self-stress doing positive work: the LP is then infeasible (Farkas) and adds nothing.
    """

    #: Dual simplex iterations per non-empty site.
    iterations_per_site: float = 4.0
    #: A candidate is polished when its violation is at most this times its size.
    polish_relative: float = 1e-12
    name: str = "smallest"

    def run(self, s: Search) -> None:
        import highspy

        r = s.rigid
        if r is not None and 0 < r.work and s.resolution.displacement * r.residual < r.work:
            return
        p, inf = s.p, highspy.kHighsInf
        n2, m = p.n2, p.sites.size
        one = sp.csr_matrix(np.ones((n2, 1)))
        eye = sp.identity(n2, format="csr")
        A = sp.vstack(
            [sp.hstack([p.R, sp.csr_matrix((m, 1))]), sp.hstack([eye, -one]), sp.hstack([eye, one])]
        )
        rows_lo = np.r_[np.where(p.sigma > 0, -inf, -p.e0), np.full(n2, -inf), np.zeros(n2)]
        rows_hi = np.r_[np.where(p.sigma < 0, inf, -p.e0), np.zeros(n2), np.full(n2, inf)]
        free = np.full(n2 + 1, inf)
        options = {"solver": "simplex", "simplex_strategy": 1}
        options["simplex_iteration_limit"] = int(self.iterations_per_site * m)
        h = run_lp(A, np.r_[np.zeros(n2), 1.0], -free, free, rows_lo, rows_hi, **options)
        s.note(self.name, "smallest-displacement LP", h)
        sol = h.getSolution()
        if sol.value_valid:
            u = np.asarray(sol.col_value[:n2], dtype=float)
            if s.offer_u(u, self.name):
                return
            cert = p.exact.floppy(u, s.resolution)
            if cert.violation <= self.polish_relative * max(cert.size, 1.0):
                x = s.refiner.polished(s, u)
                if x is not None and s.offer_u(x, self.name):
                    return
        if h.getModelStatus() == highspy.HighsModelStatus.kInfeasible:
            *_, has_ray, ray = h.getDualRay()  # type: ignore[attr-defined]
            if has_ray:
                s.offer_t(-np.asarray(ray, dtype=float)[:m], self.name)


#: The default strategies of the verdict search, in order.
DEFAULT_STRATEGIES = (Affine(), Newton(), Refine(), InteriorPoint(), Support(), LinearProgram())
#: Every strategy by name, the default ones and the opt-in ones.
STRATEGIES = {x.name: x for x in (*DEFAULT_STRATEGIES, SmallestDisplacement())}


def search(
    p: Problem,
    resolution: Resolution,
    strategies,
    start: np.ndarray | None = None,
    start_tensions: np.ndarray | None = None,
    refiner: Refiner | None = None,
    polish: bool = True,
    balance: bool = True,
) -> Search:
    """Run ``strategies`` (objects with a ``name`` and ``run(search)``) in order until a certificate
    is accepted, after the starting points ``start`` ((2N,), units of ``max |e0|``; offered and
    crossed over) and ``start_tensions`` ((m,), offered). ``refiner`` (default ``Refiner()``) cleans
    the candidates, polishing and balancing where ``polish``, ``balance``; the final
    :class:`Search`."""
    s = Search(p, resolution, Refiner() if refiner is None else refiner, polish, balance)
    if not np.any(p.e0):  # nothing is strained: u = 0 is exact
        s.offer_u(np.zeros(p.n2), "trivial")
    if start_tensions is not None and not s.decided:
        s.offer_t(start_tensions, "hint")
    if start is not None and not s.decided:
        start = np.asarray(start, dtype=float).ravel()
        if not s.offer_u(start, "hint"):
            s.crossovers(start, "hint", taus=p.tol.hint_crossover_taus)
    for strategy in strategies:
        if s.decided:
            break
        strategy.run(s)
    return s
