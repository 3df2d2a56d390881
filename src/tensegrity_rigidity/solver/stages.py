"""The verdict search: stages that propose points, one search state that checks them.

A verdict is a certificate accepted by the resolution model of :mod:`.certificates`; nothing
else decides. The stages only propose candidates:

* displacements ``u`` (floppy candidates, checked as they are and, when they fail by a
  violation of at most ``1e-6``, once more after :class:`Polish` moved them onto their tight
  set in extended precision);
* tensions ``t`` (rigid candidates, first moved onto an exact self-stress by
  :func:`~.selfstress.purify` and, when that stalls with real work left, once more by
  :class:`Balance`).

:class:`Search` holds what all stages share: the problem, the lowest-energy point so far and
the best candidate of each kind. Stages run in the order given by
``SolverOptions.stages`` until one candidate is accepted. Each stage is a small object with a
``name`` and a ``run(search)`` method and can be run on its own (the tests do). Every limit is
a count of iterations or factorisations, never a time: the verdict is a function of the
instance and the options only.

Stages (``STAGES``; the default order is :data:`DEFAULT_STAGES`):

``affine``
    The tensions of the affine deformation, purified: deeply rigid samples end here.
``newton``
    Semismooth Newton on the energy with exact line search, from the origin (or a warm start).
    Away from the transition samples end here in 4 to 10 factorisations.
``crossover``
    The energy minimised exactly on a guessed near-tight set from the lowest-energy point,
    corrected by KKT signs (:func:`~.newton.crossover`).
``ipm``
    The specialised interior point of :mod:`.ipm`; at accuracies 1e-3, 1e-5 and 1e-7 and at
    its end its tensions are purified and its displacements crossed over.
``project`` (not in the default order)
    The projection of the best floppy candidate so far onto the zero-energy displacements
    (the minimum-norm interior point of :mod:`.displacements` with ``t* = 0``). Near the
    threshold the zero-energy displacements reach ``1e6`` times the strain; the energy's
    minimisers drift along the floppy modes, and their crossovers leave violations of
    ``1e-3`` to ``0.4`` there (n = 64), while the projection, whose Newton systems stay well
    conditioned, reaches the zero-energy set to ``1e-10``. Opt-in: on the near-threshold set
    it narrowed one threshold interval of six at n = 64 and made the searches 64 % slower
    before ``lp`` (``benchmarks/bench_stages.py``).
``refine``
    The minimum-norm displacements that zero the extensions of the rods and of the engaged
    one-sided elements, by a proximal iteration with extrapolation on one factorisation, its
    residuals in extended precision. Near a rods-only threshold the energy's minimisers reach
    ``1e6`` to ``1e8`` times the strain and their violations stall at ``1e-9``, the size times
    double-precision round-off; the minimum-norm solution is often ``1e3`` times smaller and
    is resolved to ``1e-10``. On a rigid sample the residual converges to the least-squares
    self-stress, a rigid candidate.
``lp``
    The verdict LP over self-stresses with ``|t_b| <= 1`` (HiGHS's interior point with an
    iteration limit, its crossover and one round of LP iterative refinement); its primal is
    purified, its dual displacements are checked and crossed over (the interior point's, when
    the crossover's clean-up runs out of iterations). Then the feasibility LP for a zero-energy
    displacement by the dual simplex: a vertex is offered as a floppy candidate, a proof of
    infeasibility (a dual ray: an admissible self-stress with positive work, by Farkas' lemma)
    as a rigid one.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from .certificates import FloppyCertificate, Resolution, RigidCertificate
from .displacements import min_norm_minimizer
from .ipm import IpmState, interior_point
from .newton import CROSSOVER_TAUS, crossover, newton
from .problem import Problem
from .selfstress import kept, purify, rebalance

#: Relative sizes below which approximate tensions are dropped before purification, tried in
#: turn: an interior point resolves its tensions to about its accuracy, and elements it
#: leaves at that level usually belong to no self-stress. A tolerance that drops the same
#: entries as the one before is skipped (:func:`~.selfstress.kept`): purification would return
#: the same tensions. That is the case for most affine tensions (no entry between 1e-9 and
#: 1e-6 of the largest), where it halves the purifications of a floppy sample's first stage.
SUPPORT_TOLS = (1e-6, 1e-9)


@dataclass
class Search:
    """State shared by the stages of one verdict search (normalised units of the problem).

    Attributes
    ----------
    p : Problem
        The problem (unit stiffness for the verdict).
    resolution : Resolution
        Tolerances of the certificates.
    u, E : (2N,) float, float
        The lowest-energy point offered so far and its energy.
    floppy : FloppyCertificate or None
        The accepted floppy certificate, else the candidate with the smallest violation among
        those within the displacement bound (or the smallest overall).
    rigid : RigidCertificate or None
        The accepted rigid certificate, else the candidate with the largest margin
        ``work - U residual``.
    stage : str
        The stage whose candidate was accepted ("" while undecided).
    iterations : int
        Newton iterations spent.
    polish : Polish or None
        How floppy candidates that narrowly fail are polished before they are kept (None:
        never; :func:`search` uses :data:`POLISH`).
    polished : int
        Candidates polished so far.
    balance : Balance or None
        How rigid candidates that narrowly fail are balanced after purification (None:
        never; :func:`search` uses :data:`BALANCE`).
    balanced : int
        Candidates balanced so far.
    ipm_end : IpmState or None
        Where the ``ipm`` stage's interior point ended (:class:`~.ipm.IpmState`), for the
        relaxation of :func:`~tensegrity_rigidity.solver.core.solve` to go on from.
    """

    p: Problem
    resolution: Resolution
    u: np.ndarray = field(default_factory=lambda: np.zeros(0))
    E: float = np.inf
    floppy: FloppyCertificate | None = None
    rigid: RigidCertificate | None = None
    stage: str = ""
    iterations: int = 0
    polish: Polish | None = None
    polished: int = 0
    balance: Balance | None = None
    balanced: int = 0
    ipm_end: IpmState | None = None

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
        """Offer displacements as a floppy candidate (and as the lowest-energy point).

        Parameters
        ----------
        u : (2N,) float or longdouble
            Displacements (units of ``max |e0|``); the certificate keeps extended precision.
        stage : str
            The stage offering them.
        E : float, optional
            Their energy, if known.

        Returns
        -------
        bool
            True once the search is decided.

        A candidate within the displacement bound that fails with a violation of at most
        ``polish.below`` is polished (:class:`Polish`) and the result checked too.
        """
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
        res, polish = self.resolution, self.polish
        if (
            polish is not None
            and not cert.accepted
            and cert.violation <= polish.below
            and cert.size <= res.displacement
            and self.polished < polish.attempts
        ):
            self.polished += 1
            x = polish(self, exact)
            if x is not None:
                self._offer_floppy(self.p.exact.floppy(x, res), stage)
        return self.decided

    def _offer_floppy(self, cert: FloppyCertificate, stage: str) -> FloppyCertificate:
        """Keep ``cert`` if it is the best floppy candidate so far; decide if it is accepted."""
        if self.floppy is None or _floppy_key(cert) < _floppy_key(self.floppy):
            self.floppy = cert
        if cert.accepted:
            self.stage = stage
        return cert

    def offer_t(self, t: np.ndarray, stage: str, as_is: bool = False) -> bool:
        """Offer approximate tensions as a rigid candidate, purified first.

        Parameters
        ----------
        t : (m,) float or longdouble
            Approximate tensions on the non-empty sites.
        stage : str
            The stage offering them.
        as_is : bool
            Check ``t`` itself first (in its own precision; wrong signs are rejected), and
            purify only when that fails: for tensions already balanced to extended
            round-off, which purification could only coarsen.

        Returns
        -------
        bool
            True once the search is decided.
        """
        if self.decided:
            return True
        if as_is and self._offer_rigid(self.p.exact.rigid(t, self.resolution), stage):
            return True
        t = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(t)) or not np.any(t):
            return False
        best = None
        previous = None
        for support_tol in SUPPORT_TOLS:
            support = kept(t, support_tol)
            if previous is not None and np.array_equal(support, previous):
                continue  # purify's input, and so its result, as at the last tolerance
            previous = support
            try:
                tp = purify(
                    self.p, t, support_tol=support_tol, work_floor=self.resolution.violation
                )
            except ArithmeticError:
                continue
            cert = self.p.exact.rigid(tp, self.resolution)
            if self._offer_rigid(cert, stage):
                return True
            if best is None or _rigid_key(cert, self.resolution) > _rigid_key(
                best, self.resolution
            ):
                best = cert
        res, balance = self.resolution, self.balance
        if (
            balance is not None
            and best is not None
            and self.balanced < balance.attempts
            and balance.takes(best, res)
        ):
            self.balanced += 1
            x = balance(self, best.t)
            if x is not None:
                self._offer_rigid(self.p.exact.rigid(x, res), stage)
        return self.decided

    def _offer_rigid(self, cert: RigidCertificate, stage: str) -> bool:
        """Keep ``cert`` if it is the best rigid candidate so far; True if it is accepted."""
        if self.rigid is None or _rigid_key(cert, self.resolution) > _rigid_key(
            self.rigid, self.resolution
        ):
            self.rigid = cert
        if cert.accepted:
            self.stage = stage
        return cert.accepted

    def offer_point(self, u: np.ndarray, stage: str) -> bool:
        """Offer displacements ``u`` (2N,) and the tensions of the energy at them; True
        once the search is decided."""
        e, _, t = self.p.state(u)
        E = 0.5 * float(np.dot(t, e))
        return self.offer_u(u, stage, E) or (E > 0 and self.offer_t(t, stage))

    def crossovers(self, u: np.ndarray, stage: str, taus=CROSSOVER_TAUS) -> bool:
        """Crossovers (:func:`~.newton.crossover`) from ``u`` (2N,) with the near-tight set
        guessed at the widening thresholds ``taus``; True once the search is decided."""
        for tau in taus:
            x = crossover(self.p, u, tau=tau)
            if x is not None and self.offer_point(x, stage):
                return True
        return False


def _floppy_key(c: FloppyCertificate, bound: float = np.inf) -> tuple:
    return (not c.accepted, c.size > bound, c.violation)


def _rigid_key(c: RigidCertificate, res: Resolution) -> float:
    return c.work - res.displacement * c.residual


# --------------------------------------------------------------------------- stages


@dataclass(frozen=True)
class Affine:
    """The tensions of the affine deformation, purified: decides deeply rigid samples in a
    few factorisations."""

    name: str = "affine"

    def run(self, s: Search) -> None:
        s.offer_point(np.zeros(s.p.n2), self.name)


@dataclass(frozen=True)
class Newton:
    """Semismooth Newton from the search's point (see :func:`~.newton.newton`)."""

    max_iter: int = 15
    max_truncated: int = 4
    name: str = "newton"

    def run(self, s: Search) -> None:
        # stop once the energy alone would allow a violation well below tau
        floor = 0.5 * (0.1 * s.resolution.violation) ** 2
        u, E, it = newton(s.p, s.u, self.max_iter, self.max_truncated, floor)
        s.iterations += it
        s.offer_point(u, self.name)


