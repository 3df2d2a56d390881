"""The model: periodic networks, lattices, random elements, strain, linear mechanics, files.

Imports nothing else from the package but :mod:`tensegrity_rigidity.errors`.
"""
