"""Exact relaxation and the certified rigid/floppy verdict of one instance.

Imports :mod:`tensegrity_rigidity.model` only.
"""

from .core import SolveResult, SolverOptions, solve

__all__ = ["SolveResult", "SolverOptions", "solve"]