@dataclass(frozen=True)
class Crossover:
    """Crossovers from the lowest-energy point so far."""

    taus: tuple[float, ...] = (1e-7, 1e-5, 1e-3)
    name: str = "crossover"

    def run(self, s: Search) -> None:
        s.crossovers(s.u, self.name, self.taus)


@dataclass(frozen=True)
class InteriorPoint:
    """The energy interior point with purification and crossovers on the way.

    At each checkpoint accuracy the multipliers are purified into a self-stress and the
    displacements get the tightest crossover guess; at the end all three guesses.
    """

    checkpoints: tuple[float, ...] = (1e-3, 1e-5, 1e-7)
    tol: float = 1e-9
    max_iter: int = 60
    name: str = "ipm"

    def run(self, s: Search) -> None:
        def tensions(u, lam):
            e = s.p.e0 + s.p.R @ u
            t = s.p.k * e
            t[s.p.one_sided] = s.p.sigma[s.p.one_sided] * lam
            return t

        def on_checkpoint(u, lam):
            return (
                s.offer_u(u, self.name)
                or s.offer_t(tensions(u, lam), self.name)
                or s.crossovers(u, self.name, taus=(1e-7,))
            )

        end: list[IpmState] = []
        u, _, lam, _ = interior_point(
            s.p,
            max_iter=self.max_iter,
            tol=self.tol,
            checkpoints=self.checkpoints,
            callback=on_checkpoint,
            record=end,
        )
        s.ipm_end = end[0]
        if not s.decided:
            s.offer_u(u, self.name)
        if not s.decided:
            s.offer_t(tensions(u, lam), self.name)
        if not s.decided:
            s.crossovers(u, self.name)


