"""Exact relaxation and the certified rigid/floppy verdict of one instance.

Imports :mod:`tensegrity_rigidity.model` only.
"""

from .certificates import Resolution
from .core import SolveResult, SolverOptions, Verdict, decide, solve

__all__ = ["Resolution", "SolveResult", "SolverOptions", "Verdict", "decide", "solve"]
