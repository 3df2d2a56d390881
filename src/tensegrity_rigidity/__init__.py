"""tensegrity_rigidity: exact rigidity of random periodic tensegrity networks.

Pipeline, one module per stage: :mod:`~.lattice` (geometry) -> :mod:`~.elements` (random rods,
cables, struts) -> :mod:`~.strain` -> :mod:`~.mechanics` (rigidity matrix, energy, tensions) ->
:mod:`~.solver` (exact relaxation and certified verdict) -> :mod:`~.io` (instance files).
"""

from .elements import place_elements, site_uniforms
from .errors import InputError, SpecError, TensegrityError, UndecidedWarning
from .io import load_instance, save_instance
from .lattice import DEFAULT_DELTA, random_periodic_network, square_lattice, triangular_lattice
from .network import Element, Instance, PeriodicNetwork
from .sample import lattice_instance
from .single_node import single_node_probability
from .solver import SolveResult, SolverOptions, solve
from .strain import strain_tensor

__all__ = [
    "DEFAULT_DELTA",
    "Element",
    "InputError",
    "Instance",
    "PeriodicNetwork",
    "SolveResult",
    "SolverOptions",
    "SpecError",
    "TensegrityError",
    "UndecidedWarning",
    "lattice_instance",
    "load_instance",
    "place_elements",
    "random_periodic_network",
    "save_instance",
    "single_node_probability",
    "site_uniforms",
    "solve",
    "square_lattice",
    "strain_tensor",
    "triangular_lattice",
]

__version__ = "0.1.0"