@dataclass(frozen=True)
class Projection:
    """The zero-energy displacements nearest to the origin, from the best floppy candidate.

    Runs the projection interior point of :func:`~.displacements.min_norm_minimizer` with
    zero tensions (rods unstretched, one-sided elements slack or unstrained) for at most
    ``max_iter`` iterations, started at the best floppy candidate so far (else the
    lowest-energy point), and offers its end point. The identity block of its Newton systems
    keeps them well conditioned however near-floppy the network is, so it reaches the
    zero-energy set where the energy's minimisers, drifting along floppy modes, are too large
    to be resolved. On a rigid sample the set is empty: the steps shrink, the iteration stops
    after ``stall`` short steps in a row, and the certificate rejects the iterate.

    Attributes
    ----------
    max_iter : int
        Most interior-point iterations (each one sparse LDL^T factorisation).
    stall : int
        Consecutive steps shorter than 1e-2 after which it stops (``min_norm_minimizer``).
    name : str
        The stage's name in ``SolverOptions.stages``.
    """

    max_iter: int = 150
    stall: int = 20
    name: str = "project"

    def run(self, s: Search) -> None:
        start = np.asarray(s.floppy.u, dtype=float) if s.floppy is not None else s.u
        zero = np.zeros(s.p.sites.size)
        mn = min_norm_minimizer(s.p, zero, start, max_iterations=self.max_iter, stall=self.stall)
        s.offer_u(mn.u, self.name)


