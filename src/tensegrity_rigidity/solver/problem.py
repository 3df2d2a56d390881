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
from ..model.network import Element, Instance
from .certificates import ExactGeometry, bond_vectors
from .linalg import PatternFactor


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
    """

    def __init__(
        self,
        instance: Instance,
        regularization: float = 1e-12,
        backend: str = "auto",
        unit_stiffness: bool = False,
    ):
        net = instance.network
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
        self.n2 = 2 * net.n_nodes
        self.mu = regularization
        self._pattern()
        self._factor = PatternFactor(self._indptr, self._indices, self.n2, backend)
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
        """Fixed upper-triangular CSC pattern of R^T D R + mu I and the scatter map into it."""
        net = self.instance.network
        i, j = net.bonds[self.sites, 0], net.bonds[self.sites, 1]
        cols = np.c_[2 * i, 2 * i + 1, 2 * j, 2 * j + 1]  # (m, 4)
        d = net.bond_vectors()[self.sites]
        dhat = d / np.hypot(d[:, 0], d[:, 1])[:, None]
        vals = np.c_[-dhat, dhat]  # row b of R: -dhat at node i, +dhat at node j
        rr_rows = np.repeat(cols, 4, axis=1)  # (m, 16): row index of entry (p, q) = cols[p]
        rr_cols = np.tile(cols, (1, 4))  # col index = cols[q]
        rr_vals = np.einsum("bp,bq->bpq", vals, vals).reshape(-1, 16)
        keep = rr_rows <= rr_cols  # upper triangle
        diag = np.arange(self.n2)
        rows = np.r_[rr_rows[keep], diag]
        colsf = np.r_[rr_cols[keep], diag]
        # distinct (col, row) entries in CSC order, and where each contribution lands: a sparse
        # COO -> CSC conversion plus a binary search is 2x faster than np.unique's inverse
        csc = sp.csc_matrix((np.ones(rows.size), (rows, colsf)), shape=(self.n2, self.n2))
        csc.sum_duplicates()
        uniq = np.repeat(np.arange(self.n2, dtype=np.int64), np.diff(csc.indptr)) * self.n2
        uniq += csc.indices
        inverse = np.searchsorted(uniq, colsf.astype(np.int64) * self.n2 + rows)
        self._indices = csc.indices.astype(np.int32)
        self._indptr = csc.indptr.astype(np.int32)
        self._nnz = len(uniq)
        # the values as one sparse product: row e of ``_assemble`` holds the contributions
        # ``rr`` to pattern entry e in their order above (a stable sort by entry; a bond from a
        # node to its own image contributes more than once to an entry), so that each entry
        # adds them in increasing index from 0, as the np.bincount over them that this replaced
        # (eeb682e) did: the same sums to the last bit on x86-64 (SciPy's product fuses no
        # multiply-add there), in a third of the time (0.25 -> 0.08 ms a call at n = 64, for
        # about 1.5 ms more here)
        n_rr = rr_rows[keep].size
        slot = inverse[:n_rr]
        order = np.argsort(slot, kind="stable")
        self._assemble = sp.csr_matrix(
            (
                rr_vals[keep][order],
                np.nonzero(keep)[0][order],
                np.r_[0, np.cumsum(np.bincount(slot, minlength=self._nnz))],
            ),
            shape=(self._nnz, self.sites.size),
        )
        self._diagonal = inverse[n_rr:]  # pattern entries of the diagonal

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
