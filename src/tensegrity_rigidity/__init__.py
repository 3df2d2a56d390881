"""tensegrity_rigidity: exact rigidity of random periodic tensegrity networks.

Subpackages by pipeline stage (ARCHITECTURE.md): :mod:`~.model` (networks, lattices, random
elements, strain, linear mechanics, files) -> :mod:`~.solver` (exact relaxation and certified
verdict) -> :mod:`~.analysis` (observables, estimators, single-node theory) -> :mod:`~.ensemble`
(sweeps, storage, executors, thresholds) -> :mod:`~.paper` (studies, figures, report) ->
:mod:`~.cli`.
"""

from .analysis.single_node import single_node_probability
from .errors import InputError, SpecError, TensegrityError, UndecidedWarning
from .model.elements import place_elements, site_uniforms
from .model.io import load_instance, save_instance
from .model.lattice import (
    DEFAULT_DELTA,
    random_periodic_network,
    square_lattice,
    triangular_lattice,
)
from .model.network import Element, Instance, PeriodicNetwork
from .model.sampling import lattice_instance
from .model.strain import strain_tensor
from .solver.core import SolveResult, SolverOptions, solve

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
