"""Analysis: per-sample observables, ensemble estimators, the single-node theory.

Imports :mod:`~tensegrity_rigidity.model` and :mod:`~tensegrity_rigidity.solver` only.
"""
