"""Ensembles: sweep specs, per-sample runs, executors, the result store, thresholds.

Imports :mod:`~tensegrity_rigidity.model`, :mod:`~tensegrity_rigidity.solver` and
:mod:`tensegrity_rigidity.analysis.observables`.
"""
