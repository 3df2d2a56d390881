"""Exact per-sample thresholds along monotone paths in (p_r, p_t), by bisection.

With the coupled site uniforms of :mod:`~tensegrity_rigidity.elements`, a path on which both
``p_r`` and ``p_r + p_t`` never decrease only ever adds elements or turns one-sided elements into
rods, so a sample's rigidity is monotone along it (MODEL.md). The configuration changes only at
finitely many *events* (where ``p_r`` or ``p_r + p_t`` crosses a site's ``U``); bisection over the
sorted events finds the first rigid configuration in about ``log2(#events)`` solves.

Paths (parameter ``s``):

* ``"p_r"``: ``p_r = s`` in ``[0, 1 - p_t]`` at fixed ``p_t``;
* ``"total"``: ``p_r = s`` in ``[0, T]`` with ``p_r + p_t = T`` fixed (one-sided -> rods).

The threshold ``s*`` is the event that made the sample rigid: the sample is rigid for
``p_r > s*`` and floppy for ``p_r <= s*`` (``s* = nan`` if it is floppy along the whole path,
``s* = 0`` if rigid from the start). Hence ``P(p_r) = mean(s* < p_r)`` on any grid.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, UndecidedWarning
from ..model.network import Element, Instance, PeriodicNetwork
from ..solver.core import SolverOptions, solve


@dataclass(frozen=True)
class Threshold:
    """Result of a threshold search.

    Attributes
    ----------
    s : float
        Critical p_r (see module docstring); nan if never rigid on the path.
    p_t : float
        p_t at the threshold.
    solves : int
        Number of exact solves used.
    decided : bool
        False when a configuration on the bisection path had no certificate to tolerance
        (a verdict below double-precision resolution); s is then nan and the sample should be
        excluded from statistics, and counted.
    """

    s: float
    p_t: float
    solves: int
    decided: bool = True


def _events(u: np.ndarray, path: str, p_t: float):
    """Sorted event positions and, per site, the index of its rod / one-sided event."""
    m = u.size
    if path == "p_r":
        s_max = 1.0 - p_t
        rod_s = np.where(u <= s_max, u, np.inf)
        os_s = u - p_t  # becomes one-sided when s + p_t passes U
        os_s = np.where((os_s > 0) & (os_s <= s_max), os_s, np.where(os_s <= 0, -np.inf, np.inf))
    elif path == "total":
        total = p_t
        rod_s = np.where(u < total, u, np.inf)
        os_s = np.where(u < total, -np.inf, np.inf)
    else:
        raise InputError(f"unknown threshold path {path!r}; use 'p_r' or 'total'")
    pos = np.r_[rod_s, os_s]
    kind = np.r_[np.zeros(m, int), np.ones(m, int)]
    site = np.r_[np.arange(m), np.arange(m)]
    finite = np.isfinite(pos)
    order = np.argsort(pos[finite], kind="stable")
    ev_pos = pos[finite][order]
    ev_kind = kind[finite][order]
    ev_site = site[finite][order]
    initially_os = np.isneginf(os_s)
    return ev_pos, ev_kind, ev_site, initially_os


def _kinds_after(i, ev_kind, ev_site, initially_os, v, f_c):
    """Element kinds after the first i events."""
    m = v.size
    one_sided = initially_os.copy()
    rod = np.zeros(m, bool)
    one_sided[ev_site[:i][ev_kind[:i] == 1]] = True
    rod[ev_site[:i][ev_kind[:i] == 0]] = True
    kinds = np.full(m, Element.EMPTY, dtype=np.int64)
    kinds[one_sided & (v < f_c)] = Element.CABLE
    kinds[one_sided & (v >= f_c)] = Element.STRUT
    kinds[rod] = Element.ROD
    return kinds


def find_threshold(
    network: PeriodicNetwork,
    u: np.ndarray,
    v: np.ndarray,
    strain: np.ndarray,
    p_t: float,
    f_c: float,
    path: str = "p_r",
    options: SolverOptions | None = None,
    warm_start: bool = True,
) -> Threshold:
    """Exact critical p_r of one sample along a monotone path.

    Parameters
    ----------
    network : PeriodicNetwork
        Geometry (element kinds are ignored).
    u, v : (m,) float
        The sample's site uniforms.
    strain : (2, 2) float
        Strain tensor.
    p_t : float
        Fixed p_t (path "p_r") or fixed total p_r + p_t (path "total").
    f_c : float
        Cable fraction.
    warm_start : bool
        Start each solve from the displacements of the solved configuration nearest on the path
        (it differs by the elements added in between).
    """
    opts = options or SolverOptions(min_norm=False)
    ev_pos, ev_kind, ev_site, initially_os = _events(u, path, p_t)
    n_ev = ev_pos.size
    cache: dict[int, bool] = {}
    displacements: dict[int, np.ndarray] = {}

    class _Undecided(Exception):
        pass

    def rigid(i: int) -> bool:
        if i not in cache:
            kinds = _kinds_after(i, ev_kind, ev_site, initially_os, v, f_c)
            start = None
            if warm_start and displacements:
                start = displacements[min(displacements, key=lambda j: abs(j - i))]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UndecidedWarning)
                res = solve(Instance(network.with_kinds(kinds), strain), opts, start)
            if not res.decided:
                raise _Undecided
            cache[i] = res.rigid
            displacements[i] = res.displacements
        return cache[i]

    try:
        return _bisect(rigid, n_ev, ev_pos, p_t, path, cache)
    except _Undecided:
        warnings.warn(
            "threshold undecided: a configuration on the path has no certificate to tolerance",
            UndecidedWarning,
            stacklevel=2,
        )
        return Threshold(float("nan"), float("nan"), len(cache) + 1, decided=False)


def _bisect(rigid, n_ev, ev_pos, p_t, path, cache) -> Threshold:
    """Smallest rigid configuration index by bisection; rigid(i) is monotone in i."""

    def p_t_at(s):
        return p_t if path == "p_r" else p_t - s

    if not rigid(n_ev):
        return Threshold(float("nan"), float("nan"), len(cache))
    if rigid(0):
        return Threshold(0.0, p_t_at(0.0), len(cache))
    lo, hi = 0, n_ev  # rigid(lo) False, rigid(hi) True
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if rigid(mid):
            hi = mid
        else:
            lo = mid
    s = float(ev_pos[hi - 1])
    return Threshold(s, p_t_at(s), len(cache))
