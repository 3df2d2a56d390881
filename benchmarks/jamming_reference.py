"""An independent jamming test: the oracle of the jamming tests and of `bench_jamming.py`.

Written apart from :mod:`tensegrity_rigidity.solver.jamming` and sharing none of its code:

* rattlers by a plain loop over particles;
* the rigidity matrix in double precision, dense, from the bond vectors;
* Donev et al.'s displacement LP (J. Comput. Phys. 197, 139, 2004), by SciPy's ``linprog``
  (HiGHS): maximise the total opening ``sum_c (A x)_c`` over motions with ``0 <= A x <= 1``
  (for ``strict`` with the strain columns and ``-tr eps >= 0`` among the rows);
* the rank of ``A`` by a dense SVD (translations are the only allowed null vectors).

Its verdict is "jammed" when the LP optimum is below ``lp_zero`` and the SVD shows no null vector
beyond the translations (smallest other singular value above ``sv_gap``), "unjammed" when the
optimum exceeds ``lp_open`` or a singular value is below ``sv_zero``, and "ambiguous" otherwise:
those instances are not decided with a margin and are not compared.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog

from tensegrity_rigidity.model.network import Element, PeriodicNetwork


@dataclass(frozen=True)
class ReferenceJamming:
    """The oracle's verdict and the numbers behind it."""

    status: str
    rattlers: np.ndarray
    lp_opening: float
    smallest_singular: float
    contacts: int


def reference_rattlers(network: PeriodicNetwork) -> np.ndarray:
    """Particles with fewer than d + 1 contacts, removed one sweep at a time (plain loops)."""
    d = network.dim
    contacts = [tuple(b) for b, k in zip(network.bonds, network.kinds, strict=True) if k != 0]
    removed: set[int] = set()
    changed = True
    while changed:
        changed = False
        for p in range(network.n_nodes):
            if p in removed:
                continue
            count = 0
            for i, j in contacts:
                if i in removed or j in removed:
                    continue
                count += (i == p) + (j == p)
            if count < d + 1:
                removed.add(p)
                changed = True
    return np.array(sorted(removed), dtype=np.int64)


def _matrix(network: PeriodicNetwork, kind: str, alive: np.ndarray):
    """Dense ``A`` (rows: contacts between live particles [+ volume]) and the translation count."""
    d = network.dim
    nodes = np.flatnonzero(alive)
    col = {int(p): k for k, p in enumerate(nodes)}
    rows = []
    vec = network.bond_vectors()
    strain_pairs = [(a, a) for a in range(d)] + [(a, b) for a in range(d) for b in range(a + 1, d)]
    lengths = []
    for s, ((i, j), k) in enumerate(zip(network.bonds, network.kinds, strict=True)):
        if k != Element.STRUT or not (alive[i] and alive[j]):
            continue
        n = vec[s] / np.linalg.norm(vec[s])
        lengths.append(np.linalg.norm(vec[s]))
        row = np.zeros(d * len(nodes) + (len(strain_pairs) if kind == "strict" else 0))
        row[d * col[int(j)] : d * col[int(j)] + d] += n
        row[d * col[int(i)] : d * col[int(i)] + d] -= n
        if kind == "strict":
            for q, (a, b) in enumerate(strain_pairs):
                value = n[a] * vec[s][b] + (n[b] * vec[s][a] if a != b else 0.0)
                row[d * len(nodes) + q] = value
        rows.append(row)
    A = np.array(rows).reshape(len(rows), -1)
    if kind == "strict" and len(rows):
        A[:, d * len(nodes) :] /= np.mean(lengths)
        vol = np.zeros(A.shape[1])
        vol[d * len(nodes) : d * len(nodes) + d] = -1.0
        A = np.vstack([A, vol])
    return A, d


def reference_jamming(
    network: PeriodicNetwork,
    kind: str = "collective",
    lp_zero: float = 1e-9,
    lp_open: float = 1e-6,
    sv_zero: float = 1e-10,
    sv_gap: float = 1e-6,
) -> ReferenceJamming:
    """The oracle's collective or strict verdict (see the module docstring)."""
    out = reference_rattlers(network)
    alive = np.ones(network.n_nodes, dtype=bool)
    alive[out] = False
    if not alive.any():
        return ReferenceJamming("unjammed", out, np.inf, 0.0, 0)
    A, d = _matrix(network, kind, alive)
    m, n = A.shape
    # maximise sum(A x) s.t. 0 <= A x <= 1, x free (HiGHS through SciPy)
    res = linprog(
        -A.sum(axis=0),
        A_ub=np.vstack([A, -A]),
        b_ub=np.r_[np.ones(m), np.zeros(m)],
        bounds=[(None, None)] * n,
        method="highs",
    )
    opening = -res.fun if res.status == 0 else np.nan
    sv = np.linalg.svd(A, compute_uv=False) if m else np.zeros(0)
    # the translations are d null vectors of A: the smallest other singular value
    expected_null = d
    padded = np.r_[sv, np.zeros(max(n - len(sv), 0))]
    others = np.sort(padded)[expected_null:] if n > expected_null else np.array([np.inf])
    smallest = float(others[0]) if others.size else np.inf
    if not np.isfinite(opening):
        status = "ambiguous"
    elif opening > lp_open or smallest < sv_zero:
        status = "unjammed"
    elif opening < lp_zero and smallest > sv_gap:
        status = "jammed"
    else:
        status = "ambiguous"
    return ReferenceJamming(status, out, float(opening), smallest, m)
