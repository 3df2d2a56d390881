"""The non-empty part of an instance as the solver sees it, with a reusable factorisation.

:class:`Problem` holds ``R``, ``e0``, stiffnesses and signs of the non-empty sites, the fixed
pattern of ``R^T D R + mu I`` every Newton, crossover and interior-point matrix is assembled into
(analysed once, :mod:`.linalg`), and the certificates' extended-precision geometry.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..model.mechanics import affine_extensions, rigidity_matrix
from ..model.network import Element, Instance, vector_norms
from .certificates import ExactGeometry, bond_vectors
from .linalg import PatternFactor, nested_dissection
from .tolerances import DEFAULT_REGULARIZATION, Tolerances


class Problem:
    """The non-empty part of an instance with a reusable factorisation of the Newton matrix.

    Built from ``instance`` with the shift ``regularization`` (``mu``, relative to the mean
    stiffness), the factorisation ``backend``, unit stiffnesses where ``unit_stiffness`` and
    ``tolerances`` (default ``Tolerances()``, read as ``tol``). Holds the non-empty ``sites`` (m,),
    ``R`` (m, dN) and ``RT``, ``e0`` (m,) in units of ``scale`` (``max |e0|`` over all bond sites),
    ``k`` (m,) relative to ``k_scale``, ``sigma`` (m,; +1 cables, -1 struts, 0 rods) and the count
    of numeric ``factorizations``.
    """

    def __init__(
        self,
        instance: Instance,
        regularization: float = DEFAULT_REGULARIZATION,
        backend: str = "auto",
        unit_stiffness: bool = False,
        tolerances: Tolerances | None = None,
    ):
        net = instance.network
        self.tol = Tolerances() if tolerances is None else tolerances
        self.instance = instance
        self.sites = np.flatnonzero(net.kinds != Element.EMPTY)
        kinds = net.kinds[self.sites]
        k = np.ones(self.sites.size) if unit_stiffness else net.stiffness_or_ones()[self.sites]
        #: mean stiffness (physical units); ``k`` below is relative to it
        self.k_scale = float(k.mean()) if k.size else 1.0
        self.k = k / self.k_scale
        self.rod = kinds == Element.ROD
        # sigma = +1 for cables, -1 for struts: a one-sided element is engaged when sigma e > 0
        self.sigma = np.where(
            kinds == Element.CABLE, 1.0, np.where(kinds == Element.STRUT, -1.0, 0.0)
        )
        self.one_sided = ~self.rod
        self.R = rigidity_matrix(net, self.sites)
        self.RT = self.R.T.tocsr()
        e0_all = affine_extensions(net, instance.strain)
        e0 = e0_all[self.sites]
        #: largest affine extension over all bond sites (physical units). Everything
        #: below is in units of it: extensions and displacements are divided by ``scale``,
        #: energies by ``k_scale scale^2``, tensions by ``k_scale scale``.
        self.scale = float(np.abs(e0_all).max()) if e0_all.size else 0.0
        self.e0 = e0 / self.scale if self.scale > 0 else e0
        #: dimension d of the space and number dN of displacement unknowns
        self.dim = net.dim
        self.n2 = self.dim * net.n_nodes
        self.mu, self.backend = regularization, backend
        self._pattern()
        ordering = None  # 3D: a nested-dissection ordering (2D keeps CHOLMOD's AMD, and its bits)
        if self.dim == 3:
            ordering = nested_dissection(net.n_nodes, net.bonds[self.sites], self.dim)
        self._factor = PatternFactor(self._indptr, self._indices, self.n2, backend, ordering)
        self._weights: np.ndarray | None = None
        self.factorizations = 0
        self._exact: ExactGeometry | None = None

    @property
    def exact(self) -> ExactGeometry:
        """The extended-precision geometry of the certificates (built on first use)."""
        if self._exact is None:
            net = self.instance.network
            d = bond_vectors(net, self.sites)
            self._exact = ExactGeometry(net.bonds[self.sites], d, self.e0, self.sigma, net.n_nodes)
        return self._exact

    def _pattern(self) -> None:
        """Fixed upper-triangular CSC pattern of ``R^T D R + mu I`` and the map into it.

        The ``d`` columns of node ``J`` hold ``d`` rows per node ``I < J`` bonded to it, then its
        own diagonal block. ``_assemble`` (nnz, m) holds each entry's terms bond by bond: its
        products sum them in the order of a per-entry construction (tests/solver/test_problem.py).
        """
        net = self.instance.network
        d, n_nodes = self.dim, net.n_nodes
        i, j = net.bonds[self.sites].T.astype(np.int64)
        m = i.size
        lo, hi = np.minimum(i, j), np.maximum(i, j)
        nodes = np.arange(n_nodes, dtype=np.int64)
        # node pairs (I, J), I <= J, with every node's own pair: column J lists its rows I in
        # increasing order, J itself last
        pairs = sp.csc_matrix(
            (np.ones(m + n_nodes), (np.r_[lo, nodes], np.r_[hi, nodes])), shape=(n_nodes, n_nodes)
        )
        pairs.sum_duplicates()
        below = np.diff(pairs.indptr).astype(np.int64) - 1  # pairs (I, J) with I < J, per J
        bonded = np.zeros(n_nodes, dtype=bool)
        bonded[i] = bonded[j] = True
        # column dJ + c: d rows per pair below J, then rows dJ .. dJ + c of its own block (dJ + c
        # alone on a node without elements: its diagonal only)
        comp = np.arange(d)
        counts = d * below[:, None] + np.where(bonded[:, None], comp + 1, 1)
        indptr = np.zeros(d * n_nodes + 1, dtype=np.int64)
        np.cumsum(counts.ravel(), out=indptr[1:])
        nnz = int(indptr[-1])
        pair_col, pair_row = np.repeat(nodes, below + 1), pairs.indices.astype(np.int64)
        off = pair_row != pair_col
        col_off, row_off = pair_col[off], pair_row[off]
        in_column = np.flatnonzero(off) - pairs.indptr[col_off]
        own = indptr[:-1].reshape(n_nodes, d) + d * below[:, None]  # first own row of each column
        indices = np.empty(nnz, dtype=np.int32)
        for c in range(d):
            first = indptr[d * col_off + c] + d * in_column
            for a in range(d):
                indices[first + a] = d * row_off + a
            for a in range(c + 1):
                indices[own[bonded, c] + a] = d * nodes[bonded] + a
            indices[own[~bonded, c]] = d * nodes[~bonded] + c
        diagonal = np.where(bonded[:, None], own + comp, own).ravel()
        # each bond's terms vals_p vals_q (k = 2d p + q) with cols_p <= cols_q, bond after bond:
        # which are kept, and which lie in a node's own block, depends only on whether i < j,
        # i > j or i == j (a bond to the node's own image)
        case = np.where(i < j, 0, np.where(i > j, 1, 2))
        ends = np.array([[0, 1], [1, 0], [0, 0]])[:, np.arange(2 * d) // d]  # (3, 2d)
        rep_cols = d * ends + np.r_[comp, comp]
        keep = (rep_cols[:, :, None] <= rep_cols[:, None, :])[case]  # (m, 2d, 2d)
        same = (ends[:, :, None] == ends[:, None, :])[case]
        node = np.repeat(np.c_[i, j], d, axis=1)  # (m, 2d)
        keys = pair_col * n_nodes + pair_row
        pair_offset = d * (np.searchsorted(keys, hi * n_nodes + lo) - pairs.indptr[hi])
        offset = np.where(same, (d * below[node])[:, None, :], pair_offset[:, None, None])
        start = indptr[d * node + np.r_[comp, comp]]
        slot = (start[:, None, :] + offset + np.r_[comp, comp][:, None])[keep]
        vec = net.bond_vectors()[self.sites]
        dhat = vec / vector_norms(vec)[:, None]
        vals = np.c_[-dhat, dhat]
        value = (vals[:, :, None] * vals[:, None, :])[keep]
        site = np.broadcast_to(np.arange(m, dtype=np.int32)[:, None, None], keep.shape)[keep]
        order = np.argsort(slot, kind="stable")
        rows = np.zeros(nnz + 1, dtype=np.int64)
        np.cumsum(np.bincount(slot, minlength=nnz), out=rows[1:])
        self._indices, self._indptr, self._diagonal = indices, indptr.astype(np.int32), diagonal
        self._assemble = sp.csr_matrix((value[order], site[order], rows), shape=(nnz, m))

    def values(self, weights: np.ndarray, shift: float | None = None) -> np.ndarray:
        """Entries ((nnz,), pattern order) of ``R^T diag(weights) R + shift I`` for ``weights`` (m,)
        (``shift``: default ``mu``)."""
        out = self._assemble @ np.asarray(weights, dtype=float)
        out[self._diagonal] += self.mu if shift is None else shift
        return out

    def factor(self, weights: np.ndarray) -> PatternFactor:
        """The factorisation of ``R^T diag(weights) R + mu I`` (``weights`` (m,)), reused while the
        weights do not change."""
        if self._weights is None or not np.array_equal(weights, self._weights):
            self._weights = None  # until the factorisation below succeeds
            self._factor.factor(self.values(weights, self.mu))
            self._weights = weights.copy()
            self.factorizations += 1
        return self._factor

    def factor_values(self, values: np.ndarray) -> PatternFactor:
        """Factorise the matrix given by its ``values`` ((nnz,), as :meth:`values` returns them)."""
        self._weights = None
        self._factor.factor(values)
        self.factorizations += 1
        return self._factor

    def factor_shifted(self, weights: np.ndarray, shifts) -> PatternFactor | None:
        """Factorise ``R^T diag(weights) R + mu I`` with the first ``mu`` of ``shifts`` that
        succeeds; None when all fail."""
        for mu in shifts:
            try:
                return self.factor_values(self.values(weights, mu))
            except ArithmeticError:
                continue
        return None

    def energy(self, u: np.ndarray) -> float:
        """The energy ``1/2 sum_b k_b h_b(e_b) e_b^2`` at ``u`` (2N,), units ``k_scale scale^2``."""
        e, _, t = self.state(u)
        return 0.5 * float(np.dot(t, e))

    def state(self, u: np.ndarray):
        """Extensions (m,), engaged mask (m,) and tensions (m,) at displacements ``u`` (2N,): rods,
        stretched cables and compressed struts are engaged."""
        e = self.e0 + self.R @ u
        act = self.rod | (self.sigma * e > 0)
        t = np.where(act, self.k * e, 0.0)
        return e, act, t
