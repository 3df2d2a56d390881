"""tensegrity_rigidity: exact rigidity of random periodic tensegrity networks.

The top level holds what a user needs (listed in ``__all__``):

* one sample: :func:`lattice_instance` (a random strained lattice), the builders
  :func:`triangular_lattice`, :func:`square_lattice`, :func:`random_periodic_network`, the data
  types :class:`PeriodicNetwork`, :class:`Instance`, :class:`Element`, :func:`strain_tensor`,
  and instance files (:func:`load_instance`, :func:`save_instance`);
* its verdict: :func:`solve` (the relaxed state and its certificate, a :class:`SolveResult`),
  :func:`decide` (the certified :class:`Verdict` only), :class:`SolverOptions`, and the
  nonaffinity of a solved sample (:func:`nonaffinity`);
* packings and their jamming: :func:`contact_network` (the contacts of a periodic packing as
  struts), :func:`crystal_packing`, :func:`read_gsd` (a GSD frame), the certified test
  :func:`jamming` (local, collective, strict; a :class:`JammingResult`), the builders
  :func:`kagome_lattice` and :func:`honeycomb_lattice`;
* rods-only networks combinatorially: :func:`rigid_clusters` (a pebble game on the fixed box:
  rigid clusters, overconstrained bonds, floppy modes, strain rigidity; a
  :class:`RigidClusters`);
* ensembles: sweep specs (:func:`parse_spec`, :func:`load_spec`, :class:`Spec`),
  :func:`run_sweep` and :func:`load_results`, exact per-sample thresholds
  (:func:`find_threshold`, :class:`Threshold`);
* the errors and warnings: :class:`TensegrityError`, :class:`InputError`, :class:`SpecError`,
  :class:`SweepFailed`, :class:`SweepInterrupted`, :class:`UndecidedWarning`.

Everything else lives in the subpackages, by pipeline stage (ARCHITECTURE.md):
:mod:`~tensegrity_rigidity.model` (networks, lattices, random elements, strain, linear
mechanics, files) -> :mod:`~tensegrity_rigidity.combinatorics` (the pebble game of rods-only
networks) -> :mod:`~tensegrity_rigidity.solver` (exact relaxation and certified
verdict) -> :mod:`~tensegrity_rigidity.analysis` (observables, estimators, single-node theory)
-> :mod:`~tensegrity_rigidity.ensemble` (sweeps, storage, executors, thresholds) ->
:mod:`~tensegrity_rigidity.paper` (studies, figures, report) -> :mod:`~tensegrity_rigidity.cli`.

Every name but the errors is imported on first use, so that ``import tensegrity_rigidity``
and the command line start in a few milliseconds: the command line installs its signal
handlers before NumPy and SciPy load (a Ctrl-C during those imports used to print a
traceback).
"""

from __future__ import annotations

import importlib
import warnings
from typing import TYPE_CHECKING, Any

from .errors import InputError, SpecError, TensegrityError, UndecidedWarning

if TYPE_CHECKING:
    from .analysis.observables import nonaffinity
    from .combinatorics.clusters import RigidClusters, rigid_clusters
    from .ensemble.spec import Spec, load_spec, parse_spec
    from .ensemble.sweep import (
        SweepFailed,
        SweepInterrupted,
        SweepReport,
        load_results,
        run_sweep,
    )
    from .ensemble.thresholds import Threshold, find_threshold
    from .model.interop import read_gsd
    from .model.io import load_instance, save_instance
    from .model.lattice import (
        DEFAULT_DELTA,
        honeycomb_lattice,
        kagome_lattice,
        random_periodic_network,
        square_lattice,
        triangular_lattice,
    )
    from .model.network import Element, Instance, PeriodicNetwork
    from .model.packing import contact_network, crystal_packing
    from .model.sampling import lattice_instance
    from .model.strain import strain_tensor
    from .solver.core import SolveResult, SolverOptions, Verdict, decide, solve
    from .solver.jamming import JammingResult, jamming

__all__ = [
    "DEFAULT_DELTA",
    "Element",
    "InputError",
    "Instance",
    "JammingResult",
    "PeriodicNetwork",
    "RigidClusters",
    "SolveResult",
    "SolverOptions",
    "Spec",
    "SpecError",
    "SweepFailed",
    "SweepInterrupted",
    "SweepReport",
    "TensegrityError",
    "Threshold",
    "UndecidedWarning",
    "Verdict",
    "contact_network",
    "crystal_packing",
    "decide",
    "find_threshold",
    "honeycomb_lattice",
    "jamming",
    "kagome_lattice",
    "lattice_instance",
    "load_instance",
    "load_results",
    "load_spec",
    "nonaffinity",
    "parse_spec",
    "random_periodic_network",
    "read_gsd",
    "rigid_clusters",
    "run_sweep",
    "save_instance",
    "solve",
    "square_lattice",
    "strain_tensor",
    "triangular_lattice",
]

__version__ = "0.1.0"

#: names imported on first use: name -> module (relative to this package)
_LAZY = {
    "nonaffinity": ".analysis.observables",
    **dict.fromkeys(("RigidClusters", "rigid_clusters"), ".combinatorics.clusters"),
    **dict.fromkeys(("Spec", "load_spec", "parse_spec"), ".ensemble.spec"),
    **dict.fromkeys(
        ("run_sweep", "load_results", "SweepReport", "SweepFailed", "SweepInterrupted"),
        ".ensemble.sweep",
    ),
    **dict.fromkeys(("Threshold", "find_threshold"), ".ensemble.thresholds"),
    **dict.fromkeys(("load_instance", "save_instance"), ".model.io"),
    **dict.fromkeys(
        ("DEFAULT_DELTA", "random_periodic_network", "square_lattice", "triangular_lattice"),
        ".model.lattice",
    ),
    **dict.fromkeys(("kagome_lattice", "honeycomb_lattice"), ".model.lattice"),
    **dict.fromkeys(("contact_network", "crystal_packing"), ".model.packing"),
    "read_gsd": ".model.interop",
    **dict.fromkeys(("JammingResult", "jamming"), ".solver.jamming"),
    **dict.fromkeys(("Element", "Instance", "PeriodicNetwork"), ".model.network"),
    "lattice_instance": ".model.sampling",
    "strain_tensor": ".model.strain",
    **dict.fromkeys(("SolveResult", "SolverOptions", "Verdict", "decide", "solve"), ".solver.core"),
}

#: names the top level exported before version 0.2, now importable from their modules only
_MOVED = {
    "site_uniforms": ".model.elements",
    "place_elements": ".model.elements",
    "single_node_probability": ".analysis.single_node",
}


def __getattr__(name: str) -> Any:
    """Import a public name on first use; old names still work, with a warning."""
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    if name in _MOVED:
        where = f"{__name__}{_MOVED[name]}"
        warnings.warn(
            f"tensegrity_rigidity.{name} is deprecated; import it from {where}",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(importlib.import_module(_MOVED[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