@dataclass(frozen=True)
class Refine:
    """The minimum-norm zero-violation displacements on a fixed engaged set: a proximal
    iteration accelerated by extrapolation, with residuals in extended precision.

    Near the threshold the energy's minimisers drift along floppy modes to ``1e6``-``1e8``
    times the strain, and their violations stall at ``1e-9`` to ``1e-8``, the size of ``u``
    times the double-precision round-off. The displacements that matter are far smaller. On
    the engaged set ``A`` (rods and the one-sided elements engaged at the lowest-energy point)
    this stage solves ``min |u|`` subject to ``e0_A + R_A u = 0`` from the proximal (iterated
    Tikhonov) step

        u <- u - (R_A^T R_A + mu I)^{-1} R_A^T (e0_A + R_A u),    u_0 = 0,

    which stays in the row space of ``R_A`` and converges to the minimum-norm solution when
    the system is consistent; each singular direction shrinks by ``mu / (s^2 + mu)`` per
    step, too slowly for the few with ``s^2 << mu``. Every ``window`` steps the iterate is
    replaced by the affine combination of the last ``window + 1`` iterates whose residual is
    least (reduced rank extrapolation: the residual is affine in ``u``, so it is exactly the
    same combination of their residuals), which removes those few slow directions. The
    residuals and forces are evaluated in extended precision on the certificates' geometry and
    ``u`` is accumulated in it, so the violation falls to ``~1e-13`` where double precision
    stalls at ``1e-9``. One factorisation per round; a round ends when the violation on ``A``
    is below ``tau / 10``, when ``patience`` extrapolations in a row fail to halve it (a rigid
    sample: the residual converges to the least-squares self-stress), or after ``max_iter``
    steps.

    The end point is offered as a floppy candidate (checked on every element); if the round
    did not converge its residual, a self-stress up to round-off, is offered as a rigid one.
    One-sided elements outside ``A`` that the end point violates join ``A`` for the next round.

    Measured (``benchmarks/bench_stages.py --rods-only``, BENCHMARKS.md): on rods-only
    thresholds at n = 64 it decides every probe the energy stages left undecided (20 of 207),
    and the median search falls from 5.5 to 1.4 s; on the mixed near-threshold set it decides
    almost nothing and costs 0 to 5 %. The solves add components along exact mechanisms of
    relative size ``~eps / mu`` (2e-3 at the default shift), which change neither the
    extensions nor the verdict.

    Attributes
    ----------
    shifts : tuple of float
        ``mu`` relative to the unit stiffness, tried in turn until a factorisation succeeds
        (the matrix is singular on floppy networks; smaller converges faster).
    window : int
        Steps between extrapolations.
    patience : int
        Extrapolations in a row that may fail to halve the least violation so far before the
        round stops (the violation often falls in alternating large and small steps).
    max_iter : int
        Most steps per round (each one back-substitution).
    rounds : int
        Most rounds (engaged sets).
    name : str
        The stage's name in ``SolverOptions.stages``.
    """

    shifts: tuple[float, ...] = (1e-13, 1e-11, 1e-9)
    window: int = 8
    patience: int = 2
    max_iter: int = 200
    rounds: int = 3
    name: str = "refine"

    def run(self, s: Search) -> None:
        p = s.p
        e = p.e0 + p.R @ s.u
        active = p.rod | (p.sigma * e >= 0)
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
        """Proximal steps with extrapolation on the engaged set ``active`` (m,) bool, from
        ``start`` ((2N,), default the origin); returns (u (2N,) longdouble, residual on
        ``active`` (m,) longdouble, converged)."""
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


@dataclass(frozen=True)
class Polish:
    """Floppy candidates moved onto their tight set in extended precision: the displacement
    side of purification.

    A candidate from a double-precision solver (an LP vertex, an interior point) misses its
    constraints by its size times the round-off, or by the solver's own tolerance: an LP
    vertex of size ``1e7`` by ``1e-9`` to ``1e-8``, above ``tau`` however exact the point it
    approximates. Holding the rods and the one-sided elements within ``slack`` of their bound
    at zero extension, the proximal iteration of :class:`Refine`, started from the candidate,
    converges to a nearby point of that affine set, with the residuals evaluated and ``u``
    accumulated in extended precision. One-sided elements outside the set that the end point
    violates join it for another round. The end point is checked as a floppy certificate like
    any other candidate; a polish that does not converge adds nothing.

    The slacks are tried in turn until the end point is accepted. A slack too wide holds
    elements that are slack at every zero-energy point near the candidate, and the held set
    becomes inconsistent; too narrow, and the rounds add violated elements one set at a time.
    At n = 64, configuration 3, two probes' candidates (violations ``1.6e-9`` and ``5.3e-9``,
    sizes ``6.6e4`` and ``1.2e6``) fail at ``1e-6`` (12 more struts held; the set misses by
    ``3.4e-8``) and end at ``8.4e-11`` and ``4.8e-11`` at ``1e-9``.

    Measured on the near-threshold set (``BENCHMARKS.md``): at n = 64, configuration 1,
    sample 0, event 12245, the feasibility LP's vertex (violation ``1.4e-8``, size ``9.9e6``)
    ends at ``4.5e-13`` and decides the probe, which no stage decided before; that threshold
    interval narrowed from 228 to 184 events. Only candidates within the displacement bound
    whose violation is at most ``below`` are polished, at most ``attempts`` per search (each
    costs one factorisation per round and slack and at most ``refine.max_iter``
    back-substitutions).

    Attributes
    ----------
    below : float
        Largest violation of a candidate that is polished (units of ``max |e0|``).
    slacks : tuple of float
        One-sided elements whose extension lies within the slack of their bound are held at
        it; tried in turn.
    rounds : int
        Most rounds (tight sets) per slack.
    attempts : int
        Most candidates polished per search.
    refine : Refine
        The proximal iteration's settings.
    """

    below: float = 1e-6
    slacks: tuple[float, ...] = (1e-6, 1e-9)
    rounds: int = 3
    attempts: int = 4
    refine: Refine = field(default_factory=Refine)

    def __call__(self, s: Search, u: np.ndarray) -> np.ndarray | None:
        """The polished displacements ((2N,) longdouble) of candidate ``u`` (2N,): the first
        end point that is a floppy certificate, else the first that converged, else None
        (every factorisation failed or no round converged)."""
        fallback = None
        for slack in self.slacks:
            x = self._polish(s, u, slack)
            if x is None:
                continue
            if s.p.exact.floppy(x, s.resolution).accepted:
                return x
            fallback = x if fallback is None else fallback
        return fallback

    def _polish(self, s: Search, u: np.ndarray, slack: float) -> np.ndarray | None:
        """Rounds of the proximal iteration from ``u`` holding the elements within ``slack``
        of their bound; the end point ((2N,) longdouble), or None."""
        p = s.p
        v = np.asarray(p.exact.extensions(u), dtype=float)
        active = p.rod | (p.sigma * v >= -slack)
        x = np.asarray(u, dtype=np.longdouble)
        for _ in range(self.rounds):
            solver = p.factor_shifted(active.astype(float), self.refine.shifts)
            if solver is None:
                return None
            x, _, converged = self.refine._round(s, active, solver, start=x)
            if not converged:
                return None
            v = np.asarray(p.exact.extensions(x), dtype=float)
            joined = ~active & (p.sigma * v > 0)
            if not joined.any():
                break
            active = active | joined
        return x


