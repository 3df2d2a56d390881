"""The non-empty part of an instance as the solver sees it, with a reusable factorisation.

:class:`Problem` holds the rigidity matrix ``R`` of the non-empty sites, the affine extensions
``e0``, stiffnesses, element signs and the fixed sparsity pattern of ``R^T D R + mu I`` into
which every Newton, crossover and interior-point matrix is assembled (the fill-reducing ordering
and symbolic analysis are computed once per instance; :mod:`.linalg`). It also carries the
extended-precision geometry on which certificates are checked (:mod:`.certificates`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..model.mechanics import affine_extensions, rigidity_matrix
from ..model.network import Element, Instance, vector_norms
from .certificates import ExactGeometry, bond_vectors
from .linalg import PatternFactor, nested_dissection
from .tolerances import Tolerances

_AT_I, _AT_J, _OFF_DIAGONAL = 0, 1, 2


def _bond_terms() -> tuple[tuple[tuple[int, int, int, float, int, int], ...], ...]:
    """The terms one bond adds to the upper triangle of ``R^T D R``, for a bond from node
    ``i`` to node ``j`` with ``i < j``, ``i > j`` and ``i == j`` (a bond to the node's own
    image, in a small periodic box).

    The bond's row of ``R`` holds ``vals = (-dhat_x, -dhat_y, dhat_x, dhat_y)`` at columns
    ``cols = (2i, 2i + 1, 2j, 2j + 1)``; its terms are the products ``vals_p vals_q``
    (``k = 4p + q``, in increasing ``k``) with ``cols_p <= cols_q``. Each is returned as
    ``(where, a, c, sign, p % 2, q % 2)``: ``where`` is node ``i``'s diagonal block, node
    ``j``'s, or the block of the pair (lower node, higher node); ``(a, c)`` the entry's
    components within the block; the term is ``sign dhat_{p % 2} dhat_{q % 2}``, exactly the
    rounded product ``vals_p vals_q``.
    """
    out = []
    for i, j in ((0, 1), (1, 0), (0, 0)):
        cols = (2 * i, 2 * i + 1, 2 * j, 2 * j + 1)
        terms = []
        for k in range(16):
            p, q = divmod(k, 4)
            row, col = cols[p], cols[q]
            if row > col:
                continue
            if row // 2 != col // 2:
                where = _OFF_DIAGONAL
            else:
                where = _AT_I if row // 2 == i else _AT_J
            sign = (1.0 if p >= 2 else -1.0) * (1.0 if q >= 2 else -1.0)
            terms.append((where, row % 2, col % 2, sign, p % 2, q % 2))
        out.append(tuple(terms))
    return tuple(out)


#: :func:`_bond_terms`, computed once
_BOND_TERMS = _bond_terms()


class Problem:
    """The non-empty part of an instance with a reusable factorisation of the Newton matrix.

    Parameters
    ----------
    instance : Instance
        Network, elements and strain.
    regularization : float
        ``mu``, the diagonal shift of ``R^T D R + mu I`` relative to the mean stiffness.
    backend : {"auto", "cholmod", "qdldl"}
        Factorisation backend (:class:`~.linalg.PatternFactor`).
    unit_stiffness : bool
        Use unit stiffness on every element (the verdict does not depend on stiffness).
    tolerances : Tolerances, optional
        The numeric constants the routines working on the problem read (default
        ``Tolerances()``).

    Attributes
    ----------
    sites : (m,) int
        The non-empty bond sites of the instance.
    R, RT : sparse (m, 2N), (2N, m)
        Rigidity matrix of those sites and its transpose.
    e0 : (m,) float
        Affine extensions in units of ``scale``.
    k : (m,) float
        Stiffnesses relative to ``k_scale``.
    sigma : (m,) float
        +1 on cables, -1 on struts, 0 on rods.
    scale, k_scale : float
        ``max |e0|`` over all bond sites and the mean stiffness (physical units).
    factorizations : int
        Numeric factorisations so far.
    tol : Tolerances
        The numeric constants of the search and the relaxation.
    """

    def __init__(
        self,
        instance: Instance,
        regularization: float = 1e-12,
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
        self.mu = regularization
        if self.dim == 2:
            self._pattern()
        else:
            self._pattern_general()
        # 3D networks: a nested-dissection ordering (2D keeps CHOLMOD's AMD, and its bits)
        ordering = None
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
        """Fixed upper-triangular CSC pattern of R^T D R + mu I and the map into it.

        Built per node pair: node ``J``'s two columns hold rows ``2I, 2I + 1`` for every
        node ``I < J`` bonded to it, then its own diagonal block. ``_assemble`` (entries x
        sites) holds each entry's terms (:data:`_BOND_TERMS`) ordered by bond, so that
        ``_assemble @ w`` adds them in a fixed order: the same sums to the last bit as a
        per-entry construction (tests/solver/test_problem.py keeps it as the reference).
        """
        net = self.instance.network
        n_nodes = net.n_nodes
        i = net.bonds[self.sites, 0].astype(np.int64)
        j = net.bonds[self.sites, 1].astype(np.int64)
        m = i.size
        lo, hi = np.minimum(i, j), np.maximum(i, j)
        nodes = np.arange(n_nodes, dtype=np.int64)
        # node pairs (I, J), I <= J, with every node's own pair: column J lists its rows I
        # in increasing order, J itself last
        pairs = sp.csc_matrix(
            (np.ones(m + n_nodes), (np.r_[lo, nodes], np.r_[hi, nodes])),
            shape=(n_nodes, n_nodes),
        )
        pairs.sum_duplicates()
        per_node = np.diff(pairs.indptr).astype(np.int64)
        bonded = np.zeros(n_nodes, dtype=bool)
        bonded[i] = bonded[j] = True
        # column 2J: 2 rows per pair below J, then 2J; column 2J + 1: the same, then 2J and
        # 2J + 1 (2J + 1 alone on a node without elements: its diagonal only)
        counts = np.empty(2 * n_nodes, dtype=np.int64)
        counts[0::2] = 2 * per_node - 1
        counts[1::2] = 2 * per_node - 1 + bonded
        indptr = np.zeros(2 * n_nodes + 1, dtype=np.int64)
        np.cumsum(counts, out=indptr[1:])
        nnz = int(indptr[-1])
        pair_col = np.repeat(nodes, per_node)
        pair_row = pairs.indices.astype(np.int64)
        in_column = np.arange(pair_col.size) - pairs.indptr[pair_col]
        below = pair_row != pair_col
        indices = np.empty(nnz, dtype=np.int32)
        for c in (0, 1):
            first = indptr[2 * pair_col + c] + 2 * in_column
            indices[first] = 2 * pair_row  # 2I below the diagonal, 2J on it
            indices[first[below] + 1] = 2 * pair_row[below] + 1
        last = indptr[2 * nodes + 1] + 2 * (per_node - 1)
        indices[last[~bonded]] = 2 * nodes[~bonded] + 1
        indices[last[bonded] + 1] = 2 * nodes[bonded] + 1
        # entries (2X + a, 2X + c) of node X's diagonal block, by a + c
        block = np.stack([indptr[2 * nodes] + 2 * (per_node - 1), last, last + bonded])
        # each bond's offset in its pair's rows: 2 * (position of (lo, hi) in column hi)
        keys = pair_col * n_nodes + pair_row
        pair_offset = 2 * (np.searchsorted(keys, hi * n_nodes + lo) - pairs.indptr[hi])
        d = net.bond_vectors()[self.sites]
        dhat = d / np.hypot(d[:, 0], d[:, 1])[:, None]
        # every bond's terms, bond after bond, each bond's in k order
        case = np.where(i < j, 0, np.where(i > j, 1, 2))
        n_terms = np.array([len(t) for t in _BOND_TERMS])[case]
        start = np.zeros(m, dtype=np.int64)
        np.cumsum(n_terms[:-1], out=start[1:])
        slot = np.empty(int(n_terms.sum()), dtype=np.int64)
        value = np.empty(slot.size)
        site = np.empty(slot.size, dtype=np.int32)
        for kind, terms in enumerate(_BOND_TERMS):
            b = np.flatnonzero(case == kind)
            if b.size == 0:
                continue
            dx, dy = dhat[b, 0], dhat[b, 1]
            dxdy = dx * dy  # dy * dx to the last bit
            products = {(0, 0): dx * dx, (0, 1): dxdy, (1, 0): dxdy, (1, 1): dy * dy}
            for t, (where, a, c, sign, pa, qc) in enumerate(terms):
                at = start[b] + t
                if where == _OFF_DIAGONAL:
                    slot[at] = indptr[2 * hi[b] + c] + pair_offset[b] + a
                else:
                    slot[at] = block[a + c, (i if where == _AT_I else j)[b]]
                value[at] = products[pa, qc] if sign > 0 else -products[pa, qc]
                site[at] = b
        order = np.argsort(slot, kind="stable")
        rows = np.zeros(nnz + 1, dtype=np.int64)
        np.cumsum(np.bincount(slot, minlength=nnz), out=rows[1:])
        self._indices = indices
        self._indptr = indptr.astype(np.int32)
        self._nnz = nnz
        self._assemble = sp.csr_matrix((value[order], site[order], rows), shape=(nnz, m))
        self._diagonal = np.empty(2 * n_nodes, dtype=np.int64)  # pattern entries of the diagonal
        self._diagonal[0::2] = block[0]
        self._diagonal[1::2] = block[2]

    def _pattern_general(self) -> None:
        """The pattern and the assembly map of :meth:`_pattern` in any dimension ``d``.

        Each bond's row of ``R`` holds ``(-dhat, dhat)`` at the ``2d`` columns of its two
        nodes; its terms are the products ``vals_p vals_q`` with ``cols_p <= cols_q`` (both
        orders where the columns coincide, as for a bond to its node's own image, whose terms
        then cancel). The pattern is the set of entries those terms reach plus the diagonal,
        in CSC order; the assembly matrix adds each entry's terms bond by bond.
        """
        net = self.instance.network
        d, n = self.dim, self.dim * net.n_nodes
        i = net.bonds[self.sites, 0].astype(np.int64)
        j = net.bonds[self.sites, 1].astype(np.int64)
        m = i.size
        vec = net.bond_vectors()[self.sites]
        dhat = vec / vector_norms(vec)[:, None]
        axes = np.arange(d)
        cols = np.c_[d * i[:, None] + axes, d * j[:, None] + axes]  # (m, 2d)
        vals = np.c_[-dhat, dhat]
        grid_p, grid_q = np.meshgrid(np.arange(2 * d), np.arange(2 * d), indexing="ij")
        p, q = grid_p.ravel(), grid_q.ravel()
        row, col = cols[:, p], cols[:, q]  # (m, 4 d^2), bond after bond, each in k order
        keep = row <= col
        site = np.broadcast_to(np.arange(m)[:, None], row.shape)[keep]
        value = (vals[:, p] * vals[:, q])[keep]
        term_keys = col[keep] * n + row[keep]  # column-major: CSC order
        diag = np.arange(n, dtype=np.int64)
        keys = np.unique(np.r_[term_keys, diag * n + diag])
        entry = np.searchsorted(keys, term_keys)
        order = np.argsort(entry, kind="stable")
        counts = np.bincount(entry, minlength=keys.size)
        rows_ptr = np.zeros(keys.size + 1, dtype=np.int64)
        np.cumsum(counts, out=rows_ptr[1:])
        self._assemble = sp.csr_matrix(
            (value[order], site[order].astype(np.int32), rows_ptr), shape=(keys.size, m)
        )
        self._indices = (keys % n).astype(np.int32)
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.bincount(keys // n, minlength=n), out=indptr[1:])
        self._indptr = indptr.astype(np.int32)
        self._nnz = int(keys.size)
        self._diagonal = np.searchsorted(keys, diag * n + diag)

    def values(self, weights: np.ndarray, shift: float | None = None) -> np.ndarray:
        """Entries of ``R^T diag(weights) R + shift I`` in the fixed upper-triangular pattern.

        Parameters
        ----------
        weights : (m,) float
            Per-element weights.
        shift : float, optional
            Diagonal shift (default ``mu``).

        Returns
        -------
        (nnz,) float
            Values in the pattern's CSC order.
        """
        out = self._assemble @ np.asarray(weights, dtype=float)
        out[self._diagonal] += self.mu if shift is None else shift
        return out

    def factor(self, weights: np.ndarray) -> PatternFactor:
        """The factorisation of ``R^T diag(weights) R + mu I``, reused while the weights do
        not change.

        Parameters
        ----------
        weights : (m,) float
            Per-element weights.

        Returns
        -------
        PatternFactor
            Solves with the factorised matrix (``.solve(b)``, b of shape (2N,)).
        """
        if self._weights is None or not np.array_equal(weights, self._weights):
            self._weights = None  # until the factorisation below succeeds
            self._factor.factor(self.values(weights, self.mu))
            self._weights = weights.copy()
            self.factorizations += 1
        return self._factor

    def factor_values(self, values: np.ndarray) -> PatternFactor:
        """Factorise a matrix given by its values in the fixed pattern.

        Parameters
        ----------
        values : (nnz,) float
            Values as returned by :meth:`values`.

        Returns
        -------
        PatternFactor
            The factorisation.
        """
        self._weights = None
        self._factor.factor(values)
        self.factorizations += 1
        return self._factor

    def factor_shifted(self, weights: np.ndarray, shifts) -> PatternFactor | None:
        """Factorise ``R^T diag(weights) R + mu I`` with the first shift ``mu`` of ``shifts``
        for which it succeeds (singular matrices need a larger one).

        Parameters
        ----------
        weights : (m,) float
            Per-element weights.
        shifts : sequence of float
            Shifts tried in turn.

        Returns
        -------
        PatternFactor or None
            The factorisation, or None when every shift failed.
        """
        for mu in shifts:
            try:
                return self.factor_values(self.values(weights, mu))
            except ArithmeticError:
                continue
        return None

    def energy(self, u: np.ndarray) -> float:
        """The energy ``E(u)`` (no background stiffness).

        Parameters
        ----------
        u : (2N,) float
            Displacements in units of ``scale``.

        Returns
        -------
        float
            ``1/2 sum_b k_b h_b(e_b) e_b^2`` in units of ``k_scale scale^2``.
        """
        e, _, t = self.state(u)
        return 0.5 * float(np.dot(t, e))

    def active(self, e: np.ndarray) -> np.ndarray:
        """Engaged elements at extensions ``e`` ((m,)): rods, stretched cables, compressed
        struts; returns an (m,) bool array."""
        return self.rod | (self.sigma * e > 0)

    def state(self, u: np.ndarray):
        """Extensions (m,), engaged mask (m,) and tensions (m,) at displacements ``u`` (2N,)."""
        e = self.e0 + self.R @ u
        act = self.active(e)
        t = np.where(act, self.k * e, 0.0)
        return e, act, t
