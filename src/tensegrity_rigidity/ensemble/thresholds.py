"""Exact per-sample thresholds along monotone paths in (p_r, p_t), by certified bisection.

With the coupled site uniforms of :mod:`~tensegrity_rigidity.model.elements`, a path on which
both ``p_r`` and ``p_r + p_t`` never decrease only ever adds elements or turns one-sided
elements into rods, so a sample's rigidity is monotone along it (docs/model.md). The configuration
changes only at finitely many *events* (where ``p_r`` or ``p_r + p_t`` crosses a site's ``U``);
configuration ``i`` is the one after the first ``i`` events.

Paths (parameter ``s``):

* ``"p_r"``: ``p_r = s`` in ``[0, 1 - p_t]`` at fixed ``p_t``;
* ``"total"``: ``p_r = s`` in ``[0, T]`` with ``p_r + p_t = T`` fixed (one-sided -> rods).

The threshold ``s*`` is the event that made the sample rigid: the sample is rigid for
``p_r > s*`` and floppy for ``p_r <= s*`` (``s* = nan`` if it is floppy along the whole path).
``s* = 0`` marks a sample rigid from the start, at ``p_r = 0`` too. Hence ``P(p_r)`` is the
fraction of samples with ``s* < p_r`` or ``s* = 0`` on any grid
(:func:`~tensegrity_rigidity.analysis.binomial.rigid_at`).

Search. Each probe is a certified verdict (:func:`~tensegrity_rigidity.solver.decide`), and a
certificate says more than its own configuration:

* a rigid certificate (an admissible self-stress) stays admissible for every later
  configuration, and for every earlier one in which each element it stresses already exists
  with a compatible kind: the search jumps the upper end of the bracket to the first such
  configuration;
* a floppy certificate (a displacement) stays valid for every configuration up to the first
  event that adds a constraint it violates: the lower end jumps there.

Thresholds never drop a sample. When a probe is undecided (within resolution of the
boundary, see :mod:`tensegrity_rigidity.solver.certificates`, or not resolved by the
stages), the search goes on bisecting
on both sides of it, for the last certified floppy configuration below it and the first
certified rigid one above it, and reports the threshold as the interval of events between them
(:attr:`Threshold.s_low`, :attr:`Threshold.s_high`) with the number of undecided probes. The
search is deterministic: the same instance and options give the same probes and the same
result on every run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..combinatorics.clusters import SpanningCluster, spanning_cluster
from ..errors import InputError
from ..model.elements import check_probabilities
from ..model.limits import check_memory, stage_bytes
from ..model.network import Element, Instance, PeriodicNetwork
from ..solver.certificates import NOT_RESOLVED
from ..solver.core import SolverOptions, Verdict, decide


@dataclass(frozen=True)
class Threshold:
    """Result of a threshold search.

    Attributes
    ----------
    s : float
        Critical p_r (see module docstring); nan if never rigid on the path. Within an
        interval (``s_low < s_high``) the event in its middle.
    p_t : float
        p_t at ``s``.
    solves : int
        Certified verdicts computed (probes).
    s_low, s_high : float
        The threshold lies in ``[s_low, s_high]``: the event after the last certified floppy
        configuration and the event that made the first certified rigid one rigid. Equal to
        ``s`` when every probe was decided.
    undecided : int
        Probes that were undecided (within resolution of the boundary, or not resolved by the
        stages).
    jumps : int
        Bracket moves made by certificate transfer instead of a probe.
    not_resolved : int
        Of the undecided probes, those the search did not resolve (the others are within
        resolution: :func:`~tensegrity_rigidity.solver.certificates.undecided_reason`).
    """

    s: float
    p_t: float
    solves: int
    s_low: float = float("nan")
    s_high: float = float("nan")
    undecided: int = 0
    jumps: int = 0
    not_resolved: int = 0

    @property
    def decided(self) -> bool:
        """True when the threshold is a single event (no undecided probe left it open)."""
        return self.s_low == self.s_high or (np.isnan(self.s_low) and np.isnan(self.s_high))


class EventPath:
    """The configurations of one sample along a monotone path.

    Parameters
    ----------
    u, v : (m,) float
        The sample's site uniforms.
    path : {"p_r", "total"}
        The path (see the module docstring).
    p_t : float
        Fixed p_t (path "p_r") or the fixed total (path "total").
    f_c : float
        Cable fraction.
    """

    def __init__(self, u: np.ndarray, v: np.ndarray, path: str, p_t: float, f_c: float):
        m = u.size
        if path == "p_r":
            s_max = 1.0 - p_t
            rod_s = np.where(u <= s_max, u, np.inf)
            os_s = u - p_t  # becomes one-sided when s + p_t passes U
            os_s = np.where(
                (os_s > 0) & (os_s <= s_max), os_s, np.where(os_s <= 0, -np.inf, np.inf)
            )
        elif path == "total":
            rod_s = np.where(u < p_t, u, np.inf)
            os_s = np.where(u < p_t, -np.inf, np.inf)
        else:
            raise InputError(f"unknown threshold path {path!r}; use 'p_r' or 'total'")
        pos = np.r_[rod_s, os_s]
        kind = np.r_[np.zeros(m, int), np.ones(m, int)]
        site = np.r_[np.arange(m), np.arange(m)]
        finite = np.isfinite(pos)
        order = np.argsort(pos[finite], kind="stable")
        self.positions = pos[finite][order]  # (n_events,)
        ev_kind = kind[finite][order]
        ev_site = site[finite][order]
        self.n_events = self.positions.size
        # per site: index of the event that makes it a rod / one-sided (-1: from the start,
        # n_events: never); configuration i has applied the events 0 .. i-1
        self.rod_event = np.full(m, self.n_events)
        self.os_event = np.where(np.isneginf(os_s), -1, self.n_events)
        idx = np.arange(self.n_events)
        self.rod_event[ev_site[ev_kind == 0]] = idx[ev_kind == 0]
        self.os_event[ev_site[ev_kind == 1]] = idx[ev_kind == 1]
        self.cable = v < f_c

    def kinds(self, i: int) -> np.ndarray:
        """Element kinds of configuration ``i``.

        Parameters
        ----------
        i : int
            The configuration: the first ``i`` events applied (0 to ``n_events``).

        Returns
        -------
        (m,) int64
            :class:`~tensegrity_rigidity.model.network.Element` codes per site.
        """
        rod = self.rod_event < i
        one_sided = (self.os_event < i) & ~rod
        kinds = np.full(self.cable.size, Element.EMPTY, dtype=np.int64)
        kinds[one_sided & self.cable] = Element.CABLE
        kinds[one_sided & ~self.cable] = Element.STRUT
        kinds[rod] = Element.ROD
        return kinds

    def first_admitting(self, t: np.ndarray) -> int:
        """First configuration in which a self-stress is admissible.

        Parameters
        ----------
        t : (m,) float
            Tensions on all sites.

        Returns
        -------
        int
            The smallest ``i`` such that every site where ``t != 0`` holds, in configuration
            ``i``, a rod or the one-sided kind whose sign ``t`` has (every later configuration
            admits it too).
        """
        on = t != 0
        sign_ok = np.where(self.cable, t >= 0, t <= 0)  # the one-sided kind admits t
        first = np.where(sign_ok, np.minimum(self.os_event, self.rod_event), self.rod_event)
        return int(first[on].max(initial=-1)) + 1

    def last_admitting(self, viol_rod: np.ndarray, viol_os: np.ndarray) -> int:
        """Last configuration in which a displacement stays a floppy certificate.

        Parameters
        ----------
        viol_rod, viol_os : (m,) bool
            Whether the displacement violates a rod, respectively the site's one-sided kind,
            at each site.

        Returns
        -------
        int
            The largest ``i`` (at most ``n_events + 1``) such that in configuration ``i``,
            and so in every earlier one, no site the displacement violates holds the kind it
            violates.
        """
        bad = np.where(viol_os, np.minimum(self.os_event, self.rod_event), self.n_events + 1)
        bad = np.where(viol_rod & ~viol_os, self.rod_event, bad)
        return int(bad.min(initial=self.n_events + 1))


def check_sample(
    network, u, v, p_t, f_c, path: str = "p_r"
) -> tuple[np.ndarray, np.ndarray, float, float]:
    """Validate one sample's path arguments before anything is computed from them.

    Parameters
    ----------
    network : PeriodicNetwork
        Its number of sites ``m`` fixes the uniforms' shape.
    u, v : (m,) float
        Site uniforms: finite, in ``[0, 1)`` (what
        :func:`~tensegrity_rigidity.model.elements.site_uniforms` draws).
    p_t, f_c : float
        Fixed p_t (path "p_r") or fixed total (path "total"), and the cable fraction: each in
        ``[0, 1]``.
    path : {"p_r", "total"}
        The path.

    Returns
    -------
    u, v : (m,) float
        Float copies.
    p_t, f_c : float

    Raises
    ------
    InputError
        One sentence naming the first argument that is wrong: a uniform array of another
        length than the network's sites (more would index sites that do not exist, fewer give
        the threshold of a subset), a NaN or a value outside ``[0, 1)``.
    """
    if not isinstance(network, PeriodicNetwork):
        raise InputError(f"network must be a PeriodicNetwork, got {type(network).__name__}")
    if path not in ("p_r", "total"):
        raise InputError(f"unknown threshold path {path!r}; use 'p_r' or 'total'")
    m = network.n_sites
    arrays = []
    for name, value in (("u", u), ("v", v)):
        try:
            raw = np.asarray(value)
        except (TypeError, ValueError):
            raise InputError(f"{name} must be an array of {m} uniforms in [0, 1)") from None
        if raw.dtype.kind not in "iuf":
            raise InputError(f"{name} must hold real numbers, got dtype {raw.dtype}")
        arr = np.array(raw, dtype=float)
        if arr.shape != (m,):
            raise InputError(
                f"{name} must have shape ({m},), one uniform per site of the network, "
                f"got {arr.shape}"
            )
        bad = np.flatnonzero(~((arr >= 0.0) & (arr < 1.0)))
        if bad.size:
            raise InputError(
                f"{name} must hold uniforms in [0, 1), got {arr[bad[0]]!r} at site {bad[0]}"
            )
        arrays.append(arr)
    # p_t plays p_r + p_t on the "total" path: either way a probability
    _, p_t, f_c = check_probabilities(0.0, p_t, f_c)
    return arrays[0], arrays[1], p_t, f_c


def find_threshold(
    network: PeriodicNetwork,
    u: np.ndarray,
    v: np.ndarray,
    strain: np.ndarray,
    p_t: float,
    f_c: float,
    path: str = "p_r",
    options: SolverOptions | None = None,
    method: str = "lp",
) -> Threshold:
    """Exact critical p_r of one sample along a monotone path.

    Parameters
    ----------
    network : PeriodicNetwork
        Geometry (element kinds are ignored).
    u, v : (m,) float
        The sample's site uniforms.
    strain : (d, d) float
        Strain tensor, of the network's dimension.
    p_t : float
        Fixed p_t (path "p_r") or fixed total p_r + p_t (path "total").
    f_c : float
        Cable fraction.
    path : {"p_r", "total"}
        The path.
    options : SolverOptions, optional
        Options of every verdict (the resolution model in particular; unused by ``"pebble"``).
    method : {"lp", "pebble"}
        ``"lp"``: certified bisection (any path). ``"pebble"``: one pass of the pebble game,
        for rods-only paths (``path="p_r"``, ``p_t = 0``); ``strain`` is then taken as generic
        and ``solves`` is 0.

    Returns
    -------
    Threshold
        The threshold, its interval and the work spent.

    Raises
    ------
    InputError
        On an unknown path or method, ``"pebble"`` on a path that is not rods-only, or
        uniforms, ``p_t`` or ``f_c`` that :func:`check_sample` refuses.
    """
    u, v, p_t, f_c = check_sample(network, u, v, p_t, f_c, path)
    if method == "lp":  # (the pebble game checks its own)
        need = stage_bytes("threshold", network.n_nodes, dim=network.dim)
        check_memory(need, f"a threshold search on {network.n_nodes:,} nodes")
    if method == "pebble":
        return _pebble_threshold(network, u, v, p_t, f_c, path)
    if method != "lp":
        raise InputError(f"unknown threshold method {method!r}; use 'lp' or 'pebble'")
    opts = SolverOptions(min_norm=False) if options is None else options
    if not isinstance(opts, SolverOptions):
        raise InputError(f"options must be a SolverOptions, got {type(opts).__name__}")
    ev = EventPath(u, v, path, p_t, f_c)
    n_ev = ev.n_events
    status: dict[int, str] = {}
    not_resolved: set[int] = set()  # undecided probes the search did not resolve
    jumps = 0
    res = opts.resolution

    hints: dict[str, np.ndarray | None] = {"t": None, "u": None}

    def probe(i: int) -> str:
        if i not in status:
            kinds = ev.kinds(i)
            verdict = decide(
                Instance(network.with_kinds(kinds), strain),
                opts,
                initial_displacements=hints["u"],
                initial_tensions=hints["t"],
            )
            status[i] = verdict.status
            if verdict.reason == NOT_RESOLVED:
                not_resolved.add(i)
            _transfer(i, kinds, verdict)
        return status[i]

    lo_cert, hi_cert = [-1], [n_ev + 1]  # certified floppy / rigid bounds from transfers

    def _transfer(i: int, kinds: np.ndarray, verdict: Verdict) -> None:
        nonlocal jumps
        sites = np.flatnonzero(kinds != Element.EMPTY)
        if verdict.status == "rigid" and verdict.rigid is not None:
            t = np.zeros(kinds.size)
            t[sites] = verdict.rigid.t
            hints["t"] = t
            j = ev.first_admitting(t)
            if j < i:
                jumps += 1
            hi_cert[0] = min(hi_cert[0], j)
        elif verdict.status == "floppy" and verdict.floppy is not None:
            hints["u"] = verdict.floppy.u * verdict.scale
            vr, vo = _violated(network, strain, verdict.floppy, res, ev.cable)
            j = ev.last_admitting(vr, vo)
            if j > i:
                jumps += 1
            lo_cert[0] = max(lo_cert[0], min(j, n_ev))

    def rigid_at(i: int) -> bool | None:
        if i >= hi_cert[0]:
            return True
        if i <= lo_cert[0]:
            return False
        s = probe(i)
        if s == "undecided":
            return None
        return s == "rigid"

    def result(a: int, b: int) -> Threshold:
        """Threshold in (a, b]: a certified floppy (or -1), b certified rigid (or n_ev + 1:
        not rigid anywhere on the path, certified only if a == n_ev)."""
        undecided = sum(1 for s in status.values() if s == "undecided")
        work = (undecided, jumps, len(not_resolved))
        if b > n_ev:
            if a == n_ev:  # certified floppy at the end of the path: never rigid
                return Threshold(np.nan, np.nan, len(status), np.nan, np.nan, *work)
            s_low = float(ev.positions[a]) if a >= 0 else 0.0
            return Threshold(np.nan, np.nan, len(status), s_low, np.inf, *work)
        if b == 0:
            return Threshold(0.0, _p_t_at(0.0), len(status), 0.0, 0.0, *work)
        s_low = float(ev.positions[max(a, 0)]) if a >= 0 else 0.0
        s_high = float(ev.positions[b - 1])
        c = (a + 1 + b) // 2
        s = float(ev.positions[c - 1]) if c >= 1 else 0.0
        return Threshold(s, _p_t_at(s), len(status), s_low, s_high, *work)

    def _p_t_at(s: float) -> float:
        return p_t if path == "p_r" else p_t - s

    # the ends of the path
    top = rigid_at(n_ev)
    if top is False:
        return result(n_ev, n_ev + 1)
    bottom = rigid_at(0)
    if bottom is True:
        return result(-1, 0)
    a = 0 if bottom is False else -1  # certified floppy (or -1: unknown below)
    b = n_ev if top else n_ev + 1  # certified rigid (or beyond the path)
    a, b = _bisect(rigid_at, a, b, lo_cert, hi_cert)
    return result(a, b)


def _pebble_threshold(
    network: PeriodicNetwork, u: np.ndarray, v: np.ndarray, p_t: float, f_c: float, path: str
) -> Threshold:
    """Threshold of a rods-only path by one incremental pass of the pebble game."""
    return pebble_pass(network, u, v, p_t, f_c, path)[0]


def pebble_pass(
    network: PeriodicNetwork,
    u: np.ndarray,
    v: np.ndarray,
    p_t: float = 0.0,
    f_c: float = 0.5,
    path: str = "p_r",
) -> tuple[Threshold, SpanningCluster]:
    """Threshold of a rods-only path and its spanning rigid cluster, in one pebble-game pass.

    Parameters
    ----------
    network : PeriodicNetwork
        Geometry (element kinds are ignored).
    u, v : (m,) float
        The sample's site uniforms (rods enter in the order of ``u``: Newman-Ziff).
    p_t, f_c, path
        As :func:`find_threshold`; the path must be rods-only (``"p_r"``, ``p_t = 0``).

    Returns
    -------
    threshold : Threshold
        As ``find_threshold(..., method="pebble")``.
    cluster : SpanningCluster
        The rigid cluster of the threshold bond just after it was added, with its stressed
        sites (:func:`~tensegrity_rigidity.combinatorics.clusters.spanning_cluster`).
    """
    u, v, p_t, f_c = check_sample(network, u, v, p_t, f_c, path)
    if path != "p_r" or p_t != 0:
        raise InputError(
            "method 'pebble' follows rods-only paths: use path 'p_r' with p_t = 0 "
            f"(got path {path!r}, p_t = {p_t})"
        )
    ev = EventPath(u, v, path, p_t, f_c)
    added = np.flatnonzero(ev.rod_event < ev.n_events)
    order = added[np.argsort(ev.rod_event[added], kind="stable")]
    cluster = spanning_cluster(network, order)
    q = cluster.position
    if q < 0:
        return Threshold(np.nan, np.nan, 0, np.nan, np.nan), cluster
    s = float(ev.positions[ev.rod_event[order[q]]])
    return Threshold(s, p_t, 0, s, s), cluster


def elements_at(u: np.ndarray, s: float, p_t: float, path: str = "p_r") -> tuple[float, float]:
    """Rods and one-sided elements of the first rigid configuration of a path.

    Parameters
    ----------
    u : (m,) float
        The sample's site uniforms.
    s : float
        Its threshold (:attr:`Threshold.s`; NaN: never rigid).
    p_t, path
        As :func:`find_threshold`.

    Returns
    -------
    rods, one_sided : float
        The counts in the configuration after every event at or below ``s`` (the threshold
        event's own site included; events, not a comparison of ``u`` with ``s + p_t``, whose
        rounding can differ), NaN when ``s`` is: a threshold in bond counts, whose
        fluctuations are the geometric part of the threshold's (the rest comes from the
        binomial numbers of sites below each ``p``).
    """
    if not np.isfinite(s):
        return np.nan, np.nan
    ev = EventPath(u, np.zeros_like(u), path, p_t, 1.0)
    kinds = ev.kinds(int(np.searchsorted(ev.positions, s, side="right")))
    rods = int(np.count_nonzero(kinds == Element.ROD))
    return float(rods), float(np.count_nonzero(kinds == Element.CABLE))


def _violated(network: PeriodicNetwork, strain: np.ndarray, cert, res, cable: np.ndarray):
    """Where a floppy certificate would be violated as a rod, resp. as the site's one-sided
    kind, on every site (two (m,) bool arrays), evaluated like the certificate itself."""
    from ..model.mechanics import affine_extensions
    from ..solver.certificates import ExactGeometry, bond_vectors, violation_roundoff

    e0 = affine_extensions(network, strain)
    scale = float(np.abs(e0).max()) or 1.0
    d = bond_vectors(network, np.arange(network.n_sites))
    sigma = np.where(cable, 1.0, -1.0)
    geo = ExactGeometry(network.bonds, d, e0 / scale, sigma, network.n_nodes)
    v = geo.extensions(cert.u)
    limit = res.violation - violation_roundoff(cert.size)
    return np.abs(v) > limit, sigma * v > limit


def _bisect(rigid_at, a: int, b: int, lo_cert, hi_cert) -> tuple[int, int]:
    """Narrow (a, b] around the threshold; undecided probes split the search in two.

    ``rigid_at(i)`` is True (certified rigid), False (certified floppy) or None (undecided).
    Returns (a, b): the largest certified floppy index found and the smallest certified rigid
    one; every index strictly between them that was probed is undecided.
    """
    while True:
        a = max(a, lo_cert[0])
        b = min(b, hi_cert[0])
        if b - a <= 1:
            return a, b
        mid = (a + b) // 2
        r = rigid_at(mid)
        if r is True:
            b = mid
        elif r is False:
            a = mid
        else:
            # undecided: the last floppy lies in [a, mid), the first rigid in (mid, b]
            a2, _ = _bisect_side(rigid_at, a, mid, want_floppy=True, lo_cert=lo_cert)
            _, b2 = _bisect_side(rigid_at, mid, b, want_floppy=False, hi_cert=hi_cert)
            return max(a2, lo_cert[0]), min(b2, hi_cert[0])


def _bisect_side(rigid_at, a, b, want_floppy, lo_cert=None, hi_cert=None):
    """Bisect (a, b) for the last certified floppy (or first certified rigid) index."""
    while b - a > 1:
        if lo_cert is not None:
            a = max(a, lo_cert[0])
        if hi_cert is not None:
            b = min(b, hi_cert[0])
        if b - a <= 1:
            break
        mid = (a + b) // 2
        r = rigid_at(mid)
        if want_floppy:
            if r is False:
                a = mid
            else:
                b = mid
        else:
            if r is True:
                b = mid
            else:
                a = mid
    return a, b