@dataclass(frozen=True)
class Balance:
    """Rigid candidates balanced to extended round-off when purification stalls: the self-stress
    side's counterpart of :class:`Polish`.

    Purification stops where the candidate's support has near-mechanisms: the remaining force
    residual lies along directions that its regularisation damps, and removing it would flip
    a few small one-sided tensions. Then a self-stress with real work (``1e-2`` of its size)
    can keep a residual of ``4e-9`` of its size, which ``U = 1e7`` forgave
    (``w > tau + U r``) and ``U = 1e8`` does not. :func:`~.selfstress.rebalance` continues
    with a smaller regularisation and an active set: corrections cut at the first one-sided
    tension they would take through zero, which is then fixed at zero. Measured on n = 64,
    configuration 2 of the near-threshold set, sample 0, event 12585 (``BENCHMARKS.md``): the
    interior point's purified tensions (work 0.043, residual 4.1e-9) end at residual 1.9e-11
    after 18 factorisations (0.1 s).

    Only candidates whose work exceeds ``tau`` and whose residual is at most ``below`` (both
    relative to ``|t|_1``) and needs to shrink by at most ``reduction`` to certify are
    balanced, at most ``attempts`` per search: a count, not a time.

    Attributes
    ----------
    below : float
        Largest relative force residual of a candidate that is balanced.
    reduction : float
        Largest factor by which balancing is asked to reduce a candidate's residual ``r``:
        it is balanced only when ``U r <= reduction (w - tau)``. On issue 13's threshold
        searches (scratch, 2026-11-28) the candidates later accepted needed a reduction of
        at most ``2.3e4`` (n = 32, 12 samples per configuration: 70 of 526 balanced) and
        ``222`` (n = 64, one sample per configuration: 4 of 129); none of those needing more
        than ``1e5`` was accepted, and they took 4.9 of the 13.5 s spent balancing at n = 32
        and 15.1 of 20.5 s at n = 64. Paired on the whole searches: the same thresholds and
        intervals, n = 32 in 150.1 s against 157.8 s (72 thresholds), n = 64 in 475 s
        against 498 s (6).
    attempts : int
        Most candidates balanced per search.
    steps : int
        Most corrections per candidate (each at most one factorisation).
    """

    below: float = 1e-6
    reduction: float = 1e5
    attempts: int = 4
    steps: int = 20

    def takes(self, cert: RigidCertificate, res: Resolution) -> bool:
        """Whether a rejected candidate ``cert`` is worth balancing at resolution ``res``:
        work above ``tau``, residual at most ``below``, and ``U r <= reduction (w - tau)``."""
        margin = float(cert.work) - res.violation
        return (
            margin > 0
            and cert.residual <= self.below
            and res.displacement * cert.residual <= self.reduction * margin
        )

    def __call__(self, s: Search, t: np.ndarray) -> np.ndarray | None:
        """The balanced tensions ((m,) longdouble) of candidate ``t`` (m,), or None."""
        return rebalance(s.p, t, steps=self.steps)


def _extrapolate(us, rs, residual):
    """The affine combination of iterates ``us`` (each (2N,)) whose residual, the same
    combination of ``rs`` (each (m,)), has the least 2-norm; returns (u, r, max |r|)."""
    last_u, last_r = us[-1], rs[-1]
    D = np.array([np.asarray(x - last_r, dtype=float) for x in rs[:-1]]).T
    c = np.linalg.lstsq(D, -np.asarray(last_r, dtype=float), rcond=None)[0]
    u = last_u + sum(ci * (ui - last_u) for ci, ui in zip(c, us[:-1], strict=True))
    r, viol = residual(u)
    return u, r, viol


