"""Single three-coordinated node: the supplement's mean-field theory, derived by enumeration.

A node of the triangular lattice with three of its six bonds occupied carries a unique self-stress
(up to scale): the null vector of the 2x3 matrix of unit bond vectors. Its sign pattern is

* **same-sign** (+++/---) when the three bonds do not lie in a half-plane, or
* **mixed** (+-+) when they do (the middle bond has the odd sign).

The node is rigid when the elements admit the pattern for one overall sign: rods take either
sign, cables need t > 0, struts t < 0. Of the C(6, 3) = 20 triples of hexagonal directions, 2 are
same-sign, 6 are mixed and 12 contain an opposite pair; with disorder the latter split evenly, so
the class weights are 8/20 (same-sign) and 12/20 (mixed). Note (docs/model.md): the supplement's
prose swaps the class labels; its table's column A is the *mixed* class (weight 3/5) and column B
the same-sign class (weight 2/5). Everything here is computed, not typed in.
"""

from __future__ import annotations

import itertools
from functools import lru_cache
from math import factorial

import numpy as np

from ..errors import InputError
from ..model.lattice import DEFAULT_DELTA

ROD, CABLE, STRUT = "r", "c", "s"


def _admissible(pattern: tuple[int, ...], elements: tuple[str, ...]) -> bool:
    for sigma in (1, -1):
        if all(
            e == ROD or (e == CABLE and sigma * s > 0) or (e == STRUT and sigma * s < 0)
            for s, e in zip(pattern, elements, strict=False)
        ):
            return True
    return False


def qbar(pattern_class: str, n_r: int, n_c: int, n_s: int) -> float:
    """Fraction of the distinct placements of (n_r, n_c, n_s) on a node of a class that are rigid.

    Parameters
    ----------
    pattern_class : {"mixed", "same"}
        Sign class of the node's self-stress: "mixed" (the supplement table's column A) or
        "same" (column B).
    n_r, n_c, n_s : int
        Rods, cables and struts on the node's three bonds (``n_r + n_c + n_s = 3``).

    Returns
    -------
    float
        q-bar: the fraction of (placement, sign pattern) pairs the elements admit.

    Raises
    ------
    InputError
        When the counts do not add up to three.
    """
    if n_r + n_c + n_s != 3 or min(n_r, n_c, n_s) < 0:
        raise InputError("a three-coordinated node holds exactly three elements")
    patterns = [(1, 1, 1)] if pattern_class == "same" else [(1, -1, 1), (-1, 1, 1), (1, 1, -1)]
    placements = set(itertools.permutations([ROD] * n_r + [CABLE] * n_c + [STRUT] * n_s))
    ok = [_admissible(p, e) for p in patterns for e in placements]
    return float(np.mean(ok))


def _sign_class(angles: np.ndarray) -> str:
    vecs = np.c_[np.cos(angles), np.sin(angles)]
    null = np.linalg.svd(vecs.T)[2][-1]  # self-stress of the three bonds
    signs = np.sign(null)
    return "same" if abs(signs.sum()) == 3 else "mixed"


@lru_cache(maxsize=1)
def class_weights() -> dict[str, float]:
    """Weights of the two classes over the 20 triples of a (generically) disordered node.

    Returns
    -------
    dict
        ``{"same": 0.4, "mixed": 0.6}`` (computed, not typed in).

    Notes
    -----
    Each triple of hexagonal directions is perturbed by angles ``+-eta * (1, 2, 4)`` (distinct
    magnitudes, so no perturbation keeps a pair exactly opposite) and classified for each of
    the 8 sign choices; the weights are the averages.
    """
    base = np.pi / 3 * np.arange(6)
    eta = 1e-3 * np.array([1.0, 2.0, 4.0])
    counts = {"same": 0.0, "mixed": 0.0}
    triples = list(itertools.combinations(range(6), 3))
    for tri in triples:
        for signs in itertools.product((1, -1), repeat=3):
            counts[_sign_class(base[list(tri)] + np.array(signs) * eta)] += 1 / 8
    return {k: v / len(triples) for k, v in counts.items()}


