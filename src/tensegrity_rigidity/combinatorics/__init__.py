"""Combinatorial rigidity of rods-only networks: a pebble game on the fixed periodic box.

:mod:`~tensegrity_rigidity.combinatorics.clusters` holds :func:`rigid_clusters` and the
incremental pass used by exact thresholds; :mod:`~tensegrity_rigidity.combinatorics.pebble` the
compiled kernel. This stage imports only :mod:`~tensegrity_rigidity.model`.
"""