@dataclass(frozen=True)
class LinearProgram:
    """Linear programs of Farkas' lemma, solved by HiGHS with iteration limits.

    First the verdict LP ``max e0 . t`` over self-stresses with ``|t_b| <= 1``: HiGHS's
    interior point (one thread, at most ``max_iter`` iterations), followed by its crossover to
    a vertex when ``refine`` is set. Its tensions are purified and offered, its dual
    displacements offered and crossed over. When the simplex clean-up after the crossover hits
    its iteration limit, HiGHS returns no solution at all; the LP is then solved again without
    the crossover and the interior point's solution offered instead (``interior_fallback``).

    Near the threshold the vertex is not yet a certificate: HiGHS accepts a basis whose
    variables miss their bounds by up to its feasibility tolerance (``1e-7``), and at n = 64
    about 200 cable tensions of such a vertex sit at ``-6e-8``. They cannot simply be zeroed:
    the forces they carry are balanced only by other elements of the basis. So the vertex is
    refined as in LP iterative refinement (Gleixner, Steffy & Wolter, INFORMS J. Comput. 28,
    449 (2016)): with ``d`` the largest force residual (in extended precision) or bound
    violation of the tensions ``t``, the correction LP

        max e0 . x   s.t.   R^T x = -R^T t / d,   (lo - t) / d <= x <= (hi - t) / d

    (the same LP, shifted to ``t`` and magnified by ``1 / d``) is solved by the primal simplex
    warm-started from the vertex's basis, and ``t + d x`` (accumulated in extended precision)
    misses its bounds and balances the nodes to about ``1e-7 d``. Each of the ``refine``
    rounds gains that factor; its tensions, with the wrong-signed ones (``~1e-15`` after one
    round) set to zero, are offered as they are, its duals as displacements.

    Then, if nothing was accepted and the problem has at most ``feasibility_sites_max``
    non-empty sites, the feasibility LP for a zero-energy displacement by the dual simplex,
    and by the primal when the dual stops with status "Unknown" (``feasibility_simplex``;
    each at most ``simplex_iterations_per_site`` iterations per non-empty site and at most
    ``simplex_iterations_max``, :func:`_feasibility_lp`): a vertex satisfies its rows to
    HiGHS's tolerance and is checked as it is; when the simplex proves the LP infeasible
    instead, its dual ray is an admissible self-stress with positive work (Farkas' lemma),
    purified and offered as a rigid candidate. A HiGHS failure leaves the search as it was.

    Attributes
    ----------
    max_iter : int
        Interior-point iterations of the verdict LP.
    simplex_iterations_per_site : float
        Simplex iterations per non-empty site of the feasibility LP (0: the feasibility LP
        is not run).
    simplex_iterations_max : int
        Most simplex iterations of the feasibility LP, whatever the size. A simplex
        iteration costs about ``n^2`` (0.17 ms at n = 32, 0.45 ms at n = 64, 2 ms at
        n = 128), so a budget per site alone grows as ``n^4``. Measured on the near-threshold
        set (BENCHMARKS.md), every run that decided took at most 1.07 iterations per site
        (at most about 10,000 iterations: 5 of 8 runs at n = 32, 6 of 36 at n = 64), and at
        n = 128 none of 4 runs decided within its 78,000 to 80,000 (130 to 155 s each). The
        default, 25,000, is above ``2 * 3 n^2`` for every n <= 64, so it changes nothing
        there.
    refine : int
        Refinement rounds of the verdict LP's vertex (0: no crossover, no refinement).
    refine_iterations_per_site : float
        Simplex iterations per non-empty site of each refinement round, and of the simplex
        HiGHS runs after the verdict LP's interior point to clean up an imprecise solution or a
        non-optimal crossover basis (without a limit that ran for minutes on near-threshold
        probes at n = 64).
    interior_fallback : bool
        When that clean-up hits its limit, HiGHS returns no solution at all, not even its
        interior point: solve the verdict LP again without the crossover and offer the interior
        point's tensions and dual displacements instead (the clean-up hit its limit on every
        undecided probe of configuration 2 of the near-threshold set at n = 64).
    feasibility_simplex : str
        How HiGHS solves the feasibility LP: ``"dual"`` (its dual simplex), ``"primal"``, or
        ``"dual+primal"`` (the default): the dual simplex, then the primal simplex when the
        dual stops with neither a vertex nor a proof of infeasibility before its iteration
        limit (status "Unknown"), each with the full budget. On one n = 64 probe the dual ends
        "Unknown" after 8,402 iterations and 41.5 s where the primal proves infeasibility in
        18,924 iterations and 5.7 s. Over the near-threshold set (``BENCHMARKS.md``) the primal
        alone loses floppy vertices the dual finds (n = 64 intervals 278 events against 247),
        while ``"dual+primal"`` narrows one n = 64 interval from 37 to 6 events and leaves the
        others and every n = 32 bracket as the dual leaves them (n = 64: 477 s against 480 s).
    feasibility_sites_max : int
        Above this many non-empty sites the feasibility LP is not run. At n = 128 (49,152
        sites on a full triangular lattice) it decided none of the near-threshold probes it
        ran on (BENCHMARKS.md: 15 runs at the 25,000-iteration cap on configurations 1 and 4,
        28 to 55 s each, and 4 earlier runs at 2 iterations per site), while at n = 64
        (12,288 sites) it decides about a quarter of its runs. The default, 24,576 (two n = 64
        lattices), lies between the sizes measured; nothing between them was.
    name : str
        The stage's name in ``SolverOptions.stages``.
    """

    max_iter: int = 100
    simplex_iterations_per_site: float = 2.0
    simplex_iterations_max: int = 25_000
    refine: int = 1
    refine_iterations_per_site: float = 0.25
    interior_fallback: bool = True
    feasibility_simplex: str = "dual+primal"
    feasibility_sites_max: int = 24_576
    name: str = "lp"

    def __post_init__(self):
        if self.feasibility_simplex not in FEASIBILITY_SIMPLEX:
            raise InputError(
                "LinearProgram.feasibility_simplex must be one of "
                f"{', '.join(map(repr, FEASIBILITY_SIMPLEX))}, got {self.feasibility_simplex!r}"
            )

    def verdict_lp(self, p: Problem, crossover: bool | None = None):
        """The verdict LP ``max e0 . t`` over self-stresses with admissible ``|t_b| <= 1``,
        solved as the stage solves it.

        Parameters
        ----------
        p : Problem
            The problem (normalised units).
        crossover : bool, optional
            Run HiGHS's crossover after the interior point (default: when ``refine`` is set).

        Returns
        -------
        h : highspy.Highs
            The solved model (columns: the tensions (m,); rows: the nodes' forces (2N,)).
        A : sparse (2N, m), CSC
            ``R^T``, its constraint matrix.
        lo, hi : (m,) float
            The tensions' bounds.
        """
        A = p.RT.tocsc()
        lo = np.where(p.sigma > 0, 0.0, -1.0)
        hi = np.where(p.sigma < 0, 0.0, 1.0)
        zeros = np.zeros(A.shape[0])
        h = _highs(
            A,
            -p.e0,
            lo,
            hi,
            zeros,
            zeros,
            solver="ipm",
            run_crossover="on" if (self.refine if crossover is None else crossover) else "off",
            ipm_iteration_limit=self.max_iter,
            simplex_iteration_limit=self._refine_budget(p),
        )
        return h, A, lo, hi

    def run(self, s: Search) -> None:
        p = s.p
        h, A, lo, hi = self.verdict_lp(p)
        sol = h.getSolution()
        if not sol.value_valid and self.refine and self.interior_fallback:
            # the crossover or its clean-up simplex hit its limit, and HiGHS dropped the
            # interior point with it: solve again without the crossover
            sol = self.verdict_lp(p, crossover=False)[0].getSolution()
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
        vertex, ray = _feasibility_lp(p, max_iter, self.feasibility_simplex)
        if vertex is not None and not s.offer_u(vertex, self.name):
            s.crossovers(vertex, self.name)
        if ray is not None:
            s.offer_t(ray, self.name)

    def _feasibility_budget(self, p: Problem) -> int:
        """Simplex iterations of the feasibility LP (0 above ``feasibility_sites_max``
        sites)."""
        if p.sites.size > self.feasibility_sites_max:
            return 0
        per_site = int(self.simplex_iterations_per_site * p.sites.size)
        return min(per_site, self.simplex_iterations_max)

    def _refine_budget(self, p: Problem) -> int:
        """Simplex iterations of the clean-up after the interior point and of each
        refinement round."""
        return int(self.refine_iterations_per_site * p.sites.size)

    def _refine(self, s: Search, h, A, lo, hi) -> bool:
        """``refine`` rounds of LP iterative refinement from the vertex of the solved verdict
        LP ``h``, each result offered; True once the search is decided."""
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


