"""The top level exports what a user needs, and only that (issue 16, item 3)."""

from __future__ import annotations

import subprocess
import sys

import pytest

import tensegrity_rigidity as tr

#: what a user needs from the top level (README, docs/api): keep in step with __all__
NEEDED = {
    "solve",
    "decide",
    "SolverOptions",
    "SolveResult",
    "Verdict",
    "lattice_instance",
    "triangular_lattice",
    "square_lattice",
    "random_periodic_network",
    "load_instance",
    "save_instance",
    "run_sweep",
    "load_results",
    "parse_spec",
    "load_spec",
    "Spec",
    "SweepReport",
    "find_threshold",
    "Threshold",
    "rigid_clusters",
    "RigidClusters",
    "nonaffinity",
    "TensegrityError",
    "InputError",
    "SpecError",
    "SweepFailed",
    "SweepInterrupted",
    "UndecidedWarning",
    "Element",
    "Instance",
    "PeriodicNetwork",
    "strain_tensor",
    "DEFAULT_DELTA",
    "contact_network",
    "crystal_packing",
    "read_gsd",
    "jamming",
    "JammingResult",
    "kagome_lattice",
    "honeycomb_lattice",
}


def test_all_is_exactly_what_a_user_needs():
    assert set(tr.__all__) == NEEDED
    assert len(tr.__all__) == len(set(tr.__all__))


def test_star_import_gives_every_name():
    namespace: dict = {}
    exec("from tensegrity_rigidity import *", namespace)
    assert NEEDED <= set(namespace)


@pytest.mark.parametrize("name", sorted(NEEDED))
def test_each_name_is_the_object_of_its_module(name):
    obj = getattr(tr, name)
    if hasattr(obj, "__module__") and name != "DEFAULT_DELTA":
        module = sys.modules[obj.__module__]
        assert getattr(module, name) is obj


def test_errors_share_one_base():
    for name in ("InputError", "SpecError", "SweepFailed"):
        assert issubclass(getattr(tr, name), tr.TensegrityError)
    assert issubclass(tr.SweepInterrupted, KeyboardInterrupt)


@pytest.mark.parametrize(
    "name, module",
    [
        ("site_uniforms", "tensegrity_rigidity.model.elements"),
        ("place_elements", "tensegrity_rigidity.model.elements"),
        ("single_node_probability", "tensegrity_rigidity.analysis.single_node"),
    ],
)
def test_low_level_names_left_the_top_level_but_still_import_with_a_warning(name, module):
    assert name not in tr.__all__
    with pytest.warns(DeprecationWarning, match=module):
        obj = getattr(tr, name)
    assert obj is getattr(sys.modules[module], name)


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no_such_thing"):
        tr.no_such_thing  # noqa: B018


def test_the_top_level_imports_the_sweep_engine_only_on_first_use():
    code = (
        "import sys, tensegrity_rigidity as t; "
        "assert 'tensegrity_rigidity.ensemble.sweep' not in sys.modules; "
        "assert 'pandas' not in sys.modules; "
        "t.run_sweep; "
        "assert 'tensegrity_rigidity.ensemble.sweep' in sys.modules"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
