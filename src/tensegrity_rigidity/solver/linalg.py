"""Repeated sparse Cholesky / LDL^T factorisation of matrices with one fixed sparsity pattern.

Every Newton, crossover and interior-point step factorises ``R^T D R + mu I`` for a new ``D``:
:class:`PatternFactor` orders and analyses the pattern once and redoes only the numeric step, by
CHOLMOD's supernodal Cholesky (CVXOPT) or, where that meets a non-positive pivot, QDLDL's LDL^T.
"""

from __future__ import annotations

import contextlib
import functools
from collections.abc import Iterator

import numpy as np
import qdldl
import scipy.linalg  # noqa: F401 (loads SciPy's own BLAS, so that one_blas_thread finds it)
import scipy.sparse as sp
from threadpoolctl import ThreadpoolController

try:  # CVXOPT ships SuiteSparse's CHOLMOD in its wheels
    from cvxopt import cholmod as _cholmod
    from cvxopt import matrix as _cvx_matrix
    from cvxopt import spmatrix as _cvx_spmatrix
except ImportError:  # pragma: no cover - cvxopt is a declared dependency
    _cholmod = None


@functools.cache
def _controller() -> ThreadpoolController:
    """The loaded thread pools, found once (inspecting them costs a few milliseconds)."""
    return ThreadpoolController()


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """Run the enclosed code with every loaded BLAS on one thread, then restore the counts.

    A multithreaded BLAS sums long dot products in an order that depends on its thread count, and
    near a threshold the last bits decide: the verdict must depend on the instance and options only.
    """
    with _controller().limit(limits=1, user_api="blas"):
        yield


def nested_dissection(n_nodes: int, pairs: np.ndarray, dim: int) -> np.ndarray:
    """A METIS nested-dissection ordering ((dim N,) int, new position -> unknown) of the ``dim
    n_nodes`` unknowns of a network with node pairs ``pairs`` (m, 2) (self-images and repeats
    allowed), each node's unknowns in turn; deterministic for a graph."""
    import pymetis

    i, j = np.asarray(pairs, dtype=np.int64).T
    off = i != j
    graph = sp.coo_matrix(
        (np.ones(2 * int(off.sum())), (np.r_[i[off], j[off]], np.r_[j[off], i[off]])),
        shape=(n_nodes, n_nodes),
    ).tocsr()
    graph.sum_duplicates()
    graph.sort_indices()
    order = np.arange(n_nodes, dtype=np.int64)
    if graph.nnz:
        adjacency = pymetis.CSRAdjacency(graph.indptr.tolist(), graph.indices.tolist())
        metis_order, _ = pymetis.nested_dissection(adjacency=adjacency)
        order = np.asarray(metis_order, dtype=np.int64)
    return (dim * order[:, None] + np.arange(dim)).ravel()


class PatternFactor:
    """Factorisations of symmetric positive (semi)definite matrices sharing one pattern.

    Parameters
    ----------
    indptr, indices, n : int arrays, int
        CSC pattern of the upper triangle (sorted rows per column) of an (n, n) matrix.
    backend : {"auto", "cholmod", "qdldl"}
        "auto": CHOLMOD where available, QDLDL for matrices it rejects.
    ordering : (n,) int, optional
        A fill-reducing permutation for CHOLMOD (default its AMD).

    Attributes
    ----------
    backend : str
        Backend of the most recent factorisation.
    """

    def __init__(
        self,
        indptr: np.ndarray,
        indices: np.ndarray,
        n: int,
        backend: str = "auto",
        ordering: np.ndarray | None = None,
    ):
        if backend not in ("auto", "cholmod", "qdldl"):
            raise ValueError(f"unknown factorisation backend {backend!r}")
        if backend == "cholmod" and _cholmod is None:  # pragma: no cover
            raise ImportError("CHOLMOD needs cvxopt")
        self.n = n
        self._indptr = np.asarray(indptr, dtype=np.int32)
        self._indices = np.asarray(indices, dtype=np.int32)
        self._use_cholmod = backend != "qdldl" and _cholmod is not None
        self._allow_qdldl = backend != "cholmod"
        self._cvx = None  # cvxopt spmatrix holding the pattern
        self._symbolic = None
        self._qdldl: qdldl.Solver | None = None
        self._ordering = None if ordering is None else np.asarray(ordering, dtype=np.int64)
        self.backend = ""

    def factor(self, data: np.ndarray) -> PatternFactor:
        """Factorise the matrix with values ``data`` (in pattern order); returns self. Raises
        ArithmeticError when it is numerically singular for every allowed backend."""
        if self._use_cholmod:
            if self._cvx is None:
                cols = np.repeat(np.arange(self.n, dtype=np.int64), np.diff(self._indptr))
                self._cvx = _cvx_spmatrix(
                    _cvx_matrix(np.ascontiguousarray(data, dtype=float)),
                    _cvx_matrix(self._indices.astype(np.int64)),
                    _cvx_matrix(cols),
                    (self.n, self.n),
                )
                _cholmod.options["supernodal"] = 2
                _cholmod.options["print"] = 0
                if self._ordering is None:  # CHOLMOD's own choice (AMD)
                    self._symbolic = _cholmod.symbolic(self._cvx, uplo="U")
                else:
                    order = _cvx_matrix(self._ordering.astype(np.int32).tolist(), tc="i")
                    self._symbolic = _cholmod.symbolic(self._cvx, p=order, uplo="U")
            else:
                self._cvx.V = _cvx_matrix(np.ascontiguousarray(data, dtype=float))
            try:
                _cholmod.numeric(self._cvx, self._symbolic)
                self.backend = "cholmod"
                return self
            except ArithmeticError:
                if not self._allow_qdldl:
                    raise
                # a non-positive pivot: this matrix goes to LDL^T (the analysis stays valid)
        H = sp.csc_matrix((data, self._indices, self._indptr), shape=(self.n, self.n))
        self.backend = ""
        try:
            if self._qdldl is None:
                self._qdldl = qdldl.Solver(H, upper=True)
            else:
                self._qdldl.update(H, upper=True)
        except RuntimeError as err:  # QDLDL met a zero pivot: the matrix is numerically singular
            self._qdldl = None
            raise ArithmeticError(f"LDL^T factorisation failed: {err}") from err
        self.backend = "qdldl"
        return self

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve with the most recent factorisation; b is (N,)."""
        if self.backend == "cholmod":
            x = _cvx_matrix(np.asarray(b, dtype=float))
            _cholmod.solve(self._symbolic, x)
            return np.asarray(x).ravel()
        if self.backend == "qdldl" and self._qdldl is not None:  # set together by factor()
            return self._qdldl.solve(b)
        raise RuntimeError("solve() before factor()")