def _highs(A, cost, col_lower, col_upper, row_lower, row_upper, basis=None, **options):
    """HiGHS on ``min cost . x`` s.t. ``row_lower <= A x <= row_upper``, ``col_lower <= x <=
    col_upper`` (``A`` CSC), one thread, silent, with ``options`` and an optional starting
    basis; returns the solved ``highspy.Highs``."""
    import highspy

    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = A.shape[1], A.shape[0]
    lp.col_cost_ = cost
    lp.col_lower_, lp.col_upper_ = col_lower, col_upper
    lp.row_lower_, lp.row_upper_ = row_lower, row_upper
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_, lp.a_matrix_.index_, lp.a_matrix_.value_ = A.indptr, A.indices, A.data
    h = highspy.Highs()
    for key, value in {"output_flag": False, "threads": 1, **options}.items():
        h.setOptionValue(key, value)
    h.passModel(lp)
    if basis is not None:
        h.setBasis(basis)
    h.run()
    return h


def _refinement(p: Problem, A, lo, hi, t: np.ndarray, basis, max_iter: int):
    """One round of LP iterative refinement of the verdict LP at tensions ``t`` ((m,)
    longdouble), warm-started from ``basis`` (:class:`LinearProgram`).

    Returns (refined tensions (m,) longdouble, the correction LP's row duals (2N,) float as
    displacements, its basis), or None when ``t`` is already exact or the primal simplex did
    not reach an optimum within ``max_iter`` iterations.
    """
    import highspy

    f = p.exact.forces(t)
    d = max(
        float(np.abs(f).max(initial=0.0)),
        float(np.max(lo - t, initial=0.0)),
        float(np.max(t - hi, initial=0.0)),
    )
    if not (np.isfinite(d) and d > 0):
        return None
    rows = np.asarray(-f / d, dtype=float)
    h = _highs(
        A,
        -p.e0,
        np.asarray((lo - t) / d, dtype=float),
        np.asarray((hi - t) / d, dtype=float),
        rows,
        rows,
        basis=basis,
        solver="simplex",
        simplex_strategy=4,  # primal: the basis stays dual feasible, its values do not
        simplex_iteration_limit=max_iter,
    )
    if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
        return None
    sol = h.getSolution()
    x = np.asarray(sol.col_value, dtype=np.longdouble)
    return t + d * x, np.asarray(sol.row_dual, dtype=float), h.getBasis()


