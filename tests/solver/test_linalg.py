"""The repeated sparse factorisation: both backends solve, and the solver does not depend on it."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from benchmarks.reference import lp_verdict
from tensegrity_rigidity import SolverOptions, solve
from tensegrity_rigidity.errors import InputError
from tensegrity_rigidity.solver.linalg import PatternFactor
from tests.instances import random_instance


def _upper_pattern(A: sp.spmatrix):
    U = sp.triu(A).tocsc()
    U.sort_indices()
    return U


@pytest.mark.parametrize("backend", ["auto", "cholmod", "qdldl"])
def test_backends_solve_spd_systems_with_new_values_in_the_same_pattern(backend):
    rng = np.random.default_rng(5)
    n = 60
    B = sp.random(n, n, density=0.08, random_state=6, format="csc")
    S = (B @ B.T + sp.eye(n)).tocsc()
    U = _upper_pattern(S)
    f = PatternFactor(U.indptr, U.indices, n, backend=backend)
    for scale in (1.0, 3.0, 0.01):
        # new values, same pattern: scale the off-diagonal part, keep it diagonally dominant
        V = _upper_pattern(S * scale + sp.eye(n) * (1.0 - scale) ** 2)
        np.testing.assert_array_equal(V.indices, U.indices)
        b = rng.standard_normal(n)
        x = f.factor(V.data).solve(b)
        full = V + sp.triu(V, 1).T
        assert np.linalg.norm(full @ x - b) <= 1e-12 * np.linalg.norm(b)


def test_auto_falls_back_to_ldl_on_an_indefinite_matrix():
    """Cholesky rejects a negative pivot; "auto" then uses LDL^T, "cholmod" raises."""
    A = sp.csc_matrix(np.array([[1.0, 2.0], [2.0, 1.0]]))  # eigenvalues 3 and -1
    U = _upper_pattern(A)
    auto = PatternFactor(U.indptr, U.indices, 2, backend="auto").factor(U.data)
    assert auto.backend == "qdldl"
    np.testing.assert_allclose(A @ auto.solve(np.array([1.0, 0.0])), [1.0, 0.0], atol=1e-14)
    with pytest.raises(ArithmeticError):
        PatternFactor(U.indptr, U.indices, 2, backend="cholmod").factor(U.data)


@pytest.mark.parametrize("backend", ["auto", "qdldl"])
def test_a_singular_matrix_raises_arithmetic_error_and_the_next_one_factors(backend):
    """A zero pivot is an ArithmeticError from every backend (the proximal stage of the solver
    relies on it), and the same PatternFactor factorises the next, regular matrix."""
    A = sp.csc_matrix(np.array([[1.0, 1.0], [1.0, 1.0]]))  # singular: eigenvalues 2 and 0
    U = _upper_pattern(A)
    f = PatternFactor(U.indptr, U.indices, 2, backend=backend)
    with pytest.raises(ArithmeticError):
        f.factor(U.data)
    good = U.data + np.array([1.0, 0.0, 1.0])  # [[2, 1], [1, 2]] in the same pattern
    x = f.factor(good).solve(np.array([3.0, 3.0]))
    np.testing.assert_allclose(x, [1.0, 1.0], atol=1e-14)


def test_unknown_backend_is_refused():
    with pytest.raises(ValueError, match="backend"):
        PatternFactor(np.zeros(2, int), np.zeros(0, int), 1, backend="mumps")
    with pytest.raises(InputError, match="factorization"):
        SolverOptions(factorization="mumps")


def test_verdict_and_energy_do_not_depend_on_the_backend():
    """Same certificates whichever factorisation the steps use (n = 8 lattices near the
    transition and random periodic networks); both agree with the LP."""
    rng = np.random.default_rng(17)
    for i in range(30):
        inst = random_instance(rng, "lattice" if i % 2 else "random")
        a = solve(inst, SolverOptions(factorization="cholmod", min_norm=False))
        b = solve(inst, SolverOptions(factorization="qdldl", min_norm=False))
        assert a.decided and b.decided, i
        assert a.rigid == b.rigid == lp_verdict(inst).rigid, i
        if a.rigid:
            assert abs(a.energy - b.energy) <= 1e-9 * b.energy, i