def configurations() -> list[tuple[int, int, int]]:
    """All element counts of a three-coordinated node.

    Returns
    -------
    list of (int, int, int)
        The 10 triples (n_r, n_c, n_s) with n_r + n_c + n_s = 3.
    """
    return [(r, c, 3 - r - c) for r in range(4) for c in range(4 - r)]


def qbar_table() -> list[dict]:
    """The supplement's table of q-bar values, computed: one row per configuration.

    Returns
    -------
    list of dict
        ``n_r``, ``n_c``, ``n_s``, ``qbar_mixed`` (column A), ``qbar_same`` (column B).
    """
    return [
        {
            "n_r": r,
            "n_c": c,
            "n_s": s,
            "qbar_mixed": qbar("mixed", r, c, s),
            "qbar_same": qbar("same", r, c, s),
        }
        for r, c, s in configurations()
    ]


def single_node_probability(p_r: float, p_c: float, p_s: float) -> float:
    """P_N(p_r, p_c, p_s): probability that a three-coordinated node is rigid (supplement Eq.).

    Parameters
    ----------
    p_r, p_c, p_s : float
        Probabilities of a rod, a cable and a strut on a bond (non-negative, sum at most 1,
        not all zero).

    Returns
    -------
    float
        P_N.

    Raises
    ------
    InputError
        On negative or non-finite probabilities, a sum above 1, or all zero.

    Notes
    -----
    ``P_N = sum q(n) [w_mixed qbar_mixed(n) + w_same qbar_same(n)] / sum q(n)`` with
    ``q(n_r, n_c, n_s) = p_r^n_r p_c^n_c p_s^n_s (1 - p)^(6 - 3) / (n_r! n_c! n_s! 3!)``. Only the
    ratios p_r : p_c : p_s matter (the node is conditioned on three occupied bonds).
    """
    ps = np.array([p_r, p_c, p_s], dtype=float)
    if not np.all(np.isfinite(ps)) or np.any(ps < 0) or ps.sum() > 1 + 1e-12:
        raise InputError("p_r, p_c, p_s must be non-negative with p_r + p_c + p_s <= 1")
    if ps.sum() == 0:
        raise InputError("at least one of p_r, p_c, p_s must be positive")
    w = class_weights()
    num = den = 0.0
    for r, c, s in configurations():
        q = p_r**r * p_c**c * p_s**s / (factorial(r) * factorial(c) * factorial(s))
        num += q * (w["mixed"] * qbar("mixed", r, c, s) + w["same"] * qbar("same", r, c, s))
        den += q
    return num / den


def simulate_single_node(
    p_r: float,
    p_c: float,
    p_s: float,
    trials: int,
    rng: np.random.Generator,
    delta: float = DEFAULT_DELTA,
) -> tuple[int, int]:
    """Monte Carlo of the supplement's single node.

    Parameters
    ----------
    p_r, p_c, p_s : float
        Relative probabilities of a rod, a cable and a strut.
    trials : int
        Number of random nodes.
    rng : numpy.random.Generator
        Source of the kicks, bonds and elements.
    delta : float
        Node disorder.

    Returns
    -------
    rigid, trials : int
        Rigid nodes and trials.

    Notes
    -----
    Each trial perturbs a central node and its six neighbours by uniform kicks in
    ``[-delta, delta]``, picks three of the six bonds at random, takes the null vector of their
    2x3 matrix of unit vectors as the self-stress, draws rod/cable/strut with probabilities
    proportional to (p_r, p_c, p_s), and checks that the elements admit its signs.
    """
    probs = np.array([p_r, p_c, p_s], dtype=float)
    probs = probs / probs.sum()
    nbrs = np.c_[np.cos(np.pi / 3 * np.arange(6)), np.sin(np.pi / 3 * np.arange(6))]
    rigid = 0
    for _ in range(trials):
        centre = rng.uniform(-delta, delta, 2)
        pos = nbrs + rng.uniform(-delta, delta, (6, 2))
        pick = rng.choice(6, size=3, replace=False)
        d = pos[pick] - centre
        d /= np.linalg.norm(d, axis=1)[:, None]
        null = np.linalg.svd(d.T)[2][-1]
        kinds = rng.choice([ROD, CABLE, STRUT], size=3, p=probs)
        rigid += _admissible(tuple(np.sign(null)), tuple(kinds))
    return rigid, trials