#: The values of ``LinearProgram.feasibility_simplex``: HiGHS's simplex variants, tried in turn
#: (the next one only after status "Unknown").
FEASIBILITY_SIMPLEX = {"dual": ("dual",), "primal": ("primal",), "dual+primal": ("dual", "primal")}


def _feasibility_lp(
    p: Problem, max_iter: int, simplex: str = "dual"
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The feasibility LP ``{u : e0 + R u admissible}`` by HiGHS's simplex.

    Rows in site order: rods ``R u = -e0``, cables ``R u <= -e0``, struts ``R u >= -e0``; the
    columns are free. One thread.

    Parameters
    ----------
    p : Problem
        The problem (normalised units).
    max_iter : int
        Most simplex iterations of each variant run.
    simplex : str
        A key of :data:`FEASIBILITY_SIMPLEX`: the variants tried in turn, each after the last
        one stopped with status "Unknown" (neither an answer nor its iteration limit).

    Returns
    -------
    vertex : (2N,) float or None
        A vertex, when HiGHS finds the LP feasible.
    ray : (m,) float or None
        When HiGHS proves it infeasible: minus its dual ray ``y`` (Farkas' lemma: row
        multipliers with ``R^T y = 0`` whose bounds cannot be met; ``y <= 0`` on rows at their
        upper bound, ``>= 0`` at their lower one), tensions with ``R^T t = 0`` up to
        round-off, ``t >= 0`` on cables, ``<= 0`` on struts and ``t . e0 > 0``: a rigid
        candidate. Nothing is trusted: the caller purifies it and the certificate checks its
        signs, work and residual.
    """
    import highspy

    A = p.R.tocsc()
    inf = highspy.kHighsInf
    for variant in FEASIBILITY_SIMPLEX[simplex]:
        h = _highs(
            A,
            np.zeros(A.shape[1]),
            np.full(A.shape[1], -inf),
            np.full(A.shape[1], inf),
            np.where(p.sigma > 0, -inf, -p.e0),
            np.where(p.sigma < 0, inf, -p.e0),
            solver="simplex",
            simplex_iteration_limit=max_iter,
            primal_feasibility_tolerance=1e-9,
            simplex_strategy=4 if variant == "primal" else 1,
        )
        status = h.getModelStatus()
        if status == highspy.HighsModelStatus.kOptimal:
            return np.asarray(h.getSolution().col_value, dtype=float), None
        if status == highspy.HighsModelStatus.kInfeasible:
            # (status, has_ray, values); a method of the compiled base class that highspy's
            # type stubs leave out
            *_, has_ray, ray = h.getDualRay()  # type: ignore[attr-defined]
            return (None, -np.asarray(ray, dtype=float)) if has_ray else (None, None)
        if status != highspy.HighsModelStatus.kUnknown:
            break  # the budget is spent (or HiGHS failed otherwise): no second variant
    return None, None


#: The stages by name, for ``SolverOptions.stages``.
STAGES = {
    "affine": Affine(),
    "newton": Newton(),
    "crossover": Crossover(),
    "ipm": InteriorPoint(),
    "project": Projection(),
    "refine": Refine(),
    "lp": LinearProgram(),
}

#: How :func:`search` polishes floppy candidates (:class:`Polish`).
POLISH = Polish()

#: How :func:`search` balances rigid candidates (:class:`Balance`).
BALANCE = Balance()

#: The default order of the stages.
DEFAULT_STAGES = ("affine", "newton", "refine", "crossover", "ipm", "lp")


def search(
    p: Problem,
    resolution: Resolution,
    stages,
    start: np.ndarray | None = None,
    start_tensions: np.ndarray | None = None,
    polish: Polish | None = POLISH,
    balance: Balance | None = BALANCE,
) -> Search:
    """Run ``stages`` (stage objects) in order until a certificate is accepted.

    Parameters
    ----------
    p : Problem
        The problem.
    resolution : Resolution
        Tolerances of the certificates.
    stages : sequence of stages
        Objects with a ``run(search)`` method, e.g. ``STAGES[name]``.
    start : (2N,) float, optional
        Starting displacements (units of ``max |e0|``).
    start_tensions : (m,) float, optional
        Starting tensions on the non-empty sites.
    polish : Polish or None, optional
        How floppy candidates are polished (default :data:`POLISH`; None: checked only as
        they are).
    balance : Balance or None, optional
        How rigid candidates are balanced after purification (default :data:`BALANCE`;
        None: purified only).

    Returns
    -------
    Search
        The final state: the accepted certificate (or the best candidates) and the stage.

    ``start`` ((2N,), normalised units) and ``start_tensions`` ((m,), non-empty sites) are
    candidates from elsewhere (a neighbouring configuration, say): the tensions are purified
    and offered, the displacements offered, crossed over, and used as Newton's start.
    """
    s = Search(p, resolution, polish=polish, balance=balance)
    if not np.any(p.e0):  # nothing is strained: u = 0 is exact
        s.offer_u(np.zeros(p.n2), "trivial")
    if start_tensions is not None and not s.decided:
        s.offer_t(start_tensions, "hint")
    if start is not None and not s.decided:
        start = np.asarray(start, dtype=float).ravel()
        if not s.offer_u(start, "hint"):
            s.crossovers(start, "hint", taus=(1e-9, 1e-7))
    for stage in stages:
        if s.decided:
            break
        stage.run(s)
    return s
