"""The paper: its claims, the studies that test them, figures, the report, the reproduction.

May import every other subpackage but :mod:`~tensegrity_rigidity.cli`.
"""
